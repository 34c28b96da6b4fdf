#pragma once
/// Action maps for CharacterEnv (each a policy action ↦ a sim::World command).
#include <functional>
#include <memory>

#include "podium/character/character_env.h"
#include "podium/character/pose_bridge.h"
#include "podium/learn/vae.h"

namespace podium::character {

/// Torques: action ∈ [−1, 1] per joint DoF, τ = a · torque limit · strength (the World's
/// strength multiplier β, so the box is [−β, β] times the limits: get-up seed §4–5, App. D).
class TorqueActions : public ActionMap {
 public:
  learn::BoxSpace space(const sim::CharacterModel& model) const override;
  sim::Control control() const override { return sim::Control::torque; }
  void command(const CharacterEnv& env, std::span<const double> action, Eigen::VectorXd& out) const override;
};

/// PD or stable-PD targets: the action is a pose (the bridge's z-up layout) inside the joint
/// limits; the target is that pose (get-up seed App. D: π_slow drives an 800 Hz PD controller).
class TargetActions : public ActionMap {
 public:
  /// `mode` is one of pd, spd_dense, spd_maba.
  TargetActions(sim::ModelPtr model, sim::Control mode);
  learn::BoxSpace space(const sim::CharacterModel& model) const override;
  sim::Control control() const override { return mode_; }
  void command(const CharacterEnv& env, std::span<const double> action, Eigen::VectorXd& out) const override;

 private:
  PoseBridge bridge_;
  sim::Control mode_;
};

/// The pose VAE's decoder as the action space (thesis §3.4.2; curve get-up seed §3.4): action =
/// [z (latent, in ±latent_bound), Δq (per pose entry, in ±offset_bound)], pose = clamp(decode(z,
/// c) + Δq) (learn::pose_action_to_target), target = the pose through the bridge, whose frame must
/// be the one the VAE was trained in. The offsets are the action's tail: naturalness_reward
/// (rewards.h, eq. 3.4) reads them there. The VAE is shared read-only by every env copy.
class VaeActions : public ActionMap {
 public:
  /// The C-VAE condition of the current state (empty for a P-VAE).
  using ConditionFn = std::function<std::vector<double>(const CharacterEnv& env)>;
  VaeActions(std::shared_ptr<const learn::PoseVae> vae, PoseBridge bridge, sim::Control mode, double latent_bound,
             double offset_bound, ConditionFn condition = {});
  learn::BoxSpace space(const sim::CharacterModel& model) const override;
  sim::Control control() const override { return mode_; }
  void command(const CharacterEnv& env, std::span<const double> action, Eigen::VectorXd& out) const override;
  /// The Δq part of an action.
  std::span<const double> offsets(std::span<const double> action) const { return action.subspan(vae_->latent_size()); }

 private:
  std::shared_ptr<const learn::PoseVae> vae_;
  PoseBridge bridge_;
  sim::Control mode_;
  double latent_bound_, offset_bound_;
  ConditionFn condition_;
};

/// Residual targets on the reference motion (get-up seed §6, Algorithm 2): target = the
/// reference pose at the env's reference clock + Δq, Δq ∈ ±offset_bound. Not clamped to the
/// joint limits: with PD, a target past a limit is how a joint near it gets more than
/// kp·(limit − q) of torque (the seed repository's slow env adds its actions unclamped).
class ResidualActions : public ActionMap {
 public:
  ResidualActions(sim::ModelPtr model, sim::Control mode, double offset_bound);
  learn::BoxSpace space(const sim::CharacterModel& model) const override;
  sim::Control control() const override { return mode_; }
  void command(const CharacterEnv& env, std::span<const double> action, Eigen::VectorXd& out) const override;

 private:
  PoseBridge bridge_;
  sim::Control mode_;
  double offset_bound_;
};

}  // namespace podium::character
