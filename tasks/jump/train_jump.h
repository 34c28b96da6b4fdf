#pragma once
/// One jump trial (thesis §3.4.1, §3.6.1): PPO on copies of JumpEnv at the trial's take-off
/// state; after each PPO iteration its score feeds the Table 3.1 curriculum, which moves the bar
/// (box width) on every copy and rebuilds the copies when the control rate f_control(ρ(z)) no
/// longer fits; the trial ends at z_freeze (§3.6.1: 1 m for strategy discovery) or after
/// total_samples. Tests every eval_every iterations; 20 evaluation jumps at the starting bar and
/// at the final z at the end. Stage 2 (§3.5.2) adds the novelty reward and a warm start.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "jump_env.h"
#include "jump_evaluation.h"
#include "podium/base/config.h"
#include "podium/base/json.h"
#include "podium/character/curriculum.h"
#include "podium/character/training_stage.h"
#include "podium/learn/learner.h"

namespace podium::tasks::jump {

/// The trial's settings (defaults: the thesis's, the `paper` preset; presets in jump_task.cpp).
struct TrainSettings {
  JumpSettings env;
  std::string ppo_preset = "paper";                   ///< learn's PpoConfig::paper() = §3.6.2
  base::Json ppo = base::Json::object();              ///< PpoConfig fields over the preset
  int copies = 16;                                    ///< JumpEnv copies stepped together
  int threads = 1;                                    ///< threads stepping them (≤ copies)
  std::int64_t total_samples = 12'000LL * 4096;       ///< §3.6.2: 12,000 iterations of 4096 samples
  double z_freeze_m = 1.0;                            ///< §3.6.1: end at this z (0: never)
  character::ThresholdCurriculum::Config curriculum;  ///< Table 3.1 for the kind, keys override it
  /// What an iteration feeds the curriculum: "per_episode" (Σ rewards / episodes ended in the
  /// iteration, as the authors' runner computes its avg_rwd) or "per_sample" (Σ rewards / samples).
  std::string curriculum_score = "per_episode";
  int eval_every = 50;        ///< iterations between tests
  EvaluationJumps eval;       ///< the tests' jumps
  int final_jumps = 20;       ///< evaluation jumps at the end, at the starting bar and at the z reached
  int checkpoint_every = 10;  ///< iterations between training checkpoints
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
  PosePrior prior;                         ///< composite PD targets (§3.4.2); none: plain targets
  std::filesystem::path prior_file;        ///< the file `prior` was loaded from
  std::filesystem::path warm_start;        ///< a PPO policy file (TorchScript or checkpoint)
  std::vector<std::vector<double>> known;  ///< bar-frame rotations already found (eq. 3.12)
};

/// The jump's part of a training stage (character/training_stage.h): copies of JumpEnv at the
/// trial's take-off state and the Table 3.1 curriculum between PPO iterations. The copies are
/// rebuilt at a new control rate under the same learner (observation and action do not depend on
/// the rate); each rate has its own checkpoint file (its tag, e.g. "12hz").
class JumpStage final : public character::TrainingStage {
 public:
  JumpStage(const TrainSettings& settings, std::uint64_t seed, const TrialInputs& inputs);
  /// Builds the copies at the z `built` names ({"z_built_m"}), or at the curriculum's start.
  void build(const base::Json& built) override;
  learn::VecEnv& envs() override { return *envs_; }
  base::Json learner_spec() const override { return jump::learner_spec(s_); }
  std::string checkpoint_tag() const override;
  base::Json build_state() const override { return {{"z_built_m", z_built_}}; }
  base::Json state() const override { return {{"curriculum", curriculum_.state()}}; }
  void load_state(const base::Json& state) override { curriculum_.load_state(state.at("curriculum")); }
  /// The iteration's score into the curriculum (feed()), and its metrics.
  void on_iteration(const character::Iteration& iteration, learn::Learner& learner, const character::MetricFn& send) override;
  bool finished() const override { return frozen(); }
  double progress() const override;
  /// eval_jumps test jumps at the current z.
  character::Figures test(const character::TestRound& round, learn::Learner& learner, const character::MetricFn& send) override;
  /// final_jumps evaluation jumps at the starting bar and at the z reached.
  void record(const character::Recording& recording) override;

  /// One iteration's score into the curriculum; on an advance, every copy moves to the new z and
  /// they are rebuilt when the control rate changed. Returns true when z advanced.
  bool feed(double score);
  double z() const { return curriculum_.value(); }
  int level() const { return curriculum_.level(); }
  double control_hz() const;                   ///< f_control(ρ(z)) at the curriculum's z
  double z_built() const { return z_built_; }  ///< the z the current copies were built at
  int rebuilds() const { return rebuilds_; }
  bool frozen() const;
  /// A fresh env at z for tests (the trial's take-off state and novelty features).
  std::unique_ptr<JumpEnv> test_env(double z) const;
  const JumpEvaluation& start_bar() const { return start_bar_; }
  const JumpEvaluation& final_bar() const { return final_bar_; }

 private:
  void build_copies(double z);
  double hz_of_copies() const;

  TrainSettings s_;
  std::uint64_t seed_;
  PosePrior prior_;
  std::vector<std::vector<double>> known_;
  character::ThresholdCurriculum curriculum_;
  double z_built_ = 0.0;
  int rebuilds_ = 0;
  std::vector<JumpEnv*> copies_;  // owned by envs_
  std::unique_ptr<learn::VecEnv> envs_;
  double score_ = 0.0;            // the last iteration's, for the log
  learn::TrainStats last_stats_;  // likewise
  JumpEvaluation start_bar_, final_bar_;
};

struct JumpOutcome {
  double z_reached_m = 0.0;  ///< curriculum z at the end
  int levels = 0;            ///< curriculum advances
  std::int64_t samples = 0;
  JumpEvaluation start_bar;  ///< final_jumps at the curriculum's first z
  JumpEvaluation final_bar;  ///< final_jumps at z_reached_m
  /// The jump shown and measured: the deterministic jump at z_reached_m if it succeeds, else the
  /// one at the starting bar.
  const JumpEvaluation& shown() const { return final_bar.deterministic_success ? final_bar : start_bar; }
  std::filesystem::path policy;  ///< TorchScript export
  base::Json to_json() const;
};

/// Runs the trial on character's training-stage driver in `run.work_dir`, resuming from its last
/// checkpoint when a previous attempt left one; with inputs.warm_start, from that policy. The
/// exported policy is the last. Throws when `run.cancel` is set.
JumpOutcome run_jump_trial(const TrainSettings& s, const TrialInputs& inputs, const character::StageRun& run);

}  // namespace podium::tasks::jump
