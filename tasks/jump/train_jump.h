#pragma once
/// One jump trial (thesis §3.4.1, §3.6.1): PPO on copies of JumpEnv at the trial's take-off
/// state; after each PPO iteration its score feeds the Table 3.1 curriculum, which moves the bar
/// (box width) on every copy and rebuilds the copies when the control rate f_control(ρ(z)) no
/// longer fits; the trial ends at z_freeze (§3.6.1: 1 m for strategy discovery) or after
/// total_samples. Tests every eval_every iterations; 20 evaluation jumps at the starting bar and
/// at the final z at the end. Stage 2 (§3.5.2) adds the novelty reward and a warm start.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "jump_env.h"
#include "jump_evaluation.h"
#include "podium/base/config.h"
#include "podium/base/json.h"
#include "podium/character/curriculum.h"
#include "podium/learn/learner.h"

namespace podium::tasks::jump {

/// The trial's settings (defaults: the thesis's, the `paper` preset; presets in jump_task.cpp).
struct TrainSettings {
  JumpSettings env;
  std::string ppo_preset = "paper";             ///< learn's PpoConfig::paper() = §3.6.2
  base::Json ppo = base::Json::object();        ///< PpoConfig fields over the preset
  int copies = 16;                              ///< JumpEnv copies stepped together
  int threads = 1;                              ///< threads stepping them (≤ copies)
  std::int64_t total_samples = 12'000LL * 4096;  ///< §3.6.2: 12,000 iterations of 4096 samples
  double z_freeze_m = 1.0;                      ///< §3.6.1: end at this z (0: never)
  character::ThresholdCurriculum::Config curriculum;  ///< Table 3.1 for the kind, keys override it
  /// What an iteration feeds the curriculum: "per_episode" (Σ rewards / episodes ended in the
  /// iteration, as the authors' runner computes its avg_rwd) or "per_sample" (Σ rewards / samples).
  std::string curriculum_score = "per_episode";
  int eval_every = 50;                          ///< iterations between tests
  EvaluationJumps eval;                         ///< the tests' jumps
  int final_jumps = 20;                         ///< issue 19: 20 evaluation jumps at the end
  int checkpoint_every = 10;                    ///< iterations between training checkpoints
};

/// Reads (and on a describing reader describes) the trial's keys, JumpSettings' among them.
TrainSettings read_train_settings(base::ConfigReader& r);
/// The learner spec for learn::make_learner.
base::Json learner_spec(const TrainSettings& s);

/// An iteration's curriculum score from its TrainStats: the reward is sparse (one value when an
/// episode ends), so the iteration's reward sum is the sum of the returns of the episodes that
/// ended in it, mean_return · episodes.
double iteration_score(const std::string& score, const learn::TrainStats& stats, std::int64_t samples);

/// What a trial is handed: the P-VAE (both stages, when the campaign trains one) and what Stage 2
/// brings (§3.5.2).
struct TrialInputs {
  PosePrior prior;                             ///< composite PD targets (§3.4.2); none: plain targets
  std::filesystem::path prior_file;            ///< the file `prior` was loaded from
  std::filesystem::path warm_start;            ///< a PPO policy file (TorchScript or checkpoint)
  std::vector<std::vector<double>> known;      ///< bar-frame rotations already found (eq. 3.12)
};

/// The learner and the copies, and the curriculum between iterations. The copies are rebuilt at a
/// new control rate with the same learner: observation and action do not depend on the rate.
class JumpTrainer {
 public:
  /// Builds copies at z_built (the curriculum starts at settings.curriculum.initial regardless).
  JumpTrainer(const TrainSettings& settings, std::uint64_t seed, const TrialInputs& inputs, double z_built);
  /// One iteration's score into the curriculum; on an advance, every copy moves to the new z and
  /// they are rebuilt when the control rate changed. Returns true when z advanced.
  bool feed(double score);
  double z() const { return curriculum_.value(); }
  int level() const { return curriculum_.level(); }
  double control_hz() const;
  double z_built() const { return z_built_; }  ///< the z the current copies were built at
  int rebuilds() const { return rebuilds_; }
  bool frozen() const;
  learn::VecEnv& envs() { return *envs_; }
  learn::Learner& learner() { return *learner_; }
  const character::ThresholdCurriculum& curriculum() const { return curriculum_; }
  void load_curriculum(const base::Json& state) { curriculum_.load_state(state); }
  /// A fresh env at z for tests (the trial's take-off state and novelty features).
  std::unique_ptr<JumpEnv> test_env(double z) const;

 private:
  void build_copies(double z);

  TrainSettings s_;
  std::uint64_t seed_;
  PosePrior prior_;
  std::vector<std::vector<double>> known_;
  character::ThresholdCurriculum curriculum_;
  double z_built_ = 0.0;
  int rebuilds_ = 0;
  std::vector<JumpEnv*> copies_;  // owned by envs_
  std::unique_ptr<learn::VecEnv> envs_;
  std::unique_ptr<learn::Learner> learner_;
};

/// Where the trial reports (a plugins::Sink without the plugin types).
struct Reporter {
  std::function<void(const std::string& name, double step, double value)> metric;
  std::function<void(double fraction)> progress;
};

struct JumpOutcome {
  double z_reached_m = 0.0;       ///< curriculum z at the end
  int levels = 0;                 ///< curriculum advances
  std::int64_t samples = 0;
  JumpEvaluation start_bar;       ///< final_jumps at the curriculum's first z
  JumpEvaluation final_bar;       ///< final_jumps at z_reached_m
  /// The jump shown and measured: the deterministic jump at z_reached_m if it succeeds, else the
  /// one at the starting bar.
  const JumpEvaluation& shown() const { return final_bar.deterministic_success ? final_bar : start_bar; }
  std::filesystem::path policy;   ///< TorchScript export
  base::Json to_json() const;
};

/// Runs the trial in `work_dir`, resuming from its last checkpoint when a previous attempt left
/// one (metric points it covers are sent again; the store drops repeats). Throws when `cancel` is
/// set (checked after every PPO iteration).
JumpOutcome run_jump_trial(const TrainSettings& s, std::uint64_t seed, const TrialInputs& inputs, const std::filesystem::path& work_dir,
                           const std::atomic<bool>* cancel, const Reporter& report);

}  // namespace podium::tasks::jump
