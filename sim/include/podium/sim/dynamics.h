#pragma once
/// Rigid-body algorithms as free functions over (model, data), after Pinocchio. All read
/// data.q / data.qd and write the caches named in data.h. Root velocity is the root link's
/// spatial velocity in its own frame; accelerations are its spatial acceleration.
#include "podium/sim/data.h"
#include "podium/sim/model.h"

namespace podium::sim {

/// Link poses from data.q (data.links[i].E, R, p).
void forward_kinematics(const CharacterModel& model, CharacterData& data);
/// Joint-space inertia M by the composite-rigid-body algorithm (Featherstone §6.2); calls
/// forward_kinematics. Writes data.M (lower and upper triangle).
void mass_matrix(const CharacterModel& model, CharacterData& data);
/// Bias forces C = RNEA(q, q̇, 0) including gravity (Featherstone §5.3). Writes data.C.
void bias_forces(const CharacterModel& model, CharacterData& data);
/// q̈ = M⁻¹(τ − C) by dense Cholesky; writes data.qdd (and data.M, data.C).
void forward_dynamics_dense(const CharacterModel& model, CharacterData& data, const Eigen::VectorXd& tau);

/// PD gains per DoF (nv each). Spherical joints take one gain per axis. Root entries are 0 for a
/// free character; nonzero root gains servo the root to its target (the thesis's "hand-of-God"
/// root forces, §2.4.1), as a 6-D spatial force in the root frame.
struct Gains {
  Eigen::VectorXd kp;  // N·m/rad
  Eigen::VectorXd kd;  // N·m·s/rad
  /// The model's own gains.
  static Gains from_model(const CharacterModel& model);
};

/// Stable PD (thesis eq. 2.6) with targets q̄ (nq; root entries ignored): τ = −Kp(q + Δt·q̇ − q̄) − Kd(q̇ + Δt·q̈). Spherical joints
/// use the rotation vector of q̄⁻¹q in place of q − q̄. Writes data.tau (root entries: the root servo force, 0 by default) and
/// data.qdd. Dense: solves (M + Kd Δt) q̈ = Q − C by Cholesky (thesis eq. 2.7), O(n³).
void stable_pd_dense(const CharacterModel& model, CharacterData& data, const Gains& gains, const Eigen::VectorXd& target,
                     double dt_s);
/// MABA: the modified articulated-body algorithm (thesis §2.3, eqs. 2.17–2.29), O(n).
void stable_pd_maba(const CharacterModel& model, CharacterData& data, const Gains& gains, const Eigen::VectorXd& target,
                    double dt_s);
/// Plain PD: τ = −Kp(q − q̄) − Kd q̇ (explicit). Writes data.tau.
void pd_torques(const CharacterModel& model, CharacterData& data, const Gains& gains, const Eigen::VectorXd& target);

/// q ← q ⊕ Δt·q̇, the position half of semi-implicit Euler (q̇ already advanced): ball-joint and
/// root quaternions by the exponential of their body-frame ω, hinge angles by Δt·q̇, and the
/// root as Bullet integrates a base: its centre of mass moves with its world velocity, which then
/// stays constant while q̇'s root entries are re-expressed in the rotated root frame.
void integrate(const CharacterModel& model, Eigen::VectorXd& q, Eigen::VectorXd& qd, double dt_s);

/// World position of a point given in a body's frame (after forward_kinematics).
Eigen::Vector3d body_point(const CharacterModel& model, const CharacterData& data, int body, const Eigen::Vector3d& local);
/// Lowest world z of any geom (m); needs forward_kinematics.
double lowest_geom_point(const CharacterModel& model, const CharacterData& data);
/// Centre of mass (world, m) and its velocity (world, m/s); needs forward_kinematics.
void center_of_mass(const CharacterModel& model, CharacterData& data, Eigen::Vector3d& com, Eigen::Vector3d& com_vel);

}  // namespace podium::sim
