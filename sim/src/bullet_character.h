#pragma once
// A CharacterModel as a Bullet btMultiBody (double precision), and the conversions between our
// coordinates and Bullet's. Bullet places each link frame at the link's centre of mass, along
// its principal axes, and keeps the base velocity as world-frame ω and COM velocity; we keep
// link frames at joint anchors and the root velocity in the root frame. Bullet types stay here.
#include <BulletDynamics/Featherstone/btMultiBody.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "podium/sim/model.h"

namespace podium::sim {

class BulletCharacter {
 public:
  explicit BulletCharacter(const CharacterModel& model);
  BulletCharacter(const BulletCharacter&) = delete;
  BulletCharacter& operator=(const BulletCharacter&) = delete;

  btMultiBody& body() { return *body_; }
  const CharacterModel& model() const { return model_; }
  /// Principal-axes rotation of link i (Bullet link frame in our link frame).
  const Eigen::Quaterniond& principal(int link) const { return principal_[link]; }

  void set_state(const Eigen::VectorXd& q, const Eigen::VectorXd& qd);
  void get_state(Eigen::VectorXd& q, Eigen::VectorXd& qd) const;
  /// Adds joint torques (nv; root entries ignored) to Bullet's accumulators.
  void add_joint_torques(const Eigen::VectorXd& tau);
  /// Adds m·g at every link's centre of mass (Bullet's world does this when stepping).
  void add_gravity(const Eigen::Vector3d& g);
  /// Bullet's articulated-body forward dynamics for the current state and accumulated forces,
  /// converted to our q̈ (nv).
  void forward_dynamics(Eigen::VectorXd& qdd);

 private:
  const CharacterModel& model_;
  std::unique_ptr<btMultiBody> body_;
  std::vector<Eigen::Quaterniond> principal_;
  btAlignedObjectArray<btScalar> scratch_r_;
  btAlignedObjectArray<btVector3> scratch_v_;
  btAlignedObjectArray<btMatrix3x3> scratch_m_;
};

inline btVector3 to_bt(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
inline Eigen::Vector3d to_eigen(const btVector3& v) { return {v.x(), v.y(), v.z()}; }
inline btQuaternion to_bt(const Eigen::Quaterniond& q) { return {q.x(), q.y(), q.z(), q.w()}; }
inline Eigen::Quaterniond to_eigen(const btQuaternion& q) { return {q.w(), q.x(), q.y(), q.z()}; }

}  // namespace podium::sim
