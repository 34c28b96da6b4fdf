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

ContactSolver::ContactSolver(const CharacterModel& model, const btMultiBody& body, const ContactSolverConfig& config)
    : model_(model), body_(body), config_(config), limit_warm_(2 * model.nv(), 0.0) {
  int points = 0;
  internal::for_each_plane_point(model, CharacterData(model), config_.ground_normal, [&](int, const Geom&, int, const Eigen::Vector3d&, double) { ++points; });
  ground_warm_.assign(points, {0.0, 0.0, 0.0});
  ground_included_.assign(points, 0);
}

void ContactSolver::step(CharacterData& data, double dt_s, btDispatcher* dispatcher) {
  data_ = &data;
  dt_ = dt_s;
  internal::mass_matrix_posed(model_, data);
  data.llt.compute(data.M);
  internal::bias_forces_posed(model_, data);  // also the link velocities at the start
  data.qdd = data.tau - data.C;
  data.llt.solveInPlace(data.qdd);
  // Root velocities in the frame of the step's start (what J and integrate() use): the COM
  // velocity integrates its classical acceleration, as Bullet integrates a base, so the origin's
  // velocity also gains ω × v + ω × (ω × c) over the spatial acceleration.
  const Eigen::Vector3d w = data.qd.head<3>(), v = data.qd.segment<3>(3), c = model_.links()[0].com;
  data.qd += dt_ * data.qdd;
  data.qd.segment<3>(3) += dt_ * (w.cross(v) + w.cross(w.cross(c)));
  internal::velocity_pass(model_, data);  // link velocities of the free motion (speculative test)
  rows_ = 0;
  target_.clear(), lo_.clear(), hi_.clear(), normal_of_.clear(), warm_.clear();
  std::fill(ground_included_.begin(), ground_included_.end(), 0);
  add_ground_contacts();
  add_manifold_contacts(dispatcher);
  if (config_.joint_limits) add_limits();
  if (rows_ == 0) return;
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

Eigen::Vector3d ContactSolver::point_velocity(int link, const Eigen::Vector3d& point) const {
  const LinkData& d = data_->links[link];
  return d.R * d.v.tail<3>() + (d.R * d.v.head<3>()).cross(point - d.p);
}

void ContactSolver::add_ground_contacts() {
  const Eigen::Vector3d& n = config_.ground_normal;
  internal::for_each_plane_point(model_, *data_, n, [&](int link, const Geom&, int k, const Eigen::Vector3d& p, double distance) {
    if (ground_included_[k]) return;
    auto& warm = ground_warm_[k];
    // Touching, or reaching the plane within this step at the current velocity (speculative).
    if (distance > config_.touching_m && distance + dt_ * n.dot(point_velocity(link, p)) > config_.touching_m) {
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
  for (int m = 0; m < dispatcher->getNumManifolds(); ++m) {
    btPersistentManifold* mf = dispatcher->getManifoldByIndexInternal(m);
    const int a = link_of(mf->getBody0()), b = link_of(mf->getBody1());
    if (a < 0 && b < 0) continue;
    for (int p = 0; p < mf->getNumContacts(); ++p) {
      btManifoldPoint& pt = mf->getContactPoint(p);
      if (pt.getDistance() > config_.touching_m) continue;
      add_contact(a, to_eigen(pt.getPositionWorldOnA()), b, to_eigen(pt.getPositionWorldOnB()), to_eigen(pt.m_normalWorldOnB), pt.getDistance(),
                  pt.m_combinedFriction, {&pt.m_appliedImpulse, &pt.m_appliedImpulseLateral1, &pt.m_appliedImpulseLateral2});
    }
  }
}

void ContactSolver::add_limits() {
  const auto& links = model_.links();
  const double inf = std::numeric_limits<double>::infinity();
  for (const Link& l : links) {
    if (l.joint != JointType::revolute || !(l.lower < l.upper)) continue;
    const int k = l.v_index;
    const double q = data_->q(l.q_index), u = data_->qd(k);
    // gap ≥ 0 inside the range; a row when the gap is violated or would close within the step.
    const double gaps[2] = {q - l.lower, l.upper - q}, signs[2] = {1.0, -1.0};
    for (int side = 0; side < 2; ++side) {
      double& warm = limit_warm_[2 * k + side];
      const double gap = gaps[side], approach = signs[side] * u;
      if (gap > 0 && gap + dt_ * approach > 0) {
        warm = 0.0;
        continue;
      }
      const int r = add_row(gap > 0 ? -gap / dt_ : -config_.erp * gap / dt_, 0.0, inf, -1, &warm);
      jt_(k, r) = signs[side];
    }
  }
}

void ContactSolver::add_contact(int link_a, const Eigen::Vector3d& point_a, int link_b, const Eigen::Vector3d& point_b, const Eigen::Vector3d& normal,
                                double distance, double friction, const std::array<double*, 3>& warm) {
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
  target_.push_back(target), lo_.push_back(lo), hi_.push_back(hi), normal_of_.push_back(normal_row), warm_.push_back(warm);
  return rows_++;
}

// Row += sign · ∂(direction · velocity of the world point fixed to `link`)/∂q̇: for each joint on
// the path to the root, column s = [ω; v] of S in that link's frame moves the point by
// R v + (R ω) × (p − o), so its entry is (Rᵀ direction)·v + (Rᵀ((p − o) × direction))·ω.
void ContactSolver::add_point_jacobian(int row, int link, const Eigen::Vector3d& point, const Eigen::Vector3d& direction, double sign) {
  const auto& links = model_.links();
  for (int k = link; k >= 0; k = links[k].parent) {
    const LinkData& d = data_->links[k];
    const Eigen::Vector3d lin = d.R.transpose() * direction, ang = d.R.transpose() * (point - d.p).cross(direction);
    for (int j = 0; j < links[k].nv; ++j)
      jt_(links[k].v_index + j, row) += sign * (d.S.col(j).head<3>().dot(ang) + d.S.col(j).tail<3>().dot(lin));
  }
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
    lambda(r) = std::clamp(*warm_[r], lo_[r] * scale, hi_[r] * scale);
  }
  v.noalias() += A * lambda;
  for (int sweep = 0; sweep < config_.iterations; ++sweep) {
    double largest = 0.0;
    for (int r = 0; r < m; ++r) {
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
  for (int r = 0; r < m; ++r) *warm_[r] = lambda(r);
  du_.noalias() = Y * lambda;
  data_->llt.matrixU().solveInPlace(du_);
  data_->qd += du_;
}

}  // namespace podium::sim
