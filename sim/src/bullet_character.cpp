#include "bullet_character.h"

#include <Eigen/Eigenvalues>

namespace podium::sim {

namespace {

// Principal axes of a link's inertia as a proper rotation (identity for massless links).
Eigen::Quaterniond principal_axes(const Link& l, Eigen::Vector3d& moments) {
  if (l.mass <= 0) {
    moments.setZero();
    return Eigen::Quaterniond::Identity();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(l.inertia);
  Eigen::Matrix3d V = eig.eigenvectors();
  if (V.determinant() < 0) V.col(2) = -V.col(2);
  moments = eig.eigenvalues();
  return Eigen::Quaterniond(V).normalized();
}

}  // namespace

BulletCharacter::BulletCharacter(const CharacterModel& model) : model_(model) {
  const auto& links = model.links();
  const int n = static_cast<int>(links.size());
  std::vector<Eigen::Vector3d> moments(n);
  principal_.resize(n);
  for (int i = 0; i < n; ++i) principal_[i] = principal_axes(links[i], moments[i]);

  body_ = std::make_unique<btMultiBody>(n - 1, links[0].mass, to_bt(moments[0]), /*fixedBase=*/false, /*canSleep=*/false);
  for (int i = 1; i < n; ++i) {
    const Link& l = links[i];
    const Link& p = links[l.parent];
    const Eigen::Matrix3d Ri = principal_[i].toRotationMatrix(), Rp = principal_[l.parent].toRotationMatrix();
    const btQuaternion rot_parent_to_this = to_bt(Eigen::Quaterniond(Eigen::Matrix3d(Ri.transpose() * Rp)));
    const btVector3 parent_com_to_pivot = to_bt(Rp.transpose() * (l.joint_pos - p.com));
    const btVector3 pivot_to_com = to_bt(Ri.transpose() * l.com);
    if (l.joint == JointType::revolute) {
      body_->setupRevolute(i - 1, l.mass, to_bt(moments[i]), l.parent - 1, rot_parent_to_this, to_bt(Ri.transpose() * l.axis),
                           parent_com_to_pivot, pivot_to_com, /*disableParentCollision=*/true);
    } else {
      body_->setupSpherical(i - 1, l.mass, to_bt(moments[i]), l.parent - 1, rot_parent_to_this, parent_com_to_pivot, pivot_to_com,
                            /*disableParentCollision=*/true);
    }
  }
  body_->finalizeMultiDof();
  // Match the rigid-body equations exactly: no artificial damping, no velocity clamp.
  body_->setLinearDamping(0);
  body_->setAngularDamping(0);
  body_->setUseGyroTerm(true);
  body_->setMaxCoordinateVelocity(1e6);
  body_->setMaxAppliedImpulse(1e6);
}

void BulletCharacter::set_state(const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  const auto& links = model_.links();
  const Link& root = links[0];
  const Eigen::Quaterniond R0q = Eigen::Quaterniond(q(3), q(4), q(5), q(6)).normalized();
  const Eigen::Matrix3d R0 = R0q.toRotationMatrix();
  const Eigen::Vector3d w = qd.head<3>(), v = qd.segment<3>(3);
  body_->setBasePos(to_bt(Eigen::Vector3d(q.head<3>() + R0 * root.com)));
  body_->setWorldToBaseRot(to_bt((R0q * principal_[0]).conjugate()));
  body_->setBaseOmega(to_bt(Eigen::Vector3d(R0 * w)));
  body_->setBaseVel(to_bt(Eigen::Vector3d(R0 * (v + w.cross(root.com)))));
  for (std::size_t i = 1; i < links.size(); ++i) {
    const Link& l = links[i];
    const int b = static_cast<int>(i) - 1;
    if (l.joint == JointType::revolute) {
      body_->setJointPos(b, q(l.q_index));
      body_->setJointVel(b, qd(l.v_index));
    } else {
      const Eigen::Quaterniond qf(q(l.q_index), q(l.q_index + 1), q(l.q_index + 2), q(l.q_index + 3));
      const Eigen::Quaterniond qb = principal_[i].conjugate() * qf.normalized() * principal_[i];
      btScalar pos[4] = {qb.x(), qb.y(), qb.z(), qb.w()};
      body_->setJointPosMultiDof(b, pos);
      const Eigen::Vector3d wb = principal_[i].conjugate() * Eigen::Vector3d(qd.segment<3>(l.v_index));
      btScalar vel[3] = {wb.x(), wb.y(), wb.z()};
      body_->setJointVelMultiDof(b, vel);
    }
  }
}

void BulletCharacter::get_state(Eigen::VectorXd& q, Eigen::VectorXd& qd) const {
  const auto& links = model_.links();
  const Link& root = links[0];
  const Eigen::Quaterniond Rb = to_eigen(body_->getWorldToBaseRot()).conjugate();
  const Eigen::Quaterniond R0q = (Rb * principal_[0].conjugate()).normalized();
  const Eigen::Matrix3d R0 = R0q.toRotationMatrix();
  q.head<3>() = to_eigen(body_->getBasePos()) - R0 * root.com;
  q.segment<4>(3) << R0q.w(), R0q.x(), R0q.y(), R0q.z();
  const Eigen::Vector3d w = R0.transpose() * to_eigen(body_->getBaseOmega());
  qd.head<3>() = w;
  qd.segment<3>(3) = R0.transpose() * to_eigen(body_->getBaseVel()) - w.cross(root.com);
  for (std::size_t i = 1; i < links.size(); ++i) {
    const Link& l = links[i];
    const int b = static_cast<int>(i) - 1;
    if (l.joint == JointType::revolute) {
      q(l.q_index) = body_->getJointPos(b);
      qd(l.v_index) = body_->getJointVel(b);
    } else {
      const btScalar* p = body_->getJointPosMultiDof(b);
      const Eigen::Quaterniond qf =
          (principal_[i] * Eigen::Quaterniond(p[3], p[0], p[1], p[2]) * principal_[i].conjugate()).normalized();
      q.segment<4>(l.q_index) << qf.w(), qf.x(), qf.y(), qf.z();
      const btScalar* v = body_->getJointVelMultiDof(b);
      qd.segment<3>(l.v_index) = principal_[i] * Eigen::Vector3d(v[0], v[1], v[2]);
    }
  }
}

void BulletCharacter::add_joint_torques(const Eigen::VectorXd& tau) {
  const auto& links = model_.links();
  for (std::size_t i = 1; i < links.size(); ++i) {
    const Link& l = links[i];
    const int b = static_cast<int>(i) - 1;
    if (l.joint == JointType::revolute) {
      body_->addJointTorque(b, tau(l.v_index));
    } else {
      const Eigen::Vector3d tb = principal_[i].conjugate() * Eigen::Vector3d(tau.segment<3>(l.v_index));
      for (int k = 0; k < 3; ++k) body_->addJointTorqueMultiDof(b, k, tb(k));
    }
  }
}

void BulletCharacter::add_gravity(const Eigen::Vector3d& g) {
  const auto& links = model_.links();
  body_->addBaseForce(to_bt(Eigen::Vector3d(links[0].mass * g)));
  for (std::size_t i = 1; i < links.size(); ++i)
    body_->addLinkForce(static_cast<int>(i) - 1, to_bt(Eigen::Vector3d(links[i].mass * g)));
}

void BulletCharacter::forward_dynamics(Eigen::VectorXd& qdd) {
  body_->computeAccelerationsArticulatedBodyAlgorithmMultiDof(0.0, scratch_r_, scratch_v_, scratch_m_, false, false, false);
  const btScalar* out = &scratch_r_[body_->getNumDofs()];
  const auto& links = model_.links();
  const Link& root = links[0];
  const Eigen::Quaterniond Rb = to_eigen(body_->getWorldToBaseRot()).conjugate();
  const Eigen::Matrix3d R0 = (Rb * principal_[0].conjugate()).toRotationMatrix();
  const Eigen::Vector3d w = R0.transpose() * to_eigen(body_->getBaseOmega());
  const Eigen::Vector3d v_com = R0.transpose() * to_eigen(body_->getBaseVel());
  const Eigen::Vector3d v = v_com - w.cross(root.com);  // root-origin velocity, root frame
  // Bullet reports ω̇ and the classical acceleration of the base COM, both in world frame.
  const Eigen::Vector3d wdot = R0.transpose() * Eigen::Vector3d(out[0], out[1], out[2]);
  const Eigen::Vector3d acc_com = R0.transpose() * Eigen::Vector3d(out[3], out[4], out[5]);
  const Eigen::Vector3d acc_origin = acc_com - wdot.cross(root.com) - w.cross(w.cross(root.com));
  qdd.head<3>() = wdot;
  qdd.segment<3>(3) = acc_origin - w.cross(v);  // spatial acceleration = classical − ω × v
  const btScalar* joint = out + 6;
  for (std::size_t i = 1; i < links.size(); ++i) {
    const Link& l = links[i];
    const int off = body_->getLink(static_cast<int>(i) - 1).m_dofOffset;
    if (l.joint == JointType::revolute) {
      qdd(l.v_index) = joint[off];
    } else {
      qdd.segment<3>(l.v_index) = principal_[i] * Eigen::Vector3d(joint[off], joint[off + 1], joint[off + 2]);
    }
  }
}

}  // namespace podium::sim
