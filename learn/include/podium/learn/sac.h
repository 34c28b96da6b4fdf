#pragma once
/// Soft Actor-Critic (Haarnoja et al. 2018) as the get-up seed uses it (§3, Table 1): twin Q
/// networks with Polyak-averaged targets, automatic temperature α, a tanh-squashed Gaussian
/// policy whose bound β can change during training (§5: actions in [−β^i, β^i] for the
/// strong-to-weak torque curriculum, a = β·tanh(u)), times a per-copy, per-episode scale s
/// (Env::action_scale(), Algorithm 1's β̂) kept with each transition, a replay buffer, uniform
/// warm-up and a fractional update-to-data ratio. Each episode's start transitions
/// (Env::start_transitions(): the get-up seed's fall) join the replay buffer too, as the seed
/// repository's env.py reset adds them; they are not environment steps.
#include <cstdint>
#include <memory>
#include <vector>

#include "podium/base/json.h"
#include "podium/learn/learner.h"

namespace podium::learn {

/// Defaults are the `quick` preset (small networks, minutes on 2 cores); paper() is Table 1.
struct SacConfig {
  std::vector<int> hidden = {64, 64};  ///< hidden widths of the actor and of each critic
  std::string activation = "relu";
  double actor_lr = 1e-3, critic_lr = 1e-3, alpha_lr = 1e-3;
  double initial_alpha = 1.0;
  double log_std_min = -5.0, log_std_max = 2.0;  ///< Table 1
  double tau = 5e-3;                             ///< target update rate
  double gamma = 0.99;
  int batch_size = 256;
  /// Update-to-data ratio: updates per environment step of each copy, fractional allowed (0.25:
  /// one update per 4 steps of one copy; with K copies ⌊0.25·K·n⌋ updates after n vector steps).
  double updates_per_step = 1.0;
  std::int64_t warmup_steps = 1000;  ///< uniform random actions, no updates, before this
  std::int64_t buffer_capacity = 1'000'000;
  double reward_scale = 1.0;
  double max_grad_norm = 0.0;  ///< 0 = no gradient clipping (Table 1: False)
  bool normalize_observations = false;
  double target_entropy = 0.0;             ///< 0 = automatic, −(action size)
  double action_bound = 1.0;               ///< initial β
  std::int64_t log_interval_steps = 1000;  ///< how often train_until calls back

  /// Table 1: actor/critic 1024-1024 ReLU, critic LR 1e-4, actor LR 1e-5, α0 = 0.1, α LR 1e-4,
  /// log σ ∈ [−5, 2], τ = 5e-3, batch 1024, 1 update per step, γ = 0.97 (π_weak), no clipping,
  /// 10 000 warm-up steps (§B).
  static SacConfig paper();
  /// The default above: 64-64 networks for the classic-control problems.
  static SacConfig quick() { return {}; }
  base::Json to_json() const;
  static SacConfig from_json(const base::Json& json);
};

/// CPU time of the updating thread spent in the network updates so far, by part, in seconds
/// summed over updates (bench/learn/sac_update_bench prints it per update).
struct SacUpdateTimes {
  double batch = 0;   ///< sampling and normalising the minibatch
  double target = 0;  ///< the soft Bellman target (no autograd)
  double critic = 0;  ///< twin critic forward, backward, Adam step
  double actor = 0;   ///< policy sample, critic forward, backward, Adam step
  double alpha = 0;   ///< temperature loss and step
  double polyak = 0;  ///< target critic averaging
};

class Sac final : public Learner {
 public:
  Sac(const SacConfig& config, const BoxSpace& observation_space, const BoxSpace& action_space, std::uint64_t seed);
  ~Sac() override;
  std::string name() const override { return "sac"; }
  void train_until(VecEnv& envs, std::int64_t total_env_steps, const TrainCallback& callback = {}) override;
  std::int64_t env_steps() const override;
  using Learner::act;
  void act(std::span<const double> observation, std::span<double> action, bool deterministic, double action_scale) override;
  using Learner::save_checkpoint;
  void save_checkpoint(const std::filesystem::path& path, const VecEnv& envs, const base::Json& user_state) const override;
  base::Json load_checkpoint(const std::filesystem::path& path, VecEnv& envs) override;
  void warm_start(const std::filesystem::path& policy) override;
  void export_torchscript(const std::filesystem::path& path) const override;
  std::vector<float> parameters() const override;

  /// β: actions are β·s·tanh(u) in the normalised box (s: each copy's Env::action_scale()), so
  /// β < 1 weakens every actuator of every copy.
  void set_action_bound(double beta);
  double action_bound() const;
  double alpha() const;
  /// Transitions in the replay buffer: environment steps and start transitions, up to its capacity.
  std::int64_t replay_size() const;
  /// Network updates done so far (⌊updates_per_step × env steps since updates began⌋).
  std::int64_t updates() const;
  /// Updates skipped because a loss was not finite (a diverging critic); counted in updates().
  std::int64_t skipped_updates() const;
  SacUpdateTimes update_times() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace podium::learn
