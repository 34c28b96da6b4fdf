#pragma once
/// The run-up stage (thesis §3.6.1, "Run-up Learning"): per strategy, PPO on copies of RunupEnv
/// (imitate the reference run, end at the strategy's take-off state) on character's
/// training-stage driver; then the full jump: the run-up policy until the take-off condition, the
/// strategy's jump policy from the state reached, recorded as one motion.
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <vector>

#include "jump_env.h"
#include "podium/character/evaluator.h"
#include "podium/character/training_stage.h"
#include "runup_env.h"
#include "train_jump.h"

namespace podium::tasks::jump {

/// Run-ups of a policy from the reference's first frame: the first deterministic, the others with
/// Gaussian action noise (EvaluationJumps' σ and seed), as the jumps are tested.
struct RunupEvaluation {
  double handover_rate = 0.0;                             ///< run-ups that reached the take-off condition
  double task_reward = 0.0;                               ///< mean r_G over those (0 when none did)
  Eigen::Vector3d omega_error = Eigen::Vector3d::Zero();  ///< mean |ω − ω̄| per axis over those, rad/s
  double lateral_speed_error = 0.0;                       ///< mean |v_y − v̄_y| over those (high jump), m/s
  double return_mean = 0.0;
};
RunupEvaluation evaluate_runups(RunupEnv& env, const character::PolicyFn& policy, const EvaluationJumps& config);

/// The strategy's jump: its policy, the P-VAE it acts through, and the JumpEnv settings (take-off
/// features, bar) it was trained at.
struct JumpPolicy {
  std::filesystem::path policy;
  PosePrior prior;
  JumpSettings settings;
};

/// The full jumps: `config.jumps` run-ups (the first deterministic, the others noisy), each handed
/// over at the take-off condition to the deterministic jump policy from the state reached (turned
/// to face +x over the take-off point, the suite turned by α as in training). The first is
/// written to `record_dir`/full_jump.jsonl as one motion (run, take-off, clear, land).
struct FullJumps {
  double success_rate = 0.0;  ///< over all run-ups (one that never hands over fails)
  std::filesystem::path trajectory;
  /// How the full jumps ended: the jump's outcome reason (jump_rules.h), or "no hand-over", with counts.
  std::map<std::string, int> endings;
};
FullJumps full_jumps(RunupEnv& runup, const character::PolicyFn& runup_policy, const JumpPolicy& jump,
                     const EvaluationJumps& config, const std::filesystem::path& record_dir);

/// The state at the hand-over turned about the vertical to face +x with the root over the origin
/// (what JumpEnv's take-off states are), and the rigid motion that does it: x' = R (x − offset).
struct Placement {
  Eigen::VectorXd q;
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
};
Placement place_for_jump(const Eigen::VectorXd& q);

/// The run-up's part of a training stage.
class RunupStage final : public character::TrainingStage {
 public:
  RunupStage(const TrainSettings& train, const RunupSettings& runup, std::uint64_t seed, std::optional<JumpPolicy> jump);
  void build(const base::Json& built) override;
  learn::VecEnv& envs() override { return *envs_; }
  base::Json learner_spec() const override;
  character::Figures test(const character::TestRound& round, learn::Learner& learner, const character::MetricFn& send) override;
  /// The best tested return so far.
  std::optional<character::ExportReason> export_rule(const character::ExportRecord& tested,
                                                     const character::ExportRecord* exported) override;
  void record(const character::Recording& recording) override;

  const RunupEvaluation& final_runups() const { return final_; }
  const FullJumps& full() const { return full_; }

 private:
  TrainSettings train_;
  RunupSettings runup_;
  std::uint64_t seed_;
  std::optional<JumpPolicy> jump_;
  std::shared_ptr<const character::Clip> reference_;
  std::unique_ptr<learn::VecEnv> envs_;
  RunupEvaluation final_;
  FullJumps full_;
};

struct RunupOutcome {
  RunupEvaluation runups;  ///< final_jumps run-ups of the exported policy
  FullJumps full;          ///< with a jump policy: final_jumps full jumps
  std::filesystem::path policy;
  std::int64_t samples = 0;
  base::Json to_json() const;
};

/// Runs the stage in `run.work_dir` (resuming from its checkpoint).
RunupOutcome run_runup_trial(const TrainSettings& train, const RunupSettings& runup, const std::optional<JumpPolicy>& jump,
                             const character::StageRun& run);

}  // namespace podium::tasks::jump
