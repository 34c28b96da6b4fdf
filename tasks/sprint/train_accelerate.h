#pragma once
/// The Acceleration + Top Speed stage (sprint seed §3.2): one PPO policy on copies of SprintEnv's
/// plain mode from a set of hand-over states (the Start stage's landings) to the finish line, on
/// r_base + r_mass + r_diag + r_mirror + r_primitive, through character's training-stage driver.
/// With w_primitive (`primitive_weight`) not 0 the stage pretrains the sport primitive's Φ1 on
/// `primitive_clips` (primitive.h) when it is built, and after every iteration trains Φ2 on the
/// strides the copies ran (its `online` setting), Φ2 and its buffer checkpointed beside the
/// driver's checkpoint. Tested on held-out episodes (each its own DR draw); the
/// exported policy's snapshots a set distance before the line are written for the dip stage.
#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "podium/character/training_stage.h"
#include "primitive.h"
#include "sprint_env.h"
#include "train_start.h"

namespace podium::tasks::sprint {

struct AccelerateSettings {
  StartTrainSettings train;             ///< track, simulation rate, PPO, copies, budget, tests (the start stage's keys)
  double handover_before_line_m = 8.0;  ///< the dip stage's snapshots: this far before the line (§3.3)
  double rise_lean_deg = 20.0;          ///< the rise: the trunk's lean from vertical below this for good
  double primitive_weight = 0.0;        ///< w_primitive of r_primitive (§3.2); not 0 needs primitive.clips
  PrimitiveSettings primitive;          ///< the sport primitive
};
/// Reads the stage's own keys (the shared ones: read_start_train_settings).
void read_accelerate_settings(base::ConfigReader& r, AccelerateSettings& s);

/// The start set when the Start stage's landings are empty or absent: per crouch start of the
/// preset, its last frame (pose and frame velocity: the first landing, just past the line) as a
/// World snapshot without a draw or step count, so every episode draws its own wind and μ. With
/// `root_x_m`, each is moved along the track to put its root there (the dip stage's fallback).
std::vector<base::Json> fallback_starts(const std::string& track, double sim_hz, std::optional<double> root_x_m = {});

/// Episodes of a policy from fixed seeds over the preset's track.
struct RunEvaluation {
  double finish_rate = 0.0;      ///< episodes that crossed the line without a fall or leaving the lane
  double distance_m = 0.0;       ///< mean distance the root covered
  double first_speed_mps = 0.0;  ///< mean speed over the first segment from the start (0 when none covered it)
  double last_speed_mps = 0.0;   ///< over the last segment before the line, finishers (0 when none)
  double segment_m = 0.0;        ///< the segments' length: 10 m, or a third of a shorter track
  double rise_distance_m = 0.0;  ///< mean over the episodes that rose (0 when none did)
  double rise_rate = 0.0;        ///< episodes whose trunk rose for good
  double flight_rate = 0.0;      ///< finishers with a flight phase in every stride of the last segment, over all
  double return_mean = 0.0;
  std::vector<base::Json> handovers;  ///< hand-over states when the root first passed the snapshot x
  base::Json to_json() const;         ///< the figures (not the states)
};
RunEvaluation evaluate_runs(SprintEnv& env, const character::PolicyFn& policy, int episodes, std::uint64_t seed,
                            const AccelerateSettings& settings, const std::filesystem::path& record_dir = {});

/// The first and last tenth of the training episodes' mean distances, from per-iteration tallies.
struct DistanceTally {
  std::vector<std::pair<std::int64_t, double>> per_iteration;  ///< (episodes, Σ distance)
  /// Mean distance of the iterations making up the first (last) tenth of the episodes, m (0: none).
  double first_tenth() const;
  double last_tenth() const;
};

class AccelerateStage final : public character::TrainingStage {
 public:
  /// `work_dir` holds Φ2's checkpoint files (a sport primitive with `online`).
  AccelerateStage(const AccelerateSettings& settings, std::vector<base::Json> starts, std::uint64_t seed,
                  std::filesystem::path work_dir = {});
  void build(const base::Json& built) override;
  learn::VecEnv& envs() override { return *envs_; }
  base::Json learner_spec() const override;
  base::Json state() const override;
  void load_state(const base::Json& state) override;
  /// Sends the mean distance of the training episodes that ended in the iteration.
  void on_iteration(const character::Iteration& iteration, learn::Learner& learner, const character::MetricFn& send) override;
  character::Figures test(const character::TestRound& round, learn::Learner& learner, const character::MetricFn& send) override;
  /// The best tested: finish rate, then the mean distance.
  std::optional<character::ExportReason> export_rule(const character::ExportRecord& tested,
                                                     const character::ExportRecord* exported) override;
  /// The exported policy's final episodes: figures, the first recorded, the dip snapshots written.
  void record(const character::Recording& recording) override;

  const RunEvaluation& final_evaluation() const { return final_; }
  const DistanceTally& distances() const { return tally_; }
  const std::filesystem::path& trajectory() const { return trajectory_; }
  const std::filesystem::path& handovers_file() const { return handovers_; }
  /// The sport primitive's figures (primitive.h SportPrimitive::summary), null without one.
  base::Json primitive_summary() const;

 private:
  SprintEnvSettings env_settings() const;
  void adapt_primitive(double steps, const character::MetricFn& send);

  AccelerateSettings s_;
  std::vector<base::Json> starts_;
  std::uint64_t seed_;
  std::filesystem::path work_dir_;
  std::shared_ptr<SportPrimitive> primitive_;
  std::vector<std::vector<double>> stride_buffer_;  // Φ2's latest strides, oldest first
  int adaptations_ = 0;
  std::unique_ptr<learn::VecEnv> envs_;
  std::vector<SprintEnv*> copies_;
  DistanceTally tally_;
  RunEvaluation final_;
  std::filesystem::path trajectory_, handovers_;
};

struct AccelerateOutcome {
  RunEvaluation final;
  DistanceTally distances;
  std::filesystem::path policy, trajectory, handovers;
  std::int64_t samples = 0;
  base::Json primitive;  ///< the sport primitive's figures, null without one
};

/// Runs the stage in `run.work_dir` (resuming from its checkpoint) from `starts`.
AccelerateOutcome run_accelerate_trial(const AccelerateSettings& settings, std::vector<base::Json> starts,
                                       const character::StageRun& run);

}  // namespace podium::tasks::sprint
