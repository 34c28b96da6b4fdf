#pragma once
/// The Slower stage as one trial (get-up seed §6, Algorithm 2, App. D): SAC trains π_slow on
/// SlowerEnv to track π_weak's get-up retimed by κ ~ U(κ_low, κ_high), then stand. Every
/// `slow_eval_every` environment steps the deterministic π_slow is tested on the fixed starts at
/// κ = `slow_test_kappa`. π_weak comes from the stage's one input trial (a Weaker trial: its
/// `policy` artifact and the strength it passed at).
#include "discover_weaker.h"
#include "podium/character/evaluator.h"
#include "slower_env.h"

namespace podium::tasks::getup {

struct SlowerConfig {
  SlowerSettings env;
  std::int64_t total_steps = 2'000'000;  ///< environment steps (the seed gives no Slower budget)
  double train_minutes = 0.0;            ///< wall-clock limit on training and tests; 0: none (learn::WallBudget)
  std::int64_t eval_every = 20'000;      ///< as Weaker's tests (App. D)
  double test_kappa = 0.5;               ///< COM tracking is judged at κ = 0.5 (the middle of App. D's range)
  double gamma = 0.95;                   ///< SAC's discount for π_slow (Table 1; π_weak's is 0.97)
  std::string warm_start;                ///< a Slower trial's training.ckpt to train on from, same π_weak ("": from scratch)
};

/// Reads (and describes) the Slower keys of the task config.
SlowerConfig read_slower(base::ConfigReader& r);

/// π_weak as the stage's input gives it.
struct WeakPolicy {
  std::filesystem::path policy;  ///< TorchScript export
  double strength = 1.0;         ///< β^i it passed its test at
};

struct SlowerOutcome {
  std::filesystem::path policy, trajectory, weak_policy;  ///< π_slow; its test rollout; π_weak's copy
  double success_rate = 0.0;                              ///< last test: standing (head top above rise_height_m) at the end
  double com_error_m = 0.0;                               ///< last test: mean |h_com − h'_com| over the rise
  double test_return = 0.0;
  std::int64_t env_steps = 0;
  std::string stopped_by = "steps";  ///< what ended training: "steps" or "time" (slow_train_minutes)
  base::Json to_json() const;
};

/// Runs the trial on character's training-stage driver in `run.work_dir`, resuming from its
/// training.ckpt when a previous attempt left one; the exported π_slow is the last one. With a
/// `warm_start`, that file is copied in and trained on (networks, replay buffer, environments,
/// curves; `slow_total_steps` counts on from its steps) with a clock of its own. Throws
/// base::UserError when π_weak never gets up (SlowerEnv's reason), or when the warm start's trial
/// imitated another π_weak (its folder's weak_policy.pt differs from `weak`'s file).
SlowerOutcome run_slower(const Settings& s, const SlowerConfig& c, const WeakPolicy& weak, const character::StageRun& run);

/// Slower's learner: the task's (learner_spec), SAC with π_slow's own discount.
base::Json slower_learner_spec(const Settings& s, const SlowerConfig& c);

/// The test of π_slow at one κ over the given starts (Slower's tests, the Evaluate stage).
character::EvaluationConfig slower_test(const SlowerSettings& s, std::vector<std::uint64_t> start_seeds);

}  // namespace podium::tasks::getup
