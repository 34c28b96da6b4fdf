// Stable PD (thesis ch. 2) two ways: dense factorisation (eq. 2.7) and MABA, the modified
// articulated-body algorithm (eqs. 2.17–2.29), plus plain explicit PD. Both SPD solvers share the
// spring-damper term Q (eq. 2.20) so they differ only in how they solve for q̈.
#include <cmath>

#include "internal.h"
#include "podium/sim/dynamics.h"
#include "spatial.h"

namespace podium::sim {

namespace {

// Rotation vector of q̄⁻¹ q: the spherical joint's "q − q̄" in the child frame. Written out
// (2 atan2(|v|, w) v/|v| on the shortest arc) instead of through Eigen::AngleAxis, whose
// conversion cost humanoid34's SPD about 12% (callgrind).
Eigen::Vector3d rotation_error(const Eigen::VectorXd& q, const Eigen::VectorXd& target, int i) {
  const Eigen::Quaterniond cur(q(i), q(i + 1), q(i + 2), q(i + 3));
  const Eigen::Quaterniond tgt(target(i), target(i + 1), target(i + 2), target(i + 3));
  Eigen::Quaterniond d = tgt.normalized().conjugate() * cur.normalized();
  if (d.w() < 0) d.coeffs() = -d.coeffs();  // shortest arc
  const double s = d.vec().norm();
  // sin(θ/2) = s: below 1e-12 the angle's series 2 s / w is exact to round-off.
  return (s < 1e-12 ? 2.0 / d.w() : 2.0 * std::atan2(s, d.w()) / s) * d.vec();
}

}  // namespace

void internal::spd_spring_term(const CharacterModel& model, CharacterData& data, const Gains& gains,
                               const Eigen::VectorXd& target, double dt_s) {
  for (const Link& l : model.links()) {
    if (l.joint == JointType::free) {
      // Optional "hand-of-God" root servo (thesis §2.4.1): errors and velocity in the root frame.
      if (gains.kp.head<6>().isZero() && gains.kd.head<6>().isZero()) {  // no servo (the default)
        data.Q.head<6>().setZero();
        continue;
      }
      const Eigen::Vector3d w = data.qd.head<3>(), v = data.qd.segment<3>(3);
      const Eigen::Matrix3d R = Eigen::Quaterniond(data.q(3), data.q(4), data.q(5), data.q(6)).normalized().toRotationMatrix();
      const Eigen::Vector3d e_pos = R.transpose() * (data.q.head<3>() - target.head<3>());
      data.Q.head<3>() =
          -gains.kp.head<3>().cwiseProduct(rotation_error(data.q, target, 3) + dt_s * w) - gains.kd.head<3>().cwiseProduct(w);
      data.Q.segment<3>(3) = -gains.kp.segment<3>(3).cwiseProduct(e_pos + dt_s * v) - gains.kd.segment<3>(3).cwiseProduct(v);
    } else if (l.joint == JointType::revolute) {
      const double qd = data.qd(l.v_index);
      // thesis eq. 2.20: Q = −Kp(q + Δt q̇ − q̄) − Kd q̇
      data.Q(l.v_index) = -gains.kp(l.v_index) * (data.q(l.q_index) + dt_s * qd - target(l.q_index)) - gains.kd(l.v_index) * qd;
    } else {
      const Eigen::Vector3d w = data.qd.segment<3>(l.v_index);
      data.Q.segment<3>(l.v_index) =
          -gains.kp.segment<3>(l.v_index).cwiseProduct(rotation_error(data.q, target, l.q_index) + dt_s * w) -
          gains.kd.segment<3>(l.v_index).cwiseProduct(w);
    }
  }
}

namespace {

// MABA in world coordinates (spatial vectors at the world origin; the recursions of eqs.
// 2.17–2.29 hold in any single frame): every link's inertia is expressed in world once, as a
// rigid body (cheap), and articulated inertias then add into their parents without the per-link 6×6
// congruence transform that dominated the link-coordinate version (measured on humanoid21, best of
// 7 × 20000 calls: 4.7 µs in link coordinates, 3.9–4.3 µs in world coordinates).

// L⁻¹ for the Cholesky factor L of a symmetric positive-definite N×N block (D = L Lᵀ, so
// D⁻¹ = L⁻ᵀ L⁻¹), in plain loops the compiler unrolls. Eigen's fixed-size inverse beyond 4×4 runs a
// pivoted LU with blocked triangular solves: the root's 6×6 block cost 15% of humanoid21's MABA
// that way (callgrind instruction count).
template <int N>
Eigen::Matrix<double, N, N> inverse_cholesky_factor(const Eigen::Matrix<double, N, N>& D) {
  // L column by column, then L⁻¹ by forward substitution; one division per column (the diagonal's
  // reciprocal, which is also L⁻¹'s diagonal), since divisions are slow and serial.
  Eigen::Matrix<double, N, N> L = Eigen::Matrix<double, N, N>::Zero(), Linv = L;
  for (int j = 0; j < N; ++j) {
    double djj = D(j, j);
    for (int k = 0; k < j; ++k) djj -= L(j, k) * L(j, k);
    L(j, j) = std::sqrt(djj);
    Linv(j, j) = 1.0 / L(j, j);
    for (int i = j + 1; i < N; ++i) {
      double dij = D(i, j);
      for (int k = 0; k < j; ++k) dij -= L(i, k) * L(j, k);
      L(i, j) = dij * Linv(j, j);
    }
  }
  for (int j = 0; j < N; ++j)
    for (int i = j + 1; i < N; ++i) {
      double sum = 0.0;
      for (int k = j; k < i; ++k) sum -= L(i, k) * Linv(k, j);
      Linv(i, j) = sum * Linv(i, i);
    }
  return Linv;
}

template <int N>
void maba_pass1(const Link& l, CharacterData& data, LinkData& d) {
  Vector6d vj;
  if constexpr (N == 6) {
    // The free root (ω and v in its own frame): vj = S q̇ = [R ω; p × R ω + R v] without forming S.
    const Eigen::Vector3d w = d.R * data.qd.template head<3>();
    vj << w, d.p.cross(w) + d.R * data.qd.template segment<3>(3);
  } else {
    // Hinge and ball joints sit at the link origin (S = [axes; 0] in the link frame), so the world
    // subspace is [R·axes; p × R·axes].
    Eigen::Matrix<double, 6, N> S;
    for (int j = 0; j < N; ++j) {
      const Eigen::Vector3d w = d.R * d.S.col(j).template head<3>();
      S.col(j) << w, d.p.cross(w);
    }
    d.S_world.template leftCols<N>() = S;
    vj = S * data.qd.template segment<N>(l.v_index);
  }
  d.v_world = l.parent < 0 ? vj : Vector6d(data.links[l.parent].v_world + vj);
  d.c_world = spatial::cross_motion(d.v_world, vj);
  const Eigen::Vector3d com = d.p + d.R * l.com;
  Eigen::Matrix3d I_com = d.inertia_mid * Eigen::Matrix3d::Identity();
  for (int k = 0; k < d.inertia_axes; ++k) {
    const Eigen::Vector3d e = d.R * d.inertia_axis.col(k);
    I_com += (d.inertia_weight(k) * e) * e.transpose();
  }
  spatial::inertia(l.mass, com, I_com, d.I);
  // p = v ×* (I v) from the momentum, without the 6×6 product: h = m (v_O + ω × c), L_O = I_c ω + c × h.
  const Eigen::Vector3d w = d.v_world.head<3>();
  const Eigen::Vector3d h = l.mass * (d.v_world.tail<3>() + w.cross(com));
  Vector6d momentum;
  momentum << I_com * w + com.cross(h), h;
  d.f = spatial::cross_force(d.v_world, momentum);
}

template <int N>
void maba_pass2(const Link& l, CharacterData& data, const Gains& gains, double dt_s, LinkData& d) {
  using MatS = Eigen::Matrix<double, 6, N>;
  using MatD = Eigen::Matrix<double, N, N>;
  if constexpr (N == 6) {  // the damped root: S = [R 0; p×R R] (world from root coordinates)
    d.S_world << d.R, Eigen::Matrix3d::Zero(), spatial::cross_columns(d.p, d.R), d.R;
  }
  const MatS S = d.S_world.template leftCols<N>();
  const MatS U = d.I * S;
  MatD D = S.transpose() * U;
  D.diagonal() +=
      gains.kd.template segment<N>(l.v_index) * dt_s;      // thesis eq. 2.19: K_i = Kd,i Δt (the root's: its servo damper)
  if (l.armature > 0) D.diagonal().array() += l.armature;  // as CRBA's M (MuJoCo's joint armature)
  const MatD L_inv = inverse_cholesky_factor<N>(D);
  const MatD D_inv = L_inv.transpose() * L_inv;
  const Eigen::Matrix<double, N, 1> u = data.Q.template segment<N>(l.v_index) - S.transpose() * d.f;
  d.U.template leftCols<N>() = U;
  d.D_inv.template topLeftCorner<N, N>() = D_inv;
  d.u.template head<N>() = u;
  if (l.parent < 0) return;
  // thesis eqs. 2.24–2.29: I^a = I^A − U D⁻¹ Uᵀ and p^a = p^A + I^a c + U D⁻¹ (Q − Sᵀ p^A), added
  // to the parent (same coordinates: no transform). U D⁻¹ Uᵀ = V Vᵀ with V = U L⁻ᵀ is exactly
  // symmetric in floating point (each entry's products and sums commute), so I^A stays symmetric
  // without a symmetrising pass (asymmetric round-off grows geometrically along long chains:
  // 1e2 relative error at 195 DoF).
  const MatS V = U * L_inv.transpose();
  LinkData& p = data.links[l.parent];
  p.I += d.I - V * V.transpose();
  p.f += d.f + d.I * d.c_world + U * (D_inv * (u - U.transpose() * d.c_world));
}

// The fictitious upward acceleration −g that accounts for gravity, in world coordinates (the root's
// a_in in MABA's frame).
Vector6d world_gravity_accel(const CharacterData& data) {
  Vector6d a = Vector6d::Zero();
  a.tail<3>() = -data.gravity;
  return a;
}

template <int N>
void maba_pass3(const Link& l, CharacterData& data, const Gains& gains, double dt_s, LinkData& d) {
  const Vector6d a_in = l.parent < 0 ? world_gravity_accel(data) : Vector6d(data.links[l.parent].a + d.c_world);
  const Eigen::Matrix<double, 6, N> U = d.U.template leftCols<N>(), S = d.S_world.template leftCols<N>();
  const Eigen::Matrix<double, N, N> D_inv = d.D_inv.template topLeftCorner<N, N>();
  const Eigen::Matrix<double, N, 1> u = d.u.template head<N>();
  const Eigen::Matrix<double, N, 1> qdd = D_inv * (u - U.transpose() * a_in);
  data.qdd.template segment<N>(l.v_index) = qdd;
  d.a = a_in + S * qdd;
  // thesis eq. 2.17: τ_i = Q_i − Kd,i Δt q̈_i
  data.tau.template segment<N>(l.v_index) =
      data.Q.template segment<N>(l.v_index) - (gains.kd.template segment<N>(l.v_index) * dt_s).cwiseProduct(qdd);
}

// The free root without servo damping (K = 0, the default): its S (world) is invertible, so eq.
// 2.18 for the root reduces to a = (I^A)⁻¹(S⁻ᵀQ − p^A) in world coordinates and q̈ = S⁻¹(a − a_in),
// one 6×6 Cholesky instead of forming Sᵀ I^A S (the generic block measured 12% of humanoid21's
// MABA time, perf). S = [R 0; p×R R] maps root to world coordinates: S⁻¹ is spatial::motion and
// S⁻ᵀ spatial::force_to_parent with E = Rᵀ, r = p.
void maba_root_undamped(CharacterData& data, LinkData& d) {
  const Eigen::Matrix3d E = d.R.transpose();
  const Vector6d f = spatial::force_to_parent(E, d.p, data.Q.head<6>()) - d.f;
  const Matrix6d L_inv = inverse_cholesky_factor<6>(d.I);
  d.a = L_inv.transpose() * (L_inv * f);
  data.qdd.head<6>() = spatial::motion(E, d.p, d.a - world_gravity_accel(data));
  data.tau.head<6>() = data.Q.head<6>();
}

}  // namespace

void stable_pd_dense(const CharacterModel& model, CharacterData& data, const Gains& gains, const Eigen::VectorXd& target,
                     double dt_s) {
  mass_matrix(model, data);
  bias_forces(model, data);
  internal::spd_spring_term(model, data, gains, target, dt_s);
  // thesis eq. 2.7: (M + Kd Δt) q̈ = −C − Kp(q + Δt q̇ − q̄) − Kd q̇
  data.M.diagonal() += gains.kd * dt_s;
  data.llt.compute(data.M);
  data.M.diagonal() -= gains.kd * dt_s;
  data.qdd = data.Q - data.C;
  data.llt.solveInPlace(data.qdd);
  // thesis eq. 2.6 (root rows have Q = 0 and Kd = 0, so τ_root = 0)
  data.tau = data.Q - (gains.kd * dt_s).cwiseProduct(data.qdd);
}

void stable_pd_maba(const CharacterModel& model, CharacterData& data, const Gains& gains, const Eigen::VectorXd& target,
                    double dt_s) {
  forward_kinematics(model, data);
  internal::stable_pd_maba_posed(model, data, gains, target, dt_s);
}

void internal::stable_pd_maba_posed(const CharacterModel& model, CharacterData& data, const Gains& gains,
                                    const Eigen::VectorXd& target, double dt_s) {
  internal::spd_spring_term(model, data, gains, target, dt_s);
  const auto& links = model.links();
  const int n = static_cast<int>(links.size());
  // Pass 1 (root → leaves): motion subspaces, velocities v_i = v_parent + S_i q̇_i, velocity
  // products c_i = v_i × S_i q̇_i, rigid-body inertias and bias forces p_i = v_i ×* I_i v_i, all
  // in world coordinates.
  for (int i = 0; i < n; ++i) {
    switch (links[i].nv) {
      case 1:
        maba_pass1<1>(links[i], data, data.links[i]);
        break;
      case 3:
        maba_pass1<3>(links[i], data, data.links[i]);
        break;
      default:
        maba_pass1<6>(links[i], data, data.links[i]);
        break;
    }
  }
  // Pass 2 (leaves → root): articulated inertias and bias forces with the SPD term, with
  // fixed-size blocks per joint type (N = 1, 3, 6 DoF) so Eigen unrolls them.
  const bool root_undamped = gains.kd.head<6>().isZero();
  for (int i = n - 1; i >= 0; --i) {
    switch (links[i].nv) {
      case 1:
        maba_pass2<1>(links[i], data, gains, dt_s, data.links[i]);
        break;
      case 3:
        maba_pass2<3>(links[i], data, gains, dt_s, data.links[i]);
        break;
      default:
        if (!root_undamped) maba_pass2<6>(links[i], data, gains, dt_s, data.links[i]);
        break;
    }
  }
  // Pass 3 (root → leaves): thesis eq. 2.18 for q̈_i, eq. 2.13 for a_i.
  for (int i = 0; i < n; ++i) {
    switch (links[i].nv) {
      case 1:
        maba_pass3<1>(links[i], data, gains, dt_s, data.links[i]);
        break;
      case 3:
        maba_pass3<3>(links[i], data, gains, dt_s, data.links[i]);
        break;
      default:
        if (root_undamped) maba_root_undamped(data, data.links[i]);
        else maba_pass3<6>(links[i], data, gains, dt_s, data.links[i]);
        break;
    }
  }
}

void pd_torques(const CharacterModel& model, CharacterData& data, const Gains& gains, const Eigen::VectorXd& target) {
  internal::spd_spring_term(model, data, gains, target, 0.0);
  data.tau = data.Q;
}

Gains Gains::from_model(const CharacterModel& model) { return Gains{model.kp(), model.kd()}; }

}  // namespace podium::sim
