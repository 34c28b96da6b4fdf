#pragma once
/// What PPO and SAC have in common, seen by tasks: train on a VecEnv up to a step budget, act,
/// checkpoint the whole learner state, export the deterministic policy as TorchScript.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "podium/base/json.h"
#include "podium/learn/env.h"
#include "podium/learn/vec_env.h"

namespace podium::learn {

/// Reported after every PPO iteration / every SAC logging interval.
struct TrainStats {
  std::int64_t env_steps = 0;    ///< environment steps so far (all copies)
  double mean_return = 0.0;      ///< mean return of episodes finished in this interval (NaN if none)
  std::size_t episodes = 0;      ///< episodes finished in this interval
  double rollout_seconds = 0.0;  ///< wall time spent stepping environments and querying the policy
  double update_seconds = 0.0;   ///< wall time spent in network updates
};
using TrainCallback = std::function<void(const TrainStats&)>;

class Learner {
 public:
  virtual ~Learner() = default;
  virtual std::string name() const = 0;
  /// Trains until env_steps() ≥ total_env_steps (whole iterations for PPO).
  virtual void train_until(VecEnv& envs, std::int64_t total_env_steps, const TrainCallback& callback = {}) = 0;
  virtual std::int64_t env_steps() const = 0;
  /// The action for one observation, in the environment's action space. Deterministic: the
  /// policy mean (PPO) or β·s·tanh(mean) (SAC); otherwise a sample, using the learner's generator.
  /// `action_scale` s is the environment's Env::action_scale() (SAC only; PPO requires 1).
  virtual void act(std::span<const double> observation, std::span<double> action, bool deterministic, double action_scale) = 0;
  void act(std::span<const double> observation, std::span<double> action, bool deterministic) {
    act(observation, action, deterministic, 1.0);
  }
  /// Saves everything needed to continue exactly: networks, optimisers, normaliser, buffers,
  /// generators, counters, and the runner's rollout state; `user_state` is stored alongside and
  /// returned by load_checkpoint() (TrainingCheckpoint keeps the task's own state there).
  virtual void save_checkpoint(const std::filesystem::path& path, const VecEnv& envs, const base::Json& user_state) const = 0;
  void save_checkpoint(const std::filesystem::path& path, const VecEnv& envs) const { save_checkpoint(path, envs, base::Json()); }
  /// Loads save_checkpoint()'s file into a learner built with the same config and spaces;
  /// returns the user_state saved with it (null when none was given).
  virtual base::Json load_checkpoint(const std::filesystem::path& path, VecEnv& envs) = 0;
  /// Starts from another run's policy: `policy` is that run's save_checkpoint() file or its
  /// export_torchscript() file, of the same algorithm, with the same network shape (hidden,
  /// activation), spaces and use of observation normalisation as this learner's config. Copies
  /// the policy network and the normaliser (and PPO's value / SAC's Q networks when `policy` is
  /// a checkpoint); everything else starts afresh under this learner's config: new optimisers,
  /// step counters and schedules at zero, an empty replay buffer, SAC's α at initial_alpha. SAC
  /// keeps its own β; at the source's β its deterministic actions equal the source's exactly.
  virtual void warm_start(const std::filesystem::path& policy) = 0;
  /// Writes a TorchScript module whose forward(obs: float32 [N, obs]) returns the deterministic
  /// action [N, act] in the environment's action space (normaliser included).
  virtual void export_torchscript(const std::filesystem::path& path) const = 0;
  /// All network parameters flattened (for tests that compare runs).
  virtual std::vector<float> parameters() const = 0;
};

/// Builds a learner from spec data: {"algorithm": "ppo" | "sac", "preset": "quick" | "paper",
/// "config": {field overrides}}; errors name the bad field (task presets stay plain data).
std::unique_ptr<Learner> make_learner(const base::Json& spec, const BoxSpace& observation_space, const BoxSpace& action_space,
                                      std::uint64_t seed);

/// Runs `episodes` episodes of `env` with the learner's policy (at the env's action_scale());
/// returns each episode's return.
std::vector<double> evaluate(Learner& learner, Env& env, int episodes, bool deterministic = true);

/// Path of the BLAS library that provides sgemm_ in this process, "" if none is loaded.
std::string active_blas_library();
/// True for Debian's reference BLAS (…/blas/libblas.so.3), the 7-9× slower fallback.
bool is_reference_blas(const std::string& library_path);
/// Once per process (learners call it): logs a warning when the reference BLAS is active, and
/// limits OpenBLAS to one thread (its own threads fight with rollout workers; measured 2x slower
/// SAC updates on 2 cores otherwise). libtorch itself runs on one intra-op thread.
void setup_blas();

}  // namespace podium::learn
