#pragma once
/// The mirror M of a pose and the mirror-symmetry reward (sprint seed §3.2 "Learn motion
/// symmetry": "the posture in odd and even steps is mirror-symmetrical"): r_mirror =
/// exp(−k‖q_t − M(q_{t−T_step})‖²), the pose against the mirrored pose one step earlier, aligned
/// at the counted touchdowns (steps.h).
///
/// M reflects the character in the vertical plane y = 0 (the lane's centre line, track.h): it
/// swaps every "left_*" joint with its "right_*" twin, negates the lateral components (a rotation
/// R becomes P R P with P = diag(1, −1, 1): quaternion (w, x, y, z) ↦ (w, −x, y, −z); a hinge angle
/// keeps or flips its sign as its axis mirrors onto its twin's; the root's y position flips).
/// Link frames are parallel at q = 0 (sim/model.h), so this is exact on any left/right-symmetric
/// model (humanoid34, athlete): M(M(q)) = q bit for bit.
#include <Eigen/Core>
#include <vector>

#include "podium/base/json.h"
#include "podium/sim/model.h"

namespace podium::tasks::sprint {

class Mirror {
 public:
  /// Throws base::UserError when a "left_"/"right_" joint has no twin or a hinge's axis does not
  /// mirror onto its twin's (±).
  explicit Mirror(const sim::CharacterModel& model);
  /// M(q) (nq).
  Eigen::VectorXd apply(const Eigen::VectorXd& q) const;
  /// ‖a − b‖²: the squared angles between the two poses' root orientations and joint rotations
  /// (spherical: the geodesic angle of a⁻¹b; hinge: the difference), rad². The root position is
  /// not part of it (the runner has moved on by a step).
  double distance2(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const;

 private:
  const sim::CharacterModel* model_;
  std::vector<int> twin_;     // per link
  std::vector<double> sign_;  // per hinge link: its angle's sign under M
};

/// The poses of the current and the previous step (between counted touchdowns), to compare a pose
/// with the one at the same phase one step earlier.
class StepAlignedPoses {
 public:
  /// Starts an episode: nothing recorded, no touchdown yet (poses before the first are dropped).
  void reset();
  /// A step was counted: the current step's poses become the previous step's.
  void touchdown();
  /// The previous step's pose at the phase the next recorded pose will have (its index since the
  /// touchdown; the previous step's last pose once past its length); nullptr before a full step.
  const Eigen::VectorXd* aligned_previous() const;
  /// Records the pose of this control step.
  void record(const Eigen::VectorXd& q) { current_.push_back(q); }
  /// The recorded poses, for env checkpoints, and back.
  base::Json state() const;
  void load_state(const base::Json& state);

 private:
  std::vector<Eigen::VectorXd> current_, previous_;
  bool started_ = false;
};

/// r_mirror = exp(−k‖q_t − M(q_prev)‖²), sprint seed §3.2.
double mirror_reward(const Mirror& mirror, const Eigen::VectorXd& q_t, const Eigen::VectorXd& q_prev, double k);

}  // namespace podium::tasks::sprint
