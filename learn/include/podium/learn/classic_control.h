#pragma once
/// Classic control problems written from their textbook equations, so learn/'s tests and
/// benchmarks run without Bullet. Written by hand: no Debian package provides them in C++.
#include "podium/base/rng.h"
#include "podium/learn/env.h"

namespace podium::learn {

/// Pendulum swing-up with continuous torque, the equations and reward of Gym's Pendulum-v1:
/// θ̈ = 3g/(2l)·sin θ + 3/(m l²)·u, semi-implicit Euler with dt = 0.05 s, |θ̇| ≤ 8, |u| ≤ 2;
/// r = −(θ² + 0.1 θ̇² + 0.001 u²) with θ wrapped to [−π, π); observation (cos θ, sin θ, θ̇);
/// truncated after 200 steps. A random policy scores about −1200, a good one about −150.
class Pendulum final : public Env {
 public:
  BoxSpace observation_space() const override;
  BoxSpace action_space() const override;
  void seed(std::uint64_t seed) override { rng_ = base::Rng(seed); }
  void reset(std::vector<double>& observation) override;
  void step(std::span<const double> action, StepResult& out) override;
  std::optional<base::Json> save_state() const override;
  void load_state(const base::Json& state) override;

  static constexpr int kEpisodeSteps = 200;

 private:
  void observe(std::vector<double>& observation) const;
  base::Rng rng_;
  double theta_rad_ = 0.0;
  double theta_dot_rad_s_ = 0.0;
  int t_ = 0;
};

/// Cart-pole balancing (Barto, Sutton & Anderson 1983, the equations of Gym's CartPole-v1) with a
/// continuous force F = 10 N · a, a ∈ [−1, 1]; Euler with τ = 0.02 s; reward 1 per step;
/// terminated when |x| > 2.4 m or |θ| > 12°; truncated after 500 steps.
class CartPole final : public Env {
 public:
  BoxSpace observation_space() const override;
  BoxSpace action_space() const override;
  void seed(std::uint64_t seed) override { rng_ = base::Rng(seed); }
  void reset(std::vector<double>& observation) override;
  void step(std::span<const double> action, StepResult& out) override;
  std::optional<base::Json> save_state() const override;
  void load_state(const base::Json& state) override;

  static constexpr int kEpisodeSteps = 500;

 private:
  base::Rng rng_;
  double state_[4] = {0, 0, 0, 0};  // x (m), ẋ (m/s), θ (rad), θ̇ (rad/s)
  int t_ = 0;
};

}  // namespace podium::learn
