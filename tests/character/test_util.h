#pragma once
// Shared helpers for the character tests.
#include <Eigen/Geometry>
#include <cstdlib>
#include <filesystem>

#include "podium/base/rng.h"
#include "podium/character/frames.h"
#include "podium/sim/model.h"
#include "shared_data.h"

namespace podium::character::testing {

/// ../shared/data/deepmimic/data, or empty when it is absent.
inline std::filesystem::path deepmimic_dir() { return podium::testing::shared_data("deepmimic/data"); }

/// A random configuration: root anywhere above the ground, hinges within ±1 rad, balls within 1 rad.
inline Eigen::VectorXd random_q(const sim::CharacterModel& model, base::Rng& rng) {
  Eigen::VectorXd q = model.neutral();
  for (const sim::Link& l : model.links()) {
    if (l.joint == sim::JointType::revolute) {
      q(l.q_index) = rng.uniform(-1, 1);
      continue;
    }
    const Eigen::Vector3d axis(rng.normal(), rng.normal(), rng.normal());
    const Eigen::Quaterniond r(Eigen::AngleAxisd(rng.uniform(-1, 1), axis.normalized()));
    set_quat(q, l.joint == sim::JointType::free ? 3 : l.q_index, r);
    if (l.joint == sim::JointType::free) q.head<3>() << rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0.5, 1.5);
  }
  return q;
}

/// Largest difference between two configurations, quaternions compared as rotations (q ≡ −q).
inline double config_distance(const sim::CharacterModel& model, const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  double worst = (a.head<3>() - b.head<3>()).cwiseAbs().maxCoeff();
  for (const sim::Link& l : model.links()) {
    if (l.joint == sim::JointType::revolute) {
      worst = std::max(worst, std::abs(a(l.q_index) - b(l.q_index)));
      continue;
    }
    const int i = l.joint == sim::JointType::free ? 3 : l.q_index;
    const Eigen::Vector4d qa = a.segment<4>(i), qb = b.segment<4>(i);
    worst = std::max(worst, std::min((qa - qb).cwiseAbs().maxCoeff(), (qa + qb).cwiseAbs().maxCoeff()));
  }
  return worst;
}

}  // namespace podium::character::testing
