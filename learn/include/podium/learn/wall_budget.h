#pragma once
/// A training loop's wall-clock limit, checked between its rounds (a round: train to the next
/// test, then test). A preset sized in minutes fits a fixed slot on machines of any speed, where a
/// step count alone does not (the get-up `quick` campaign fits 2 h; the update cost of the same
/// 128-128 SAC ranged from 2 to 12 ms over this project's machines). Another round runs
/// only if it still ends inside the limit, predicting it to take as long as the last one. The
/// state goes into the trial's checkpoint, so a resumed trial goes on with the same clock instead
/// of getting its limit afresh (the time between the last checkpoint and a kill is not counted).
///
///     WallBudget clock(minutes, saved_state);
///     while (steps < total_steps && clock.another_round_fits()) {
///       clock.start_round();
///       ... train, test ...
///       clock.end_round();
///       extra["clock"] = clock.state();  // then checkpoint
///     }
///     info["stopped_by"] = clock.stopped_by(steps, total_steps);
///     base::log_info(clock.end_message("my task", steps, total_steps));
#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>

#include "podium/base/json.h"

namespace podium::learn {

class WallBudget {
 public:
  /// `minutes` ≤ 0: no limit. `state`: a saved state() or null for a fresh clock.
  explicit WallBudget(double minutes, const base::Json& state = nullptr);

  /// No limit, or the time spent plus the last round's length is within the limit.
  bool another_round_fits() const;
  /// Times a round: start_round() before it, end_round() after it counts it.
  void start_round();
  void end_round();
  /// Counts a round that took `seconds` (what end_round() does with the measured time).
  void add_round(double seconds);

  /// What ended a loop that stopped at `steps` of `total_steps`: "steps", or "time" if the limit
  /// stopped it short.
  static std::string stopped_by(std::int64_t steps, std::int64_t total_steps);
  /// The log line that says so, with the minutes spent: "<who>: training ended by time at
  /// environment step 1160000 after 99.7 min". (Wall times reach metrics only as series under a
  /// time/ prefix, the one kind of series that differs between runs of a seed.)
  std::string end_message(std::string_view who, std::int64_t steps, std::int64_t total_steps) const;

  bool limited() const { return limit_s_ > 0.0; }
  double spent_s() const { return spent_s_; }
  /// spent / limit (0 without a limit), for progress reports.
  double fraction_used() const { return limited() ? spent_s_ / limit_s_ : 0.0; }

  base::Json state() const;

 private:
  double limit_s_ = 0.0, spent_s_ = 0.0, last_round_s_ = 0.0;
  std::chrono::steady_clock::time_point round_start_;
};

}  // namespace podium::learn
