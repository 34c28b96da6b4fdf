#pragma once
/// Imitation of a reference clip, DeepMimic-style (Peng, Abbeel, Levine, van de Panne, "DeepMimic:
/// Example-guided deep reinforcement learning of physics-based character skills", SIGGRAPH 2018,
/// §5 "Reward" and §6 "Training": RSI, early termination; the thesis's run-up (§3.6.1) and the
/// sprint's Start phase train with it):
///
///   r_I = w_p r_p + w_v r_v + w_e r_e + w_c r_c,  w = (0.65, 0.1, 0.15, 0.1)
///   r_p = exp(−2 Σ_j ŵ_j ‖q̂_j ⊖ q_j‖²)    joint rotations (the root's included)
///   r_v = exp(−0.1 Σ_j ŵ_j ‖q̇̂_j − q̇_j‖²)  joint rates (the root's angular velocity included)
///   r_e = exp(−10 Σ_e ‖p̂_e − p_e‖²)       end effectors, each relative to its own root
///   r_c = exp(−10 ‖p̂_c − p_c‖²)           centre of mass, world position
///
/// with the reference (hatted) at the env's reference clock. The paper prints r_p and r_v as plain
/// sums over the joints and r_e on world positions at 40; its code (DeepMimicCore,
/// SceneImitate.cpp, CalcRewardImitate), which made its results, weighs each joint by the
/// character file's DiffWeight normalised to sum 1 (ŵ: a weighted mean, 15× looser than the sum
/// on its 15-joint humanoid, so r_p still has a slope at 0.5 rad per joint) and measures end
/// effectors from the root in the heading frame (height above the ground) at 10. Those are the
/// defaults here. The parts: `ImitationReference` (the clip, its frame velocities and the terms),
/// `ReferenceStateStart` (RSI: a uniformly drawn frame), `EarlyTermination` (a fall or a large
/// deviation), `ReferencePhase` (the phase in the observation).
#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "podium/character/character_env.h"
#include "podium/character/motion.h"
#include "podium/character/rewards.h"

namespace podium::character {

/// The weights and kernel scales of r_I (defaults: DeepMimic's code, above).
struct ImitationWeights {
  double pose = 0.65, velocity = 0.1, end_effector = 0.15, com = 0.1;
  double pose_scale = 2.0, velocity_scale = 0.1, end_effector_scale = 10.0, com_scale = 10.0;
  /// ŵ: DeepMimic's per-joint weights (the DiffWeight of its humanoid3d.txt, whose joint names
  /// humanoid34 and the athlete share; a joint it does not name weighs 1), normalised to sum 1;
  /// false: every joint 1, normalised.
  bool deepmimic_joint_weights = true;
};

/// The squared tracking errors of one state against the reference.
struct TrackingErrors {
  double pose = 0.0;          ///< Σ_j ŵ_j ‖q̂_j ⊖ q_j‖² over the root rotation and every joint, rad²
  double velocity = 0.0;      ///< Σ_j ŵ_j ‖q̇̂_j − q̇_j‖² over the root's ω (its frame) and the joints', (rad/s)²
  double end_effector = 0.0;  ///< Σ_e ‖p̂_e − p_e‖² over the end-effector bodies, each from its root (heading frame), m²
  double com = 0.0;           ///< ‖p̂_c − p_c‖², world, m²
  double pose_rms_rad = 0.0;  ///< √(Σ_j ‖q̂_j ⊖ q_j‖² / J), unweighted over the J links: the per-joint error reports use
};

/// The four kernels and their weighted sum r_I (each term in (0, 1], 1 on the reference).
struct ImitationTerms {
  double pose = 1.0, velocity = 1.0, end_effector = 1.0, com = 1.0;
  double total = 1.0;
};
ImitationTerms imitation_terms(const TrackingErrors& errors, const ImitationWeights& weights = {});

/// A reference clip ready to be tracked: its frame velocities computed once, and scratch for
/// forward kinematics (so one instance per thread, like a CharacterEnv).
class ImitationReference {
 public:
  /// Throws base::UserError for a clip without a model or with fewer than 2 frames.
  explicit ImitationReference(std::shared_ptr<const Clip> clip, ImitationWeights weights = {});

  const Clip& clip() const { return *clip_; }
  const std::shared_ptr<const Clip>& clip_ptr() const { return clip_; }
  const ImitationWeights& weights() const { return weights_; }
  /// The reference pose at t (Clip::sample) and velocity (that of the frame at or before t).
  Eigen::VectorXd pose(double t_s) const { return clip_->sample(t_s); }
  const Eigen::VectorXd& velocity(double t_s) const;
  /// t / duration in [0, 1] (wrapped for a looping clip, clamped otherwise).
  double phase(double t_s) const;

  /// The errors of (q, q̇) against the reference at t, and their terms.
  TrackingErrors errors(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, double t_s) const;
  ImitationTerms terms(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, double t_s) const;
  /// Of the env's current state at its reference clock.
  TrackingErrors errors(const CharacterEnv& env) const;

 private:
  std::size_t frame_at(double t_s) const;

  std::shared_ptr<const Clip> clip_;
  ImitationWeights weights_;
  std::vector<double> joint_weight_;  // per link, ŵ (sums to 1)
  std::vector<Eigen::VectorXd> velocities_;
  mutable sim::CharacterData sim_, ref_;  // forward kinematics scratch
};

/// Reference state initialisation (DeepMimic §6): each episode starts at a frame of the env's
/// reference clip drawn uniformly from [first_frame, last_frame] (last_frame −1: the clip's
/// last), its pose and frame velocity, each joint turned by N(0, σ) noise (ReferenceStart);
/// the env's reference clock is set to the frame's time.
class ReferenceStateStart : public Start {
 public:
  explicit ReferenceStateStart(double joint_noise_rad = 0.0, int first_frame = 0, int last_frame = -1)
      : noise_(joint_noise_rad), first_(first_frame), last_(last_frame) {}
  void begin(CharacterEnv& env, base::Rng& rng) const override;
  /// The frame an episode starts at (what begin() draws); throws base::UserError for an empty range.
  std::size_t draw_frame(const Clip& clip, base::Rng& rng) const;

 private:
  double noise_;
  int first_, last_;
};

/// Early termination (DeepMimic §6): a fall (a body that must not touch the ground does) or a
/// large deviation from the reference (the COM at least `max_com_deviation_m` from the
/// reference's, or r_p at most `min_pose_reward`).
struct EarlyTermination {
  std::vector<int> fall_bodies;       ///< body indices; fall_bodies_except() builds the usual list
  double max_com_deviation_m = kInf;  ///< m; ∞: never
  double min_pose_reward = 0.0;       ///< 0: never (r_p > 0 always)
};
enum class Termination { none, fell, deviated };
const char* to_string(Termination termination);
/// Every body of the model but those named (e.g. the feet: any other body on the ground is a
/// fall). Throws base::UserError naming an unknown body.
std::vector<int> fall_bodies_except(const sim::CharacterModel& model, const std::vector<std::string>& allowed);
/// Whether the episode ends: fell (checked first), deviated, or none.
Termination early_termination(const EarlyTermination& rule, const sim::Observation& features, const TrackingErrors& errors,
                              const ImitationTerms& terms);

/// The reference's phase in the observation (DeepMimic §5): 1 value, ImitationReference::phase
/// at the env's reference clock. Facing-invariant.
class ReferencePhase : public ObservationPart {
 public:
  explicit ReferencePhase(std::shared_ptr<const ImitationReference> reference) : reference_(std::move(reference)) {}
  std::size_t size(const sim::CharacterModel&) const override { return 1; }
  void write(const CharacterEnv& env, std::span<double> out) const override;

 private:
  std::shared_ptr<const ImitationReference> reference_;
};

}  // namespace podium::character
