#pragma once
/// CharacterData: the mutable state, caches and scratch of one character (docs/style.md "sim/").
/// Made from a CharacterModel, sized once: no algorithm allocates after construction.
/// One CharacterData per rollout thread; copying it checkpoints the character.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <vector>

#include "podium/sim/model.h"

namespace podium::sim {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;
/// 6 × (≤ 6) and (≤ 6) × (≤ 6) per-joint blocks, stored inline (no heap).
using Matrix6Xd = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, 6>;

/// Per-link caches. Spatial vectors are [angular; linear] in the link frame (Featherstone).
struct LinkData {
  Matrix6d I_body = Matrix6d::Zero();  // link spatial inertia about its origin (constant)
  // The COM inertia as λ_mid·1 + Σ_k w_k e_k e_kᵀ over the principal axes whose moment differs from
  // the middle one (w_k = λ_k − λ_mid, link frame; 0 axes for a sphere, 1 for a capsule): rotating
  // it to world is λ_mid·1 + Σ_k w_k (R e_k)(R e_k)ᵀ, cheaper than R I Rᵀ (MABA does it per link per call).
  double inertia_mid = 0.0;
  Eigen::Matrix<double, 3, 2> inertia_axis = Eigen::Matrix<double, 3, 2>::Zero();
  Eigen::Vector2d inertia_weight = Eigen::Vector2d::Zero();
  int inertia_axes = 0;
  Matrix6Xd S;                                      // motion subspace in link frame, 6 × nv (constant)
  Eigen::Matrix3d E = Eigen::Matrix3d::Identity();  // rotation parent→link coordinates; forward_kinematics
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // link orientation in world; forward_kinematics
  Eigen::Vector3d p = Eigen::Vector3d::Zero();      // link origin in world, m; forward_kinematics
  Vector6d v = Vector6d::Zero();                    // spatial velocity; velocity pass
  Vector6d c = Vector6d::Zero();                    // velocity-product acceleration v × S q̇
  Vector6d a = Vector6d::Zero();                    // spatial acceleration (MABA: world coordinates)
  Vector6d f = Vector6d::Zero();                    // spatial force (RNEA) / bias force p^A (MABA, world coordinates)
  Matrix6d I = Matrix6d::Zero();                    // composite (CRBA) / articulated (MABA, world coordinates) inertia
  // MABA caches, world coordinates. The per-joint blocks (6 × nv, nv × nv, nv) sit in the top-left
  // corner of fixed 6-wide storage: fixed sizes keep the O(n) passes free of size checks.
  Matrix6d S_world = Matrix6d::Zero();  // motion subspace at the world origin
  Vector6d v_world = Vector6d::Zero();  // velocity and velocity-product term
  Vector6d c_world = Vector6d::Zero();
  Matrix6d U = Matrix6d::Zero();      // I^A S
  Matrix6d D_inv = Matrix6d::Zero();  // (Sᵀ I^A S + K)⁻¹ (thesis eq. 2.18)
  Vector6d u = Vector6d::Zero();      // Q − Sᵀ p^A
};

class CharacterData {
 public:
  explicit CharacterData(const CharacterModel& model);

  Eigen::VectorXd q;    // positions (nq): root pos m, root quat wxyz, joint angles rad / quats wxyz
  Eigen::VectorXd qd;   // velocities (nv): root ω, v in root frame; joint rates (spherical: ω in child frame)
  Eigen::VectorXd qdd;  // accelerations (nv); written by forward dynamics and stable_pd_*
  Eigen::VectorXd tau;  // generalized forces (nv), N·m; written by stable_pd_* and controllers

  Eigen::MatrixXd M;                // joint-space inertia (nv × nv); written by mass_matrix (CRBA)
  Eigen::VectorXd C;                // bias forces: Coriolis, centrifugal, gravity (nv); written by bias_forces (RNEA)
  Eigen::VectorXd Q;                // SPD spring-damper part, thesis eq. 2.20 (nv); written by stable_pd_*
  Eigen::LLT<Eigen::MatrixXd> llt;  // Cholesky of M (+ Kd Δt); written by dense solvers
  std::vector<LinkData> links;
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};  // m/s²
};

}  // namespace podium::sim
