#pragma once
/// The step count z_t of the sprint's state (sprint seed §2 "State": "the number of steps that
/// have been physically advanced (i.e. the number of alternating legs)", normalised, in place of
/// a phase variable). A step is a touchdown of the foot opposite to the last counted one.
///
/// Touchdown of a foot: it has been off the ground at some observation since the counter's
/// start or its last touchdown, and then on the ground for `debounce` observations in a row (so
/// contact flicker within one stance is one touchdown). Feet on the ground when the count starts
/// (in the blocks or standing) do not count until they have lifted. At most one step counts per
/// observation; when both feet touch down in the same one, the foot opposite to the last counted
/// step counts (the left one first, when none has counted yet).
#include <optional>

#include "podium/base/json.h"

namespace podium::tasks::sprint {

enum class Foot { left, right };

struct StepCounterConfig {
  int debounce = 2;      ///< observations in contact that make a touchdown (≥ 1)
  double n_norm = 50.0;  ///< N_norm: z = steps / N_norm (preset data)
};

class StepCounter {
 public:
  /// Throws base::UserError for debounce < 1 or n_norm ≤ 0.
  explicit StepCounter(StepCounterConfig config = {});
  /// Starts a count with the feet's current ground contact.
  void reset(bool left_down, bool right_down);
  /// One observation of the feet's ground contact (after a control step); true when a step counted.
  bool observe(bool left_down, bool right_down);

  int steps() const { return steps_; }
  /// z_t = steps / N_norm.
  double z() const { return static_cast<double>(steps_) / config_.n_norm; }
  /// The foot of the last counted step (nullopt before the first).
  std::optional<Foot> last_foot() const { return last_; }

  /// The counter's state, for env checkpoints, and back.
  base::Json state() const;
  void load_state(const base::Json& state);

 private:
  struct FootState {
    int run = 0;          // observations in contact in a row
    bool lifted = false;  // off the ground since the start or the last touchdown
  };
  bool touchdown(FootState& foot, bool down) const;
  StepCounterConfig config_;
  FootState feet_[2];
  int steps_ = 0;
  std::optional<Foot> last_;
};

}  // namespace podium::tasks::sprint
