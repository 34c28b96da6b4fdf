#include "contact_solver.h"

#include <BulletCollision/BroadphaseCollision/btDispatcher.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <limits>

#include "internal.h"

namespace podium::sim {

namespace {
// Bullet regenerates manifold points every step; a new point takes the impulses of the last
// step's point of the same pair nearest to it within this distance (Bullet's own contact
// breaking threshold, which it uses to match persistent points).
constexpr double kWarmMatchM = 0.02;
}  // namespace

ContactSolver::ContactSolver(const CharacterModel& model, const btMultiBody& body, const Terrain& terrain,
                             const ContactSolverConfig& config)
    : model_(model), body_(body), terrain_(terrain), config_(config) {
  int points = 0;
  internal::for_each_plane_point(model, CharacterData(model), Eigen::Vector3d::UnitZ(),
                                 [&](int, const Geom&, int, const Eigen::Vector3d&, double) { ++points; });
  warm_.ground.assign(points, {0.0, 0.0, 0.0});
  warm_.limits.assign(2 * model.nv(), 0.0);
  warm_.locks.assign(model.nv(), 0.0);
  ground_included_.assign(points, 0);
}

void ContactSolver::step(CharacterData& data, double dt_s, btDispatcher* dispatcher, const Eigen::VectorXd* tau_external,
                         const Eigen::VectorXd* implicit) {
  data_ = &data;
  dt_ = dt_s;
  internal::mass_matrix_posed(model_, data);
  if (implicit) {
    data.M.diagonal() += *implicit;  // factored with the PD's implicit part, then M restored
    data.llt.compute(data.M);
    data.M.diagonal() -= *implicit;
  } else {
    data.llt.compute(data.M);
  }
  internal::bias_forces_posed(model_, data);  // also the link velocities at the start
  data.qdd = data.tau - data.C;
  if (tau_external) data.qdd += *tau_external;
  data.llt.solveInPlace(data.qdd);
  // Root velocities in the frame of the step's start (what J and integrate() use): the COM
  // velocity integrates its classical acceleration, as Bullet integrates a base, so the origin's
  // velocity also gains ω × v + ω × (ω × c) over the spatial acceleration.
  const Eigen::Vector3d w = data.qd.head<3>(), v = data.qd.segment<3>(3), c = model_.links()[0].com;
  data.qd += dt_ * data.qdd;
  data.qd.segment<3>(3) += dt_ * (w.cross(v) + w.cross(w.cross(c)));
  internal::velocity_pass(model_, data);  // link velocities of the free motion (speculative test)
  rows_ = 0;
  target_.clear(), lo_.clear(), hi_.clear(), normal_of_.clear(), warm_ptr_.clear();
  std::fill(ground_included_.begin(), ground_included_.end(), 0);
  add_ground_contacts();
  add_manifold_contacts(dispatcher);
  add_limits();
  if (rows_ > 0) {
    qd_free_ = data.qd;
    solve_rows();
    // The impulses can drive a point that was neither touching nor approaching into the ground (a
    // foot whipped by the leg's impact): such points join, and the step is solved again from the
    // free velocities, warm-started with the impulses just found.
    const int before = rows_;
    internal::velocity_pass(model_, data);
    add_ground_contacts();
    if (rows_ > before) {
      data.qd = qd_free_;
      solve_rows();
    }
  }
  warm_.manifold.swap(found_);  // the impulses solve_rows wrote into found_
}

Eigen::Vector3d ContactSolver::point_velocity(int link, const Eigen::Vector3d& point) const {
  const LinkData& d = data_->links[link];
  return d.R * d.v.tail<3>() + (d.R * d.v.head<3>()).cross(point - d.p);
}

void ContactSolver::add_ground_contacts() {
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  internal::for_each_plane_point(model_, *data_, n, [&](int link, const Geom&, int k, const Eigen::Vector3d& p, double distance) {
    if (ground_included_[k]) return;
    auto& warm = warm_.ground[k];
    // Touching, or reaching the plane within this step at the current velocity (speculative);
    // inside a terrain region the plane is not there (the region's boxes are Bullet's).
    if ((distance > config_.touching_m && distance + dt_ * n.dot(point_velocity(link, p)) > config_.touching_m) ||
        terrain_.region_at(p.x(), p.y()) >= 0) {
      warm = {0.0, 0.0, 0.0};
      return;
    }
    ground_included_[k] = 1;
    add_contact(link, p, -1, p - distance * n, n, distance, config_.friction, {&warm[0], &warm[1], &warm[2]});
  });
}

void ContactSolver::add_manifold_contacts(btDispatcher* dispatcher) {
  auto link_of = [&](const btCollisionObject* obj) {
    const auto* col = btMultiBodyLinkCollider::upcast(obj);
    return col && col->m_multiBody == &body_ ? col->m_link + 1 : -1;
  };
  found_.clear();
  for (int m = 0; m < dispatcher->getNumManifolds(); ++m) {
    btPersistentManifold* mf = dispatcher->getManifoldByIndexInternal(m);
    const int a = link_of(mf->getBody0()), b = link_of(mf->getBody1());
    if (a < 0 && b < 0) continue;
    for (int p = 0; p < mf->getNumContacts(); ++p) {
      const btManifoldPoint& pt = mf->getContactPoint(p);
      if (pt.getDistance() > config_.touching_m) continue;
      ManifoldContact c;
      c.key = {mf->getBody0()->getUserIndex(), mf->getBody1()->getUserIndex(), pt.m_index0, pt.m_index1, p};
      c.link_a = a, c.link_b = b;
      c.point_a = to_eigen(pt.getPositionWorldOnA()), c.point_b = to_eigen(pt.getPositionWorldOnB());
      c.normal = to_eigen(pt.m_normalWorldOnB), c.local_a = to_eigen(pt.m_localPointA);
      c.distance = pt.getDistance(), c.friction = pt.m_combinedFriction;
      // Two of the character's own bodies: the model's self-contact μ if it sets one (MuJoCo's condim 1: none).
      if (a >= 0 && b >= 0 && model_.self_contact_friction()) c.friction = *model_.self_contact_friction();
      found_.push_back(c);
    }
  }
  // Canonical order (the dispatcher's depends on the collision world's history), then warm
  // starts from the last step's nearest point of the same pair.
  std::sort(found_.begin(), found_.end(), [](const ManifoldContact& x, const ManifoldContact& y) { return x.key < y.key; });
  const auto& last = warm_.manifold;
  std::size_t first = 0;
  for (ManifoldContact& c : found_) {
    auto same_pair = [&](const ManifoldContact& o) { return std::equal(o.key.begin(), o.key.begin() + 4, c.key.begin()); };
    auto before = [&](const ManifoldContact& o) {
      return std::lexicographical_compare(o.key.begin(), o.key.begin() + 4, c.key.begin(), c.key.begin() + 4);
    };
    while (first < last.size() && before(last[first])) ++first;
    double best = kWarmMatchM * kWarmMatchM;
    for (std::size_t k = first; k < last.size() && same_pair(last[k]); ++k) {
      const double d = (last[k].local_a - c.local_a).squaredNorm();
      if (d < best) best = d, c.warm = last[k].warm;
    }
  }
  for (ManifoldContact& c : found_)
    add_contact(c.link_a, c.point_a, c.link_b, c.point_b, c.normal, c.distance, c.friction, {&c.warm[0], &c.warm[1], &c.warm[2]});
}

void ContactSolver::add_limit_row(double gap, int v_index, const Eigen::Vector3d& row, int dofs, double& warm) {
  const double approach = row.head(dofs).dot(data_->qd.segment(v_index, dofs));
  if (gap > 0 && gap + dt_ * approach > 0) {  // inside, and not crossing within the step
    warm = 0.0;
    return;
  }
  const int r = add_row(gap > 0 ? -gap / dt_ : -config_.erp * gap / dt_, 0.0, std::numeric_limits<double>::infinity(), -1, &warm);
  jt_.col(r).segment(v_index, dofs) = row.head(dofs);
}

void ContactSolver::add_limits() {
  for (const Link& l : model_.links()) {
    if (l.locked) {
      add_locks(l);
      continue;
    }
    if (!config_.joint_limits) continue;
    if (l.joint == JointType::spherical) add_ball_limits(l);
    if (l.joint != JointType::revolute || !(l.lower < l.upper)) continue;
    const int k = l.v_index;
    const double q = data_->q(l.q_index);
    add_limit_row(q - l.lower, k, Eigen::Vector3d(1, 0, 0), 1, warm_.limits[2 * k]);
    add_limit_row(l.upper - q, k, Eigen::Vector3d(-1, 0, 0), 1, warm_.limits[2 * k + 1]);
  }
}

// Swing–twist split q = q_s q_t with q_t about the twist axis a (child frame): swing θ = ∠(a, R a)
// about n = a × R a / |·|, twist ψ. With ω the joint's child-frame rate, θ̇ = (R_tᵀ n)·ω and
// ψ̇ = (a + tan(θ/2) R_tᵀ(a × n))·ω (differentiating R = R_s R_t with R_s's axis n ⊥ a).
void ContactSolver::add_ball_limits(const Link& l) {
  const bool swing = l.swing_limit >= 0, twist = l.twist_lower < l.twist_upper;
  if (!swing && !twist) return;
  Eigen::Quaterniond q(data_->q(l.q_index), data_->q(l.q_index + 1), data_->q(l.q_index + 2), data_->q(l.q_index + 3));
  q.normalize();
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  const Eigen::Vector3d& a = l.axis;
  const Eigen::Vector3d b = q * a;
  const double theta = std::acos(std::clamp(a.dot(b), -1.0, 1.0));
  Eigen::Vector3d n = a.cross(b);
  n = n.norm() > 1e-12 ? Eigen::Vector3d(n.normalized()) : a.unitOrthogonal();
  const double psi = 2.0 * std::atan2(q.vec().dot(a), q.w());
  const Eigen::Matrix3d Rt_inv = Eigen::AngleAxisd(-psi, a).toRotationMatrix();
  double* warm = &warm_.limits[2 * l.v_index];
  if (swing) add_limit_row(l.swing_limit - theta, l.v_index, -(Rt_inv * n), 3, warm[0]);
  if (twist) {
    const Eigen::Vector3d rate = a + std::tan(0.5 * theta) * (Rt_inv * a.cross(n));
    add_limit_row(psi - l.twist_lower, l.v_index, rate, 3, warm[1]);
    add_limit_row(l.twist_upper - psi, l.v_index, -rate, 3, warm[2]);
  }
}

// A locked joint: bilateral rows driving its error to zero (Baumgarte), whatever the torques.
void ContactSolver::add_locks(const Link& l) {
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::Vector3d error = Eigen::Vector3d::Zero();
  if (l.joint == JointType::revolute) {
    error(0) = data_->q(l.q_index) - l.lock(0);
  } else {
    const Eigen::Quaterniond q(data_->q(l.q_index), data_->q(l.q_index + 1), data_->q(l.q_index + 2), data_->q(l.q_index + 3));
    const Eigen::Quaterniond target(l.lock(0), l.lock(1), l.lock(2), l.lock(3));
    const Eigen::AngleAxisd rel(target.conjugate() * q.normalized());  // child-frame error rotation, angle in [0, π]
    error = rel.angle() * rel.axis();
  }
  for (int k = 0; k < l.nv; ++k) {
    const int r = add_row(-config_.erp * error(k) / dt_, -inf, inf, -1, &warm_.locks[l.v_index + k]);
    jt_(l.v_index + k, r) = 1.0;
  }
}

void ContactSolver::add_contact(int link_a, const Eigen::Vector3d& point_a, int link_b, const Eigen::Vector3d& point_b,
                                const Eigen::Vector3d& normal, double distance, double friction,
                                const std::array<double*, 3>& warm) {
  const double inf = std::numeric_limits<double>::infinity();
  // Separated by `distance` > 0: the gap may close within the step, no more (speculative);
  // penetrating: push apart by erp of the depth per step (Baumgarte).
  const double target = distance > 0 ? -distance / dt_ : -config_.erp * distance / dt_;
  const Eigen::Vector3d t1 = normal.unitOrthogonal(), t2 = normal.cross(t1);
  const Eigen::Vector3d directions[3] = {normal, t1, t2};
  int normal_row = -1;
  for (int k = 0; k < 3; ++k) {
    const int r = k == 0 ? add_row(target, 0.0, inf, -1, warm[0]) : add_row(0.0, -friction, friction, normal_row, warm[k]);
    if (k == 0) normal_row = r;
    if (link_a >= 0) add_point_jacobian(r, link_a, point_a, directions[k], 1.0);
    if (link_b >= 0) add_point_jacobian(r, link_b, point_b, directions[k], -1.0);
  }
}

int ContactSolver::add_row(double target, double lo, double hi, int normal_row, double* warm) {
  if (rows_ == jt_.cols()) {
    const int capacity = std::max(16, 2 * rows_);
    Eigen::MatrixXd grown = Eigen::MatrixXd::Zero(model_.nv(), capacity);
    grown.leftCols(rows_) = jt_.leftCols(rows_);
    jt_.swap(grown);
  }
  jt_.col(rows_).setZero();
  target_.push_back(target), lo_.push_back(lo), hi_.push_back(hi), normal_of_.push_back(normal_row), warm_ptr_.push_back(warm);
  return rows_++;
}

// Row += sign · ∂(direction · velocity of the world point fixed to `link`)/∂q̇.
void ContactSolver::add_point_jacobian(int row, int link, const Eigen::Vector3d& point, const Eigen::Vector3d& direction,
                                       double sign) {
  internal::add_point_force(model_, *data_, link, point, sign * direction, jt_.col(row));
}

// Projected Gauss–Seidel on A λ + J q̇ ≥ target (complementary with λ within its bounds), then
// q̇ += M⁻¹ Jᵀ λ. With M = L Lᵀ and Y = L⁻¹ Jᵀ: A = Yᵀ Y and M⁻¹ Jᵀ λ = L⁻ᵀ (Y λ).
void ContactSolver::solve_rows() {
  const int m = rows_;
  if (y_.cols() < jt_.cols()) {
    y_.resize(model_.nv(), jt_.cols());
    a_.resize(jt_.cols(), jt_.cols());
    lambda_.resize(jt_.cols());
    v_.resize(jt_.cols());
  }
  auto Y = y_.leftCols(m);
  auto A = a_.topLeftCorner(m, m);
  auto lambda = lambda_.head(m), v = v_.head(m);  // v: row velocities
  Y = jt_.leftCols(m);
  v.noalias() = Y.transpose() * data_->qd;
  data_->llt.matrixL().solveInPlace(Y);
  A.noalias() = Y.transpose() * Y;
  // Regularisation: a closed loop (a hand pressed on the torso with the elbow at its limit) makes
  // rows dependent, and Gauss–Seidel then lets the squeezing impulses grow without bound from
  // step to step (measured: 2.4e4 N·s within 20 steps of ragdoll seed 96). A relative 1e-3 on
  // the diagonal gives the problem one solution (max 93 N·s on that run).
  A.diagonal() *= 1.0 + config_.regularization;
  for (int r = 0; r < m; ++r) {  // warm start within this step's bounds
    const double scale = normal_of_[r] >= 0 ? lambda(normal_of_[r]) : 1.0;
    lambda(r) = std::clamp(*warm_ptr_[r], lo_[r] * scale, hi_[r] * scale);
  }
  v.noalias() += A * lambda;
  for (int sweep = 0; sweep < config_.iterations; ++sweep) {
    double largest = 0.0;
    for (int r = 0; r < m; ++r) {
      // A row no joint can move (its Jacobian is zero: the contact's distance is fixed by the
      // joints) takes no impulse; dividing by its zero diagonal would make the step NaN.
      if (A(r, r) <= 0.0) continue;
      const double scale = normal_of_[r] >= 0 ? lambda(normal_of_[r]) : 1.0;
      const double next = std::clamp(lambda(r) + (target_[r] - v(r)) / A(r, r), lo_[r] * scale, hi_[r] * scale);
      const double delta = next - lambda(r);
      if (delta == 0.0) continue;
      lambda(r) = next;
      v += A.col(r) * delta;
      largest = std::max(largest, std::abs(delta) * A(r, r));
    }
    if (largest < config_.tolerance) break;
  }
  for (int r = 0; r < m; ++r) *warm_ptr_[r] = lambda(r);
  du_.noalias() = Y * lambda;
  data_->llt.matrixU().solveInPlace(du_);
  data_->qd += du_;
}

}  // namespace podium::sim
