#pragma once
/// A training loop's wall-clock limit, checked between its rounds (a round: train to the next
/// test, then test). A preset sized in minutes fits a fixed slot on machines of any speed, where a
/// step count alone does not (issue 18: the get-up `quick` campaign in 2 h; the update cost of
/// the same 128-128 SAC ranged from 2 to 12 ms over this project's machines). Another round runs
/// only if it still ends inside the limit, predicting it to take as long as the last one. The
/// state goes into the trial's checkpoint, so a resumed trial goes on with the same clock instead
/// of getting its limit afresh (the time between the last checkpoint and a kill is not counted).
///
///     WallBudget clock(minutes, saved_state);
///     while (steps < total_steps && clock.another_round_fits()) {
///       const auto started = std::chrono::steady_clock::now();
///       ... train, test ...
///       clock.add_round(seconds since started);
///       extra["clock"] = clock.state();  // then checkpoint
///     }
#include "podium/base/json.h"

namespace podium::learn {

class WallBudget {
 public:
  /// `minutes` ≤ 0: no limit. `state`: a saved state() or null for a fresh clock.
  explicit WallBudget(double minutes, const base::Json& state = nullptr);

  /// No limit, or the time spent plus the last round's length is within the limit.
  bool another_round_fits() const;
  /// Counts a round that took `seconds`.
  void add_round(double seconds);

  bool limited() const { return limit_s_ > 0.0; }
  double spent_s() const { return spent_s_; }
  /// spent / limit (0 without a limit), for progress reports.
  double fraction_used() const { return limited() ? spent_s_ / limit_s_ : 0.0; }

  base::Json state() const;

 private:
  double limit_s_ = 0.0, spent_s_ = 0.0, last_round_s_ = 0.0;
};

}  // namespace podium::learn
