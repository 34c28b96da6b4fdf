#pragma once
/// A trained policy, read-only, that several threads may query at once (trajectory generation,
/// evaluation, hand-over states). Loaded from a learner's save_checkpoint() file or its
/// export_torchscript() file; its actions equal that learner's deterministic act() exactly.
#include <filesystem>
#include <memory>
#include <span>
#include <string>

#include "podium/learn/env.h"

namespace podium::learn {

class FrozenPolicy {
 public:
  /// Throws UserError naming the file when it is neither kind of policy file.
  explicit FrozenPolicy(const std::filesystem::path& file);
  ~FrozenPolicy();
  FrozenPolicy(FrozenPolicy&&) noexcept;
  FrozenPolicy& operator=(FrozenPolicy&&) noexcept;

  std::string algorithm() const;  ///< "ppo" or "sac"
  std::size_t observation_size() const;
  std::size_t action_size() const;

  /// The deterministic action (s·clip(mean, −1, 1) for PPO, β·s·tanh(mean) for SAC, with
  /// s = `action_scale`, an Env::action_scale() in (0, 1/β]) in the environment's action space.
  /// Const and thread-safe.
  void act(std::span<const double> observation, std::span<double> action, double action_scale = 1.0) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace podium::learn
