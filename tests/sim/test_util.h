#pragma once
// Random states and shared helpers for the sim tests (seeded; no global RNG).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>

#include "podium/base/rng.h"
#include "podium/sim/model.h"

namespace podium::sim::testing {

inline Eigen::Quaterniond random_quat(base::Rng& rng, double max_angle) {
  Eigen::Vector3d axis(rng.normal(), rng.normal(), rng.normal());
  return Eigen::Quaterniond(Eigen::AngleAxisd(rng.uniform(-max_angle, max_angle), axis.normalized()));
}

/// A random configuration and velocity: root anywhere, joints within ±1 rad, velocities ~N(0, 1).
inline void random_state(const CharacterModel& model, base::Rng& rng, Eigen::VectorXd& q, Eigen::VectorXd& qd) {
  q = model.neutral();
  qd.resize(model.nv());
  for (int i = 0; i < model.nv(); ++i) qd(i) = rng.normal();
  for (const Link& l : model.links()) {
    if (l.joint == JointType::revolute) {
      q(l.q_index) = rng.uniform(-1, 1);
    } else {
      const int i = l.joint == JointType::free ? l.q_index + 3 : l.q_index;
      const Eigen::Quaterniond r = random_quat(rng, l.joint == JointType::free ? M_PI : 1.0);
      q.segment<4>(i) << r.w(), r.x(), r.y(), r.z();
      if (l.joint == JointType::free) q.head<3>() << rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0, 2);
    }
  }
}

inline double relative_error(const Eigen::VectorXd& a, const Eigen::VectorXd& reference) {
  return (a - reference).lpNorm<Eigen::Infinity>() / std::max(reference.lpNorm<Eigen::Infinity>(), 1e-12);
}

}  // namespace podium::sim::testing
