#pragma once
/// The Discover and Weaker stages as one trial (get-up seed §4–5, Algorithm 1, App. D): SAC on
/// GetupEnv; every `eval_every` environment steps the deterministic policy is tested on fixed
/// starts at β^i; a test return above ω advances the strong-to-weak curriculum β ← 0.95β; the
/// curriculum ends when a level needs more than M_i steps, and training goes on at the last
/// strength passed until `total_steps` (or `train_minutes` of wall time, if set).
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "getup_env.h"
#include "podium/base/config.h"
#include "podium/base/json.h"
#include "podium/character/curriculum.h"
#include "podium/character/training_stage.h"
#include "strategy_features.h"

namespace podium::tasks::getup {

/// The task config (defaults: the seed's settings, the `paper` preset; presets in getup_task.cpp).
struct Settings {
  EnvSettings env;
  std::string algorithm = "sac";          ///< the seed's learner; "ppo" for a preset that measures it faster
  std::string sac_preset = "paper";       ///< learn's SacConfig::paper() (Table 1)
  base::Json sac = base::Json::object();  ///< SacConfig fields over the preset
  base::Json ppo = base::Json::object();  ///< PpoConfig fields over its defaults
  std::int64_t total_steps = 10'000'000;  ///< environment steps at most (10⁷: the seed repository's)
  double train_minutes = 0.0;             ///< wall-clock limit on training and tests; 0: none (learn::WallBudget)
  std::int64_t eval_every = 20'000;       ///< App. D: every 20 000 simulation steps
  int eval_starts = 10;                   ///< App. D: 10 fixed initial states
  std::uint64_t eval_seed = 1;            ///< picks those starts (the same for every trial)
  double success_height_m = 1.2;          ///< head top above this at the end: got up (§7)
  int stand_steps = 80;                   ///< ... and above it for the last 80 control steps (2 s): stood (head_watch.h)
  character::ThresholdCurriculum::Config curriculum;  ///< App. D: β = 0.95, ω = 60
  character::StepBudget::Config budget;               ///< §5 and App. D: M_i rule, 3·10⁵, 8·10⁵
  int copies = 1;                                     ///< environment copies stepped together
  int threads = 1;                                    ///< threads stepping them (≤ copies)
  int checkpoint_every = 5;                           ///< evaluations between training checkpoints
  std::string warm_start;                             ///< a Weaker trial's training.ckpt to train on from ("": from scratch)
  double hold_strength = 0.0;                         ///< > 0: no curriculum, train and test at this β (0: Algorithm 1)
};

/// Reads (and on a describing reader describes) the config; every check of describe() is here.
Settings read_settings(base::ConfigReader& r);
/// The learner spec for learn::make_learner (SAC with the log interval the trial needs, or PPO).
base::Json learner_spec(const Settings& s);

/// Algorithm 1's decision at each test, on character's ThresholdCurriculum and StepBudget. The
/// budget follows §5's text, M_i = clip(1.5·N_{i−1}, N_min, N_max) (Algorithm 1's listing omits
/// the 1.5), from the first advance on: Discover runs until it passes ω or total_steps (the seed
/// gives it no budget; its repository applies M_i only once β < 1). When a level runs out of
/// budget the curriculum ends ("Terminate curriculum", Algorithm 1) and β returns to the last
/// strength passed, where training goes on: the seed repository's main.py (update_power) does the
/// same and trains on to its 10⁷ steps.
class WeakerSchedule {
 public:
  enum class Decision { advance, carry_on, end_curriculum };
  WeakerSchedule(const character::ThresholdCurriculum::Config& curriculum, const character::StepBudget::Config& budget)
      : curriculum_(curriculum), budget_(budget), last_passed_(curriculum.initial) {}
  /// The test at environment step `steps` scored `test_return` at strength(); once the curriculum
  /// has ended, always carry_on.
  Decision on_test(std::int64_t steps, double test_return);
  /// β^i, or once the curriculum has ended, the last strength passed.
  double strength() const { return ended_ ? last_passed_ : curriculum_.value(); }
  /// Curriculum advances (tests passed).
  int level() const { return curriculum_.level(); }
  bool ended() const { return ended_; }
  /// Ends the curriculum at `strength`: training and tests stay there (Settings::hold_strength).
  void hold(double strength) { ended_ = true, last_passed_ = strength; }
  base::Json state() const;
  void load_state(const base::Json& state);

 private:
  character::ThresholdCurriculum curriculum_;
  character::StepBudget budget_;
  double last_passed_;  // the strength of the last test passed
  bool ended_ = false;
};

/// The lower clip of the training episodes' β̂: `min_strength` during the curriculum; once it has
/// ended (or under hold_strength), the strength trained at, so β̂ ~ clip(N(β, ε), β, 1) never
/// falls below it (the seed repository's main.py update_power sets power_end to β; env.py
/// sample_power clips there).
inline double strength_floor(const WeakerSchedule& schedule, double min_strength) {
  return schedule.ended() ? schedule.strength() : min_strength;
}

/// Whether a tested policy should replace the exported one where the curriculum does not decide
/// (before the first pass, and at the last strength passed once the curriculum has ended): more
/// fixed starts stood (head_watch.h), then a higher mean test return. The seed repository keeps
/// the best mean return alone; ours ranks a get-up that stays up above a leap loop, which earns
/// more return on the way (RESULTS.md: a best-return policy came before nearly all of its trial's
/// stands). Each argument holds the figures "stood_rate" and "test_return".
bool exports_over(const character::Figures& tested, const character::Figures& exported);

struct TrialOutcome {
  std::filesystem::path policy;      ///< TorchScript export of π_weak (see run_discover_weaker)
  std::filesystem::path trajectory;  ///< its rollout from the first fixed start
  double policy_strength = 1.0;      ///< β^i at which the exported policy passed its test
  bool passed = false;               ///< whether any test passed ω (false: the best-returning policy is exported)
  double success_rate = 0.0;         ///< of the exported policy on the fixed starts, at policy_strength
  double test_return = 0.0;          ///< likewise
  double final_strength = 1.0;       ///< β when the trial ended (after the curriculum's end: the last passed)
  int levels = 0;                    ///< curriculum advances
  std::int64_t env_steps = 0;
  std::string stopped_by =
      "steps";  ///< what ended training: "steps" (total_steps) or "time" (train_minutes; time/wall_s has the seconds)
  StrategyFeatures features;  ///< of the exported policy over the fixed starts
  base::Json to_json() const;
};

/// Runs the trial on character's training-stage driver in `run.work_dir`, resuming from its
/// training.ckpt when a previous attempt left one. With a `warm_start`, that file is copied in and
/// trained on: its networks, replay buffer, environment steps (total_steps counts on from them),
/// schedule and metric points, but not its exported policy's record nor its wall clock, which
/// begin anew. The exported policy is the one that passed the last curriculum test (π_weak at the
/// weakest strength it mastered) or, after the curriculum ended, a later one tested at that
/// strength that exports_over it; when no test passed, the best by exports_over (the seed
/// repository's best_model ranks by return alone). Throws when `run.cancel` is set.
TrialOutcome run_discover_weaker(const Settings& s, const character::StageRun& run);

/// The fixed starts of the tests (eval_starts seeds drawn from eval_seed).
std::vector<std::uint64_t> test_starts(const Settings& s);

}  // namespace podium::tasks::getup
