#pragma once
// Spatial (6D) algebra in Featherstone's convention: motion and force vectors are
// [angular; linear] in a link frame. A transform X (parent → child coordinates) is the pair
// (E, r): E rotates parent coordinates into child coordinates, r is the child origin in parent
// coordinates. Hand-written because Eigen has no spatial algebra and these few lines are all we need.
#include <Eigen/Core>

#include "podium/sim/data.h"

namespace podium::sim::spatial {

/// X m: motion vector from parent to child coordinates.
inline Vector6d motion(const Eigen::Matrix3d& E, const Eigen::Vector3d& r, const Vector6d& m) {
  Vector6d out;
  out.head<3>() = E * m.head<3>();
  out.tail<3>() = E * (m.tail<3>() - r.cross(m.head<3>()));
  return out;
}

/// Xᵀ f: force vector from child to parent coordinates.
inline Vector6d force_to_parent(const Eigen::Matrix3d& E, const Eigen::Vector3d& r, const Vector6d& f) {
  Vector6d out;
  out.tail<3>() = E.transpose() * f.tail<3>();
  out.head<3>() = E.transpose() * f.head<3>() + r.cross(out.tail<3>());
  return out;
}

/// r × M, column by column (= skew(r) M without the zeros).
inline Eigen::Matrix3d cross_columns(const Eigen::Vector3d& r, const Eigen::Matrix3d& M) {
  Eigen::Matrix3d out;
  for (int c = 0; c < 3; ++c) out.col(c) = r.cross(M.col(c));
  return out;
}

/// Eᵀ S E for symmetric S, exactly symmetric.
inline Eigen::Matrix3d rotate_symmetric(const Eigen::Matrix3d& E, const Eigen::Matrix3d& S) {
  const Eigen::Matrix3d T = S * E;
  Eigen::Matrix3d out;
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) out(i, j) = out(j, i) = E.col(i).dot(T.col(j));
  return out;
}

/// Xᵀ I X for a symmetric spatial inertia: from child to parent coordinates, added to `parent`,
/// by 3×3 blocks. With I' = diag(Eᵀ, Eᵀ) I diag(E, E) = [A B; Bᵀ C] and R = r×:
/// Xᵀ I X = [A − B R + R Bᵀ − R C R,  B + R C;  Bᵀ − C R,  C], where −B R = (R Bᵀ)ᵀ and
/// R C R = (R C) R is symmetric: cross products and symmetric halves instead of 3×3 products
/// (MABA's and CRBA's hot spot).
inline void add_inertia_to_parent(const Eigen::Matrix3d& E, const Eigen::Vector3d& r, const Matrix6d& I, Matrix6d& parent) {
  const Eigen::Matrix3d A = rotate_symmetric(E, I.topLeftCorner<3, 3>());
  const Eigen::Matrix3d B = E.transpose() * (Eigen::Matrix3d(I.topRightCorner<3, 3>()) * E);
  const Eigen::Matrix3d C = rotate_symmetric(E, I.bottomRightCorner<3, 3>());
  const Eigen::Matrix3d RBt = cross_columns(r, B.transpose());
  const Eigen::Matrix3d RC = cross_columns(r, C);
  // (R C) R = −(R (R C)ᵀ)ᵀ = −R (R C)ᵀ since the result is symmetric.
  const Eigen::Matrix3d RCR = -cross_columns(r, RC.transpose());
  parent.topLeftCorner<3, 3>() += A + RBt + RBt.transpose() - RCR;
  parent.topRightCorner<3, 3>() += B + RC;
  parent.bottomLeftCorner<3, 3>() += B.transpose() + RC.transpose();
  parent.bottomRightCorner<3, 3>() += C;
}

/// v ×m m (motion cross product).
inline Vector6d cross_motion(const Vector6d& v, const Vector6d& m) {
  Vector6d out;
  out.head<3>() = v.head<3>().cross(m.head<3>());
  out.tail<3>() = v.head<3>().cross(m.tail<3>()) + v.tail<3>().cross(m.head<3>());
  return out;
}

/// v ×f f (force cross product).
inline Vector6d cross_force(const Vector6d& v, const Vector6d& f) {
  Vector6d out;
  out.head<3>() = v.head<3>().cross(f.head<3>()) + v.tail<3>().cross(f.tail<3>());
  out.tail<3>() = v.head<3>().cross(f.tail<3>());
  return out;
}

/// Spatial inertia about the frame origin of a body with mass m, COM c and inertia Ic about c,
/// written into I: [Ic + m c× c×ᵀ, m c×; m c×ᵀ, m 1] (c× c×ᵀ = |c|² 1 − c cᵀ). Entry by entry, so
/// I is exactly symmetric and MABA's per-link rebuild costs a few flops beyond the 36 stores.
inline void inertia(double m, const Eigen::Vector3d& c, const Eigen::Matrix3d& Ic, Matrix6d& I) {
  const double mx = m * c.x(), my = m * c.y(), mz = m * c.z();
  I(0, 0) = Ic(0, 0) + my * c.y() + mz * c.z();
  I(1, 1) = Ic(1, 1) + mx * c.x() + mz * c.z();
  I(2, 2) = Ic(2, 2) + mx * c.x() + my * c.y();
  I(0, 1) = I(1, 0) = Ic(1, 0) - mx * c.y();
  I(0, 2) = I(2, 0) = Ic(2, 0) - mx * c.z();
  I(1, 2) = I(2, 1) = Ic(2, 1) - my * c.z();
  // m c× = [0 −mz my; mz 0 −mx; −my mx 0] top right, its transpose bottom left
  I(0, 3) = I(3, 0) = 0.0;
  I(1, 4) = I(4, 1) = 0.0;
  I(2, 5) = I(5, 2) = 0.0;
  I(0, 4) = I(4, 0) = -mz;
  I(0, 5) = I(5, 0) = my;
  I(1, 3) = I(3, 1) = mz;
  I(1, 5) = I(5, 1) = -mx;
  I(2, 3) = I(3, 2) = -my;
  I(2, 4) = I(4, 2) = mx;
  I.bottomRightCorner<3, 3>() = m * Eigen::Matrix3d::Identity();
}

}  // namespace podium::sim::spatial
