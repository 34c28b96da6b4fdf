#pragma once
/// Curricula with JSON state (saved in learner checkpoints, so a resumed trial continues the
/// same schedule). Each reads its settings from spec data and its state from state().
#include <cstdint>
#include <string>
#include <vector>

#include "podium/base/json.h"
#include "podium/base/rng.h"

namespace podium::character {

/// A value advanced when a score passes a threshold: v ← factor·v + increment.
/// Weaker (get-up seed §5, Algorithm 1): v = β, factor 0.95, advance when the test return > ω = 60.
/// Bar height (thesis Table 3.1): v = bar, increment Δz, scores (each iteration's mean sample
/// reward) accumulate and the accumulator restarts from 0 at each advance, threshold R_T.
/// `limit` stops the schedule (v never passes it).
class ThresholdCurriculum {
 public:
  struct Config {  ///< defaults: the Weaker curriculum of get-up seed App. D (β = 0.95, ω = 60)
    double initial = 1.0;
    double factor = 0.95;
    double increment = 0.0;
    double threshold = 60.0;
    bool accumulate = false;
    double limit = 0.0;  ///< the last value (below initial for a shrinking schedule)
    /// Fields "initial", "factor", "increment", "threshold", "accumulate", "limit" (read, like
    /// every from_json here, by base::ConfigReader: unknown keys rejected, errors name `where`).
    static Config from_json(const base::Json& json, const std::string& where);
  };
  explicit ThresholdCurriculum(Config config);
  /// Feeds one score; returns true when the value advanced.
  bool observe(double score);
  double value() const { return value_; }
  int level() const { return level_; }
  /// True once the value has reached `limit`.
  bool at_limit() const { return value_ == config_.limit; }

  base::Json state() const;
  void load_state(const base::Json& state);

 private:
  Config config_;
  double value_;
  double accumulated_ = 0.0;
  int level_ = 0;
};

/// Ends a curriculum when a level takes too long (get-up seed §5): level i may use at most
/// M_i = clip(factor·N_{i−1}, N_min, N_max) steps, N_{i−1} the steps level i−1 took. The seed
/// gives no M_0; level 0 (Discover) here has M_0 = N_max. (Algorithm 1's listing omits the factor
/// 1.5 that §5's text gives; we follow the text.)
class StepBudget {
 public:
  struct Config {
    double factor = 1.5;
    std::int64_t min_steps = 300000;
    std::int64_t max_steps = 800000;
    static Config from_json(const base::Json& json, const std::string& where);
  };
  explicit StepBudget(Config config) : config_(config) {}
  /// Call when the curriculum advances at step count `steps`.
  void on_advance(std::int64_t steps);
  /// Whether the current level has used more than its budget at step count `steps`.
  bool exhausted(std::int64_t steps) const { return steps - level_start_ > budget(); }
  /// M_i of the current level.
  std::int64_t budget() const;

  base::Json state() const;
  void load_state(const base::Json& state);

 private:
  Config config_;
  std::int64_t level_start_ = 0;
  std::int64_t last_level_steps_ = -1;  // N_{i−1}; −1 at level 0
};

/// Levels unlocked one by one after N successes on the newest (curve get-up seed §4: flat, easy,
/// medium, hard terrain regions, 200 successes unlock the next; training revisits every
/// unlocked level).
class UnlockCurriculum {
 public:
  struct Config {
    std::vector<std::string> levels;
    int successes_to_unlock = 200;
    static Config from_json(const base::Json& json, const std::string& where);
  };
  explicit UnlockCurriculum(Config config);
  /// Records an episode's outcome on `level`; returns true when it unlocked the next level.
  bool record(int level, bool success);
  /// Opens the next level now (a fixed schedule in place of the successes); false when all are open.
  bool open_next();
  int unlocked() const { return unlocked_; }  ///< number of levels open (≥ 1)
  /// A level uniform among the unlocked ones.
  int sample(base::Rng& rng) const { return static_cast<int>(rng.integer(0, unlocked_ - 1)); }
  const std::string& level_name(int level) const { return config_.levels.at(level); }

  base::Json state() const;
  void load_state(const base::Json& state);

 private:
  Config config_;
  int unlocked_ = 1;
  int successes_ = 0;  // on the newest unlocked level
};

}  // namespace podium::character
