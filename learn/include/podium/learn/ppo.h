#pragma once
/// Proximal Policy Optimisation (Schulman et al. 2017, PPO-Clip) as the seeds use it: thesis
/// §3.4.1 (Gaussian policy with a fixed, annealed σ; value network trained on TD(λ) returns;
/// GAE(λ) advantages) and §3.6.2 (settings), curve get-up seed §5.6 (LR and σ schedules).
#include <cstdint>
#include <memory>
#include <vector>

#include "podium/base/json.h"
#include "podium/learn/learner.h"

namespace podium::learn {

/// Defaults are the `quick` preset for small problems; paper() gives thesis §3.6.2.
struct PpoConfig {
  std::vector<int> hidden = {64, 64};  ///< hidden layer widths (policy and value)
  std::string activation = "tanh";     ///< tanh or relu
  int rollout_steps = 256;             ///< steps per environment copy per iteration
  int epochs = 10;                     ///< passes over each batch
  int minibatch_size = 64;
  double gamma = 0.99;                                  ///< discount
  double lambda = 0.95;                                 ///< GAE(λ) and TD(λ)
  double clip = 0.2;                                    ///< ε of the clipped ratio
  double policy_lr_start = 3e-4, policy_lr_end = 3e-4;  ///< linear schedule over lr_anneal_steps
  double value_lr_start = 1e-3, value_lr_end = 1e-3;
  std::int64_t lr_anneal_steps = 1'000'000;
  double sigma_start = 0.5, sigma_end = 0.1;  ///< action σ in the normalised box [−1, 1]
  std::int64_t sigma_anneal_steps = 1'000'000;
  /// How both schedules move from start to end: 0 linearly over their anneal steps; n ≥ 2 in n equal
  /// intervals of them, the k-th holding start + (end − start)·k/(n − 1) (curve get-up seed §5.6:
  /// 5 levels, a step every 20M of its 100M simulation steps).
  int schedule_levels = 0;
  double max_grad_norm = 0.0;  ///< 0 = no gradient clipping
  bool normalize_observations = true;
  bool normalize_advantages = true;
  double reward_scale = 1.0;  ///< rewards are multiplied by this before learning

  /// Thesis §3.6.2: 1024-512 ReLU, 4096 samples per iteration, 5 epochs of minibatch 256,
  /// γ = 1, λ = 0.95, ε = 0.02, policy LR 2.5e-5, value LR 1e-2, σ 0.5 → 0.1 over 1e7 steps.
  static PpoConfig paper();
  base::Json to_json() const;
  /// Reads a config, starting from the defaults; throws UserError naming the bad field.
  static PpoConfig from_json(const base::Json& json);
};

/// A schedule's value at `step`: from `start` to `end` over `span` steps, then `end`; linear when
/// `levels` is 0, else in `levels` equal intervals (PpoConfig::schedule_levels).
double annealed(double start, double end, std::int64_t step, std::int64_t span, int levels = 0);

class Ppo final : public Learner {
 public:
  Ppo(const PpoConfig& config, const BoxSpace& observation_space, const BoxSpace& action_space, std::uint64_t seed);
  ~Ppo() override;
  std::string name() const override { return "ppo"; }
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
  /// The action σ at the current step count.
  double sigma() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace podium::learn
