#pragma once
/// The style-curve get-up's `train` stage (curve get-up seed §5, §5.6): PPO on copies of
/// CurveGetupEnv over a curve set, on character's training-stage driver. Tests run the learner's
/// deterministic policy from fixed starts on every curve; the exported policy is the best tested
/// (by success rate, then return), and after training it is recorded on the first curves with
/// its target and achieved features at control rate.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "curve_env.h"
#include "podium/base/config.h"
#include "podium/character/evaluator.h"
#include "podium/character/training_stage.h"

namespace podium::tasks::getup_curves {

/// The train stage's settings (the task config's keys; README.md lists them).
struct TrainSettings {
  /// Curve files: a name without a folder or extension is a shipped curve (data/curves/<name>.json),
  /// anything else a path (absolute, or relative to the working directory).
  std::vector<std::string> curves = {"faceup", "facedown"};
  CurveEnvSettings env;
  std::string ppo_preset = "quick";       ///< learn's PpoConfig preset under `ppo`
  base::Json ppo = base::Json::object();  ///< PpoConfig fields over the preset
  int copies = 2, threads = 1;            ///< env copies stepped together, and threads stepping them
  std::int64_t total_steps = 100'000;     ///< control steps (environment steps of every copy)
  double train_minutes = 0.0;             ///< wall budget of training and tests; 0: none
  int test_every = 10;                    ///< PPO iterations between tests
  int test_starts = 2;                    ///< test episodes per curve (fixed starts)
  int final_starts = 0;                   ///< the exported policy's final test, per curve (0: test_starts)
  std::uint64_t test_seed = 7;            ///< the fixed starts' seed (the same for every trial)
  int record_curves = 2;                  ///< the first curves recorded after training, one episode each
  int checkpoint_every = 10;              ///< PPO iterations between checkpoints
  /// Another train trial's training.ckpt to train on from (same curves and sizes); "": from scratch.
  std::string warm_start = {};
};

/// Reads the settings; errors name the JSON path and the value (base::ConfigError).
TrainSettings read_train_settings(base::ConfigReader& r);
/// The curve files `settings.curves` names, resolved (shipped names to the shipped folder).
std::vector<std::filesystem::path> curve_files(const TrainSettings& settings);
/// The folder of the shipped curves.
std::filesystem::path shipped_curve_dir();

/// A test: the deterministic policy from `starts` fixed starts on every curve.
/// How one curve's test episodes followed it (the quick bars: success; tracking on the successful
/// episodes; when the character rose).
struct CurveFollowing {
  std::string curve;  ///< its name
  double success_rate = 0.0;
  int successes = 0;
  /// Over [0, T] of the successful episodes (none without one): mean |h − p_h| in m, and the mean
  /// of |θ_x − p_θx| and |θ_z − p_θz| in degrees.
  std::optional<double> h_error_m, angle_error_deg;
  /// The rise: the first instant the achieved h reaches half the standing neck height (the model
  /// standing), mean over the episodes that got there (`risen` of them; none without one).
  std::optional<double> rise_time_s;
  int risen = 0;
  base::Json to_json() const;
};

struct CurveTest {
  double mean_return = 0.0;
  double success_rate = 0.0;
  double mean_task_reward = 0.0;  ///< r_task (eq. 4) averaged over every control step of every episode
  /// §6.4's average return rate: r_task summed over the episodes' steps, divided by their full
  /// lengths' control steps (T + T_stand each), so a step early termination cut counts as 0.
  double average_return_rate = 0.0;
  double mean_episode_s = 0.0;            ///< control time of an episode (early termination shortens it)
  std::vector<double> curve_success;      ///< per curve
  std::vector<CurveFollowing> following;  ///< per curve
};
/// Episodes with `policy` on each curve of `env` (use_curve), `starts` per curve from seeds derived
/// from `seed`: the same seeds for every curve (common random numbers: curves with the same kind
/// of start, e.g. a base curve and its edits, start from the same states). The env's curve choice
/// is drawn again afterwards.
/// `each_step`, if given, sees every step of every episode (the reset included) with its start's index.
using CurveStepFn = std::function<void(std::size_t start, const CurveGetupEnv& env)>;
CurveTest test_curves(CurveGetupEnv& env, const character::PolicyFn& policy, int starts, std::uint64_t seed,
                      const CurveStepFn& each_step = {});

/// The artifact name of the motion recorded on curve `k`: "trajectory", "trajectory_1", ...
std::string recorded_trajectory_name(std::size_t k);

/// One episode of `policy` on `env`'s current curve from start seed `seed`, recorded under `dir`
/// (the motion's path in `trajectory`): the `curves` artifact's entry for it — the curve, the
/// target and achieved features at every control step, its motion's artifact name
/// (`trajectory_name`), success and return.
base::Json record_curve_episode(CurveGetupEnv& env, const character::PolicyFn& policy, std::uint64_t seed,
                                const std::filesystem::path& dir, const std::string& trajectory_name,
                                std::filesystem::path& trajectory);

/// The train stage's outcome.
struct TrainOutcome {
  CurveTest final;  ///< the exported policy's test (as at its export)
  std::filesystem::path policy;
  std::vector<std::filesystem::path> trajectories;  ///< recorded episodes, one per recorded curve
  std::vector<std::string> recorded_curves;         ///< their curves' names
  std::filesystem::path curves;                     ///< targets and achieved features of those episodes (JSON)
  std::int64_t env_steps = 0;
  std::string stopped_by;
  int open_levels = 1;  ///< terrain regions open at the end (§5.4)
  base::Json to_json() const;
};

/// Runs the stage in `run.work_dir` (resuming from its checkpoint).
TrainOutcome run_curve_training(const TrainSettings& settings, const character::StageRun& run);

}  // namespace podium::tasks::getup_curves
