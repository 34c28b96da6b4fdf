#pragma once
/// Rotation helpers shared by the character parts: the heading frame (the root's facing
/// direction on the ground, what facing-invariant observations are expressed in), exponential
/// maps, quaternion slots in q, and DeepMimic's y-up ↔ our z-up frame change.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace podium::character {

/// Heading (rad) of a body: the twist of its rotation about the vertical in the swing–twist split
/// (q = q_swing q_twist about z; yaw = 2·atan2(q_z, q_w)). For an upright body it is the yaw of its
/// forward (+x) axis; unlike that axis's projection it stays defined when the body lies on its
/// back or front (the get-up's usual states), and turning the body by α about the vertical adds
/// exactly α. Undefined only for a body turned half a turn about a horizontal axis.
double heading_yaw(const Eigen::Matrix3d& rotation);
/// The heading frame's rotation Rz(yaw): a world vector v reads Rᵀv in it.
Eigen::Matrix3d heading_rotation(double yaw);

/// The rotation that takes DeepMimic's y-up frame to ours (+90° about x): (x, y, z) ↦ (x, −z, y).
const Eigen::Quaterniond& yup_to_zup();

/// Rotation vector (axis·angle, angle in [0, π]) of a unit quaternion, and back.
Eigen::Vector3d log_map(const Eigen::Quaterniond& r);
Eigen::Quaterniond exp_map(const Eigen::Vector3d& v);

/// The quaternion (w, x, y, z) stored at q[i..i+3], and writing one there.
Eigen::Quaterniond quat_at(const Eigen::VectorXd& q, int i);
void set_quat(Eigen::VectorXd& q, int i, const Eigen::Quaterniond& r);

}  // namespace podium::character
