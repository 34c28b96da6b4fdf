#pragma once
// The velocity update of one simulation step: free motion, then contacts and joint limits solved
// on the dense Delassus matrix. Bullet keeps collision detection; World integrates positions.
//
// Bullet's btMultiBodyConstraintSolver builds each contact row's response by its own O(n)
// articulated-body pass (calcAccelerationDeltasMultiDof): measured as 64% of a get-up-like step
// (sim/README.md, Benchmark B), and its world repeats the forward dynamics our SPD has just done.
// A humanoid has few DoF and few contacts, so this solver factors the joint-space inertia once per
// step (CRBA + Cholesky), takes the free acceleration M⁻¹(τ − C) from it (RNEA for C), forms
// A = J M⁻¹ Jᵀ for all rows at once and runs projected Gauss–Seidel on A (a few hundred flops per
// sweep), as MuJoCo does for small systems. Semi-implicit Euler as Bullet's: q̇ ← q̇ + Δt q̈ + M⁻¹Jᵀλ,
// then the caller integrates q with the new q̇. Hand-written: no packaged library solves
// multibody contact LCPs on our model.
//
// Rows per step: ground contacts generated here from the model's geoms against the plane z = 0
// outside the terrain's regions (speculative: a point joins when it touches or would reach the
// plane within the step, so fast impacts stop at the surface instead of sinking a step's travel
// deep); Bullet's manifold points for everything else (self-collision, props, region boxes) that
// touch; revolute limits, spherical swing cones and twist ranges that are violated or would be
// crossed within the step; locked joints (bilateral). Each contact has a normal row (λ ≥ 0) and
// two friction rows (|λ_t| ≤ μ λ_n, Bullet's friction pyramid), warm-started from the last step.
// Bullet's manifolds are emptied before every detection, so its points depend on the pose only;
// the manifold contacts' warm starts are kept here, in a canonical order (WarmStarts), which is
// what lets World::restore replay a rollout bitwise.
#include <BulletCollision/BroadphaseCollision/btDispatcher.h>

#include <Eigen/Core>
#include <array>
#include <vector>

#include "bullet_character.h"
#include "podium/sim/data.h"
#include "podium/sim/model.h"
#include "podium/sim/terrain.h"

namespace podium::sim {

// A manifold contact of one step: the pair's key (collision object user indices, child shape
// indices), where it sits on object A, and its three impulses (normal, two friction).
struct ManifoldContact {
  std::array<int, 5> key{};  // object A, object B, child A, child B, order within the manifold
  int link_a = -1, link_b = -1;
  Eigen::Vector3d point_a, point_b, normal, local_a;
  double distance = 0.0, friction = 0.0;
  std::array<double, 3> warm{};
};

// Everything the solver carries from one step to the next.
struct WarmStarts {
  std::vector<std::array<double, 3>> ground;  // per geom plane point
  std::vector<double> limits;                 // per DoF and side (spherical: swing, twist low/high on its 3 slots)
  std::vector<double> locks;                  // per DoF
  std::vector<ManifoldContact> manifold;      // sorted by key
};

struct ContactSolverConfig {
  double friction = 1.0;     // μ against the ground
  bool joint_limits = true;  // revolute angle limits
  double erp = 0.2;          // fraction of a penetration or limit violation removed per step
  double touching_m = 1e-3;  // contact points farther apart than this touch nothing
  // Gauss–Seidel sweeps (at most; Bullet's default 10) and the early stop: no row's velocity
  // moved by more than `tolerance` m/s in a sweep. With warm starts, 30 sweeps to 1e-9 changed
  // Benchmark B's deepest penetration by < 1 cm and cost 9% more per step.
  int iterations = 10;
  double tolerance = 1e-6;
  double regularization = 1e-3;  // relative addition to the Delassus diagonal (see solve_rows)
};

class ContactSolver {
 public:
  ContactSolver(const CharacterModel& model, const btMultiBody& body, const Terrain& terrain, const ContactSolverConfig& config);
  /// Advances data.qd by one step of dt_s under data.tau + tau_external (nv, or nullptr), gravity,
  /// the contacts in `dispatcher`'s manifolds (found at the current pose) and the joint limits.
  /// data must be posed (forward_kinematics at data.q); writes data.qdd (free acceleration), M,
  /// llt, C and link caches.
  /// `implicit` (nv, or nullptr): a diagonal added to M for the whole step (the free motion and the
  /// rows' responses), the implicit part of World's spd_implicit; data.M stays the model's.
  void step(CharacterData& data, double dt_s, btDispatcher* dispatcher, const Eigen::VectorXd* tau_external,
            const Eigen::VectorXd* implicit = nullptr);
  const WarmStarts& warm_starts() const { return warm_; }
  void set_warm_starts(const WarmStarts& warm) { warm_ = warm; }

 private:
  void add_ground_contacts();
  void add_manifold_contacts(btDispatcher* dispatcher);
  void add_limits();
  void add_ball_limits(const Link& l);
  void add_locks(const Link& l);
  // A one-sided limit row on a joint's DoFs: gap ≥ 0 inside the range, `row` its rate ∂gap/∂q̇.
  void add_limit_row(double gap, int v_index, const Eigen::Vector3d& row, int dofs, double& warm);
  // A contact's normal and two friction rows; links −1 are static; the normal points from b to a.
  void add_contact(int link_a, const Eigen::Vector3d& point_a, int link_b, const Eigen::Vector3d& point_b,
                   const Eigen::Vector3d& normal, double distance, double friction, const std::array<double*, 3>& warm);
  int add_row(double target, double lo, double hi, int normal_row, double* warm);
  void add_point_jacobian(int row, int link, const Eigen::Vector3d& point, const Eigen::Vector3d& direction, double sign);
  Eigen::Vector3d point_velocity(int link, const Eigen::Vector3d& point) const;
  void solve_rows();  // needs data_.llt of M; from the velocities in data_.qd

  const CharacterModel& model_;
  const btMultiBody& body_;
  const Terrain& terrain_;
  ContactSolverConfig config_;
  CharacterData* data_ = nullptr;  // the step's data: posed at the start, q̇ free, then final
  double dt_ = 0.0;

  // This step's rows: Jacobians as columns of jt_ (nv × capacity), the velocity each row must at
  // least reach, impulse bounds (a friction row's scale with its normal row's impulse: normal_of_),
  // and where each impulse persists for the next step's warm start.
  Eigen::MatrixXd jt_;
  Eigen::MatrixXd y_, a_;  // solve_rows' scratch, sized to jt_'s capacity
  Eigen::VectorXd lambda_, v_, du_;
  std::vector<double> target_, lo_, hi_;
  std::vector<int> normal_of_;
  std::vector<double*> warm_ptr_;
  int rows_ = 0;
  WarmStarts warm_;
  std::vector<ManifoldContact> found_;  // this step's manifold contacts; swapped into warm_.manifold
  std::vector<char> ground_included_;   // per geom point: has rows this step
  Eigen::VectorXd qd_free_;             // velocities before the contact impulses
};

}  // namespace podium::sim
