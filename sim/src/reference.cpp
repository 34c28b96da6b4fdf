#include "podium/sim/reference.h"

#include "bullet_character.h"

namespace podium::sim {

Eigen::VectorXd bullet_forward_dynamics(const CharacterModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                        const Eigen::VectorXd& tau, const Eigen::Vector3d& gravity) {
  BulletCharacter character(model);
  character.set_state(q, qd);
  character.body().clearForcesAndTorques();
  character.add_gravity(gravity);
  character.add_joint_torques(tau);
  Eigen::VectorXd qdd(model.nv());
  character.forward_dynamics(qdd);
  return qdd;
}

void bullet_state_round_trip(const CharacterModel& model, Eigen::VectorXd& q, Eigen::VectorXd& qd) {
  BulletCharacter character(model);
  character.set_state(q, qd);
  character.get_state(q, qd);
}

}  // namespace podium::sim
