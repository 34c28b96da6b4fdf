#include "podium/character/frames.h"

#include <cmath>
#include <numbers>

namespace podium::character {

double heading_yaw(const Eigen::Matrix3d& rotation) {
  Eigen::Quaterniond q(rotation);
  if (q.w() < 0) q.coeffs() = -q.coeffs();  // the same rotation, so the yaw lands in [−π, π]
  return 2.0 * std::atan2(q.z(), q.w());
}

Eigen::Matrix3d heading_rotation(double yaw) { return Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }

const Eigen::Quaterniond& yup_to_zup() {
  static const Eigen::Quaterniond c(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitX()));
  return c;
}

Eigen::Vector3d log_map(const Eigen::Quaterniond& r) {
  Eigen::Quaterniond u = r.normalized();
  if (u.w() < 0) u.coeffs() = -u.coeffs();  // q and −q are one rotation: take the short way
  const double s = u.vec().norm();
  if (s < 1e-12) return 2.0 * u.vec();
  return u.vec() * (2.0 * std::atan2(s, u.w()) / s);
}

Eigen::Quaterniond exp_map(const Eigen::Vector3d& v) {
  const double angle = v.norm();
  if (angle < 1e-12) return Eigen::Quaterniond(1.0, 0.5 * v.x(), 0.5 * v.y(), 0.5 * v.z()).normalized();
  const Eigen::Vector3d axis = v / angle;
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, axis));
}

Eigen::Quaterniond quat_at(const Eigen::VectorXd& q, int i) { return Eigen::Quaterniond(q(i), q(i + 1), q(i + 2), q(i + 3)); }

void set_quat(Eigen::VectorXd& q, int i, const Eigen::Quaterniond& r) { q.segment<4>(i) << r.w(), r.x(), r.y(), r.z(); }

}  // namespace podium::character
