#pragma once
/// Bullet's own answer for the dynamics, for checking ours (docs/style.md: "both are checked
/// against Bullet"). No Bullet type crosses this header.
#include <Eigen/Core>

#include "podium/sim/model.h"

namespace podium::sim {

/// q̈ (nv) that Bullet's btMultiBody articulated-body solver computes for state (q, q̇), joint
/// torques τ (root entries ignored) and gravity, without contacts or limits, in our coordinates.
Eigen::VectorXd bullet_forward_dynamics(const CharacterModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                        const Eigen::VectorXd& tau, const Eigen::Vector3d& gravity);

/// Round trip of a state through Bullet's coordinates (set then read back), for tests.
void bullet_state_round_trip(const CharacterModel& model, Eigen::VectorXd& q, Eigen::VectorXd& qd);

}  // namespace podium::sim
