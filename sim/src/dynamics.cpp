// CRBA, RNEA, dense forward dynamics and kinematics (Featherstone, "Rigid Body Dynamics
// Algorithms", 2008, §§4–6), hand-written over the model's link tree because no packaged
// library builds from our model format. Spatial conventions in spatial.h.
#include "podium/sim/dynamics.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "internal.h"
#include "spatial.h"

namespace podium::sim {

CharacterData::CharacterData(const CharacterModel& model)
    : q(model.neutral()),
      qd(Eigen::VectorXd::Zero(model.nv())),
      qdd(Eigen::VectorXd::Zero(model.nv())),
      tau(Eigen::VectorXd::Zero(model.nv())),
      M(Eigen::MatrixXd::Zero(model.nv(), model.nv())),
      C(Eigen::VectorXd::Zero(model.nv())),
      Q(Eigen::VectorXd::Zero(model.nv())),
      llt(model.nv()),
      links(model.links().size()) {
  for (std::size_t i = 0; i < links.size(); ++i) {
    const Link& l = model.links()[i];
    LinkData& d = links[i];
    spatial::inertia(l.mass, l.com, l.inertia, d.I_body);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> principal(l.inertia);  // ascending moments
    d.inertia_mid = principal.eigenvalues()(1);
    for (int k : {0, 2}) {
      // Differences below 1e-12 of the largest moment are round-off of a symmetric shape.
      const double w = principal.eigenvalues()(k) - d.inertia_mid;
      if (std::abs(w) <= 1e-12 * principal.eigenvalues()(2)) continue;
      d.inertia_axis.col(d.inertia_axes) = principal.eigenvectors().col(k);
      d.inertia_weight(d.inertia_axes++) = w;
    }
    d.S = Matrix6Xd::Zero(6, l.nv);
    if (l.joint == JointType::free) d.S = Matrix6d::Identity();
    if (l.joint == JointType::spherical) d.S.topRows<3>().setIdentity();
    if (l.joint == JointType::revolute) d.S.col(0).head<3>() = l.axis;
  }
  // Eigen's sizing constructor leaves the LLT's status unset, and copying a CharacterData (world
  // snapshots do) would read it (UBSan: invalid enum load); a factor of the identity sets every
  // field and keeps the storage. Every dense solver computes its own factor before solving.
  llt.compute(Eigen::MatrixXd::Identity(model.nv(), model.nv()));
}

namespace {
Eigen::Quaterniond quat_at(const Eigen::VectorXd& q, int i) {
  return Eigen::Quaterniond(q(i), q(i + 1), q(i + 2), q(i + 3)).normalized();
}

}  // namespace

namespace internal {

// Velocities v_i = X_i v_p + S_i q̇_i and velocity-product terms c_i = v_i × S_i q̇_i.
void velocity_pass(const CharacterModel& model, CharacterData& data) {
  const auto& links = model.links();
  for (std::size_t i = 0; i < links.size(); ++i) {
    const Link& l = links[i];
    LinkData& d = data.links[i];
    const Vector6d vj = d.S * data.qd.segment(l.v_index, l.nv);
    if (l.parent < 0) {
      d.v = vj;
      d.c.setZero();
    } else {
      d.v = spatial::motion(d.E, l.joint_pos, data.links[l.parent].v) + vj;
      d.c = spatial::cross_motion(d.v, vj);
    }
  }
}

}  // namespace internal

using internal::velocity_pass;

namespace {
// The fictitious upward acceleration −g that accounts for gravity, in root coordinates.
Vector6d root_gravity_accel(const CharacterData& data) {
  Vector6d a = Vector6d::Zero();
  a.tail<3>() = -(data.links[0].E * data.gravity);
  return a;
}
}  // namespace

void forward_kinematics(const CharacterModel& model, CharacterData& data) {
  const auto& links = model.links();
  for (std::size_t i = 0; i < links.size(); ++i) {
    const Link& l = links[i];
    LinkData& d = data.links[i];
    Eigen::Matrix3d Rj = Eigen::Matrix3d::Identity();
    switch (l.joint) {
      case JointType::free:
        Rj = quat_at(data.q, l.q_index + 3).toRotationMatrix();
        break;
      case JointType::spherical:
        Rj = quat_at(data.q, l.q_index).toRotationMatrix();
        break;
      case JointType::revolute:
        Rj = Eigen::AngleAxisd(data.q(l.q_index), l.axis).toRotationMatrix();
        break;
    }
    d.E = Rj.transpose();
    if (l.parent < 0) {
      d.R = Rj;
      d.p = data.q.head<3>();
    } else {
      const LinkData& p = data.links[l.parent];
      d.R = p.R * Rj;
      d.p = p.p + p.R * l.joint_pos;
    }
  }
}

void mass_matrix(const CharacterModel& model, CharacterData& data) {
  forward_kinematics(model, data);
  internal::mass_matrix_posed(model, data);
}

void internal::mass_matrix_posed(const CharacterModel& model, CharacterData& data) {
  const auto& links = model.links();
  const int n = static_cast<int>(links.size());
  for (int i = 0; i < n; ++i) data.links[i].I = data.links[i].I_body;
  for (int i = n - 1; i > 0; --i) {
    const Link& l = links[i];
    spatial::add_inertia_to_parent(data.links[i].E, l.joint_pos, data.links[i].I, data.links[l.parent].I);
  }
  for (int i = 0; i < n; ++i) {
    const Link& l = links[i];
    Matrix6Xd F = data.links[i].I * data.links[i].S;
    data.M.block(l.v_index, l.v_index, l.nv, l.nv) = data.links[i].S.transpose() * F;
    int j = i;
    while (links[j].parent >= 0) {
      for (int k = 0; k < F.cols(); ++k) F.col(k) = spatial::force_to_parent(data.links[j].E, links[j].joint_pos, F.col(k));
      j = links[j].parent;
      const Link& lj = links[j];
      data.M.block(lj.v_index, l.v_index, lj.nv, l.nv) = data.links[j].S.transpose() * F;
      data.M.block(l.v_index, lj.v_index, l.nv, lj.nv) = data.M.block(lj.v_index, l.v_index, lj.nv, l.nv).transpose();
    }
  }
  // MuJoCo adds joint armature (rotor inertia) to the diagonal of the joint-space inertia.
  if (model.has_armature()) data.M.diagonal() += model.armature();
}

void bias_forces(const CharacterModel& model, CharacterData& data) {
  forward_kinematics(model, data);
  internal::bias_forces_posed(model, data);
}

void internal::bias_forces_posed(const CharacterModel& model, CharacterData& data) {
  velocity_pass(model, data);
  const auto& links = model.links();
  const int n = static_cast<int>(links.size());
  const Vector6d a0 = root_gravity_accel(data);
  for (int i = 0; i < n; ++i) {
    const Link& l = links[i];
    LinkData& d = data.links[i];
    d.a = l.parent < 0 ? a0 : Vector6d(spatial::motion(d.E, l.joint_pos, data.links[l.parent].a) + d.c);
    d.f = d.I_body * d.a + spatial::cross_force(d.v, d.I_body * d.v);
  }
  for (int i = n - 1; i >= 0; --i) {
    const Link& l = links[i];
    LinkData& d = data.links[i];
    data.C.segment(l.v_index, l.nv) = d.S.transpose() * d.f;
    if (l.parent >= 0) data.links[l.parent].f += spatial::force_to_parent(d.E, l.joint_pos, d.f);
  }
}

void forward_dynamics_dense(const CharacterModel& model, CharacterData& data, const Eigen::VectorXd& tau) {
  mass_matrix(model, data);
  bias_forces(model, data);
  data.llt.compute(data.M);
  data.qdd = tau - data.C;
  data.llt.solveInPlace(data.qdd);
}

void integrate(const CharacterModel& model, Eigen::VectorXd& q, Eigen::VectorXd& qd, double dt_s) {
  auto rotate = [&](int qi, const Eigen::Vector3d& omega_body) {
    const double angle = omega_body.norm() * dt_s;
    const Eigen::Quaterniond step =
        angle > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, omega_body.normalized())) : Eigen::Quaterniond::Identity();
    const Eigen::Quaterniond r = (quat_at(q, qi) * step).normalized();
    q.segment<4>(qi) << r.w(), r.x(), r.y(), r.z();
  };
  for (const Link& l : model.links()) {
    switch (l.joint) {
      case JointType::free: {
        // ω is unchanged in the rotated frame (a rotation about ω leaves it fixed).
        const Eigen::Vector3d w = qd.segment<3>(l.v_index),
                              com_vel =
                                  quat_at(q, l.q_index + 3) * Eigen::Vector3d(qd.segment<3>(l.v_index + 3) + w.cross(l.com));
        const Eigen::Vector3d com = q.head<3>() + quat_at(q, l.q_index + 3) * l.com + dt_s * com_vel;
        rotate(l.q_index + 3, w);
        const Eigen::Quaterniond R1 = quat_at(q, l.q_index + 3);
        q.head<3>() = com - R1 * l.com;
        qd.segment<3>(l.v_index + 3) = R1.conjugate() * com_vel - w.cross(l.com);
        break;
      }
      case JointType::spherical:
        rotate(l.q_index, qd.segment<3>(l.v_index));
        break;
      case JointType::revolute:
        q(l.q_index) += dt_s * qd(l.v_index);
        break;
    }
  }
}

Eigen::Vector3d body_point(const CharacterModel& model, const CharacterData& data, int body, const Eigen::Vector3d& local) {
  const Body& b = model.bodies()[body];
  const LinkData& d = data.links[b.link];
  return d.p + d.R * (b.offset + local);
}

void center_of_mass(const CharacterModel& model, CharacterData& data, Eigen::Vector3d& com, Eigen::Vector3d& com_vel) {
  velocity_pass(model, data);
  com.setZero();
  com_vel.setZero();
  const auto& links = model.links();
  for (std::size_t i = 0; i < links.size(); ++i) {
    const LinkData& d = data.links[i];
    const Link& l = links[i];
    com += l.mass * (d.p + d.R * l.com);
    com_vel += l.mass * (d.R * (d.v.tail<3>() + d.v.head<3>().cross(l.com)));
  }
  com /= model.total_mass();
  com_vel /= model.total_mass();
}

double lowest_geom_point(const CharacterModel& model, const CharacterData& data) {
  double z = 1e9;
  internal::for_each_plane_point(model, data, Eigen::Vector3d::UnitZ(),
                                 [&](int, const Geom&, int, const Eigen::Vector3d&, double height) { z = std::min(z, height); });
  return z;
}

// For each joint on the path to the root, column s = [ω; v] of S in that link's frame moves the
// point by R v + (R ω) × (p − o), so its entry is (Rᵀ f)·v + (Rᵀ((p − o) × f))·ω.
void internal::add_point_force(const CharacterModel& model, const CharacterData& data, int link, const Eigen::Vector3d& point,
                               const Eigen::Vector3d& force, Eigen::Ref<Eigen::VectorXd> tau) {
  const auto& links = model.links();
  for (int k = link; k >= 0; k = links[k].parent) {
    const LinkData& d = data.links[k];
    const Eigen::Vector3d lin = d.R.transpose() * force, ang = d.R.transpose() * (point - d.p).cross(force);
    for (int j = 0; j < links[k].nv; ++j)
      tau(links[k].v_index + j) += d.S.col(j).head<3>().dot(ang) + d.S.col(j).tail<3>().dot(lin);
  }
}

void internal::for_each_plane_point(const CharacterModel& model, const CharacterData& data, const Eigen::Vector3d& normal,
                                    const std::function<void(int, const Geom&, int, const Eigen::Vector3d&, double)>& visit) {
  int k = 0;
  const auto& links = model.links();
  for (std::size_t i = 0; i < links.size(); ++i) {
    const LinkData& d = data.links[i];
    const int link = static_cast<int>(i);
    for (const Geom& g : links[i].geoms) {
      const Eigen::Vector3d c = d.p + d.R * g.pos;
      const Eigen::Matrix3d R = d.R * g.rot.toRotationMatrix();
      auto rounded = [&](const Eigen::Vector3d& centre, double radius) {
        visit(link, g, k++, centre - radius * normal, normal.dot(centre) - radius);
      };
      switch (g.type) {
        case ShapeType::sphere:
          rounded(c, g.radius);
          break;
        case ShapeType::capsule:
          rounded(c + g.half_length * R.col(2), g.radius);
          rounded(c - g.half_length * R.col(2), g.radius);
          break;
        case ShapeType::box:
          for (int corner = 0; corner < 8; ++corner) {
            const Eigen::Vector3d s((corner & 1) ? 1 : -1, (corner & 2) ? 1 : -1, (corner & 4) ? 1 : -1);
            rounded(c + R * s.cwiseProduct(g.half_extents), 0.0);
          }
          break;
      }
    }
  }
}

}  // namespace podium::sim
