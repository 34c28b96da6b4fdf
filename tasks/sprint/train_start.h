#pragma once
/// The Start stage (sprint seed §3.1): PPO on copies of SprintEnv's Start mode (imitate a crouch
/// start drawn per episode, end at the first landing) through character's training-stage driver;
/// tested on fixed episodes from the references' first frames; the exported policy's landings
/// (hand-over states with their draws) written for stage 2.
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "podium/base/config.h"
#include "podium/character/evaluator.h"
#include "podium/character/training_stage.h"
#include "sprint_env.h"
#include "user_start.h"

namespace podium::tasks::sprint {

struct StartTrainSettings {
  std::string track = "smoke";  ///< the presets.json entry (track, rewards, DR, the start block)
  double sim_hz = 600.0;
  std::string ppo_preset = "quick";
  base::Json ppo = base::Json::object();  ///< PpoConfig fields over the preset
  int copies = 2, threads = 1;
  std::int64_t total_samples = 256;
  int eval_every = 1;      ///< PPO iterations between tests
  int eval_episodes = 4;   ///< episodes per test (deterministic policy; each draws its reference and DR)
  int final_episodes = 8;  ///< the exported policy's episodes: the reported figures and the landings
  int checkpoint_every = 1;
  std::uint64_t eval_seed = 20'240;  ///< the tests' episodes' seeds derive from it (not used in training)
  /// Another trial's training.ckpt of the same stage to train on from; "": from scratch.
  std::string warm_start;
  /// User clips as references besides the four crouch starts (user_start.h), in this order after them.
  std::vector<StartClipSpec> clips;
};

/// Reads the stage's keys (errors name their JSON path).
StartTrainSettings read_start_train_settings(base::ConfigReader& r);

/// The Start's references: the four crouch starts with the preset's landing distance, then the
/// user clips (user_start.h).
std::vector<StartReference> start_references(const sim::ModelPtr& model, double control_hz, const StartPreset& start,
                                             const std::vector<StartClipSpec>& clips);

/// Start-mode episodes of a policy from fixed seeds.
struct StartEvaluation {
  double landing_rate = 0.0;        ///< episodes ended at the first landing (not a fall, deviation or time limit)
  double tracking_error_rad = 0.0;  ///< mean over all steps of √(Σ_j ‖q̂_j ⊖ q_j‖² / J), J the model's links (root included)
  double com_speed_ratio = 0.0;  ///< mean over landings of the COM's forward speed at the landing over the reference's
  double return_mean = 0.0;
  /// Per reference (the env's order): its name, the episodes that drew it and their landings.
  struct PerReference {
    std::string name;
    int episodes = 0, landings = 0;
  };
  std::vector<PerReference> per_reference;
  double min_reference_landing_rate = 0.0;  ///< the lowest landing rate of a reference drawn at least once
  std::vector<base::Json> landings;         ///< the landings' hand-over states
  /// How the episodes ended, by SprintEnv outcome name ("time_limit": cut while running).
  std::map<std::string, int> ends;
  std::string ends_text() const;  ///< e.g. "landed 3, fell 12, deviated 5"
  base::Json to_json() const;     ///< the figures (not the states)
};
/// The forward COM speed at a reference's last frame (its last two frames' COM by forward
/// kinematics over the frame time), m/s.
double reference_landing_speed(const character::Clip& clip);
StartEvaluation evaluate_starts(SprintEnv& env, const character::PolicyFn& policy, int episodes, std::uint64_t seed,
                                const std::filesystem::path& record_dir = {});

/// The Start stage's part of a training stage.
class StartStage final : public character::TrainingStage {
 public:
  StartStage(const StartTrainSettings& settings, std::uint64_t seed);
  void build(const base::Json& built) override;
  learn::VecEnv& envs() override { return *envs_; }
  base::Json learner_spec() const override;
  character::Figures test(const character::TestRound& round, learn::Learner& learner, const character::MetricFn& send) override;
  /// The best tested: landing rate, then the smaller tracking error.
  std::optional<character::ExportReason> export_rule(const character::ExportRecord& tested,
                                                     const character::ExportRecord* exported) override;
  /// The exported policy's final episodes: figures, the first recorded, the landings written.
  void record(const character::Recording& recording) override;

  const StartEvaluation& final_evaluation() const { return final_; }
  const std::filesystem::path& trajectory() const { return trajectory_; }
  const std::filesystem::path& landings_file() const { return landings_; }

 private:
  SprintEnvSettings env_settings() const;

  StartTrainSettings s_;
  std::uint64_t seed_;
  std::vector<StartReference> references_;
  std::unique_ptr<learn::VecEnv> envs_;
  StartEvaluation final_;
  std::filesystem::path trajectory_, landings_;
};

struct StartOutcome {
  StartEvaluation final;
  std::filesystem::path policy, trajectory, landings;
  std::int64_t samples = 0;
};

/// Runs the stage in `run.work_dir` (resuming from its checkpoint).
StartOutcome run_start_trial(const StartTrainSettings& settings, const character::StageRun& run);

}  // namespace podium::tasks::sprint
