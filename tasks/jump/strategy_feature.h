#pragma once
/// The jumps' strategy feature (thesis §3.6.1 "Strategy Features"): the root orientation when the
/// centre of mass lies in the bar's vertical plane (the obstacle's centre plane).
///   Stage 1 (1-D): the angle between the root's forward axis (+x of the root body; the model
///     faces +x) and the global up vector, in [0, π] — 0 clears the bar facing up (a flop), π
///     facing down (a straddle), π/2 upright (a scissor kick);
///   Stage 2 (3-D): the root orientation in the bar frame (jump_suite.h: x over the bar, z up) as a
///     rotation vector (axis·angle, angle in [0, π]; it jumps across the sphere of radius π, where
///     nearby orientations can lie far apart).
/// Observed after every control step; at the step whose COM passes the plane (from the take-off
/// side), the root orientation is slerped to the fraction of the step at which it crossed. An
/// episode that never crosses reads the state of its closest approach (as the authors'
/// repository does), and crossed() says so.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>

#include "jump_suite.h"
#include "podium/base/json.h"

namespace podium::tasks::jump {

/// Stage 1's strategy threshold: up-angles 0.5 rad apart are other strategies. Facing up (a flop,
/// ≈ 0), side-on (a scissor, π/2) and facing down (a straddle, π) lie ≥ π/2 apart; 0.5 rad (29°)
/// splits them with room for the spread of one technique over retrained policies, and [0, π]
/// holds about six such cells — the thesis's six strategies in ten samples.
inline constexpr double kUpAngleStrategyThresholdRad = 0.5;

/// Stage 1's feature of a root orientation: the angle (rad) between its forward axis and up.
double up_angle(const Eigen::Quaterniond& root);

class CrossingRecorder {
 public:
  explicit CrossingRecorder(const JumpSuite& suite) : suite_(suite) {}
  /// Starts an episode.
  void reset();
  /// The state after a control step (and the take-off state): COM (world) and root orientation.
  void observe(const Eigen::Vector3d& com, const Eigen::Quaterniond& root);

  bool crossed() const { return crossed_; }
  /// The root orientation at the crossing (or closest approach); identity before any observation.
  const Eigen::Quaterniond& root_at_crossing() const { return root_; }
  /// Stage 1: the angle (rad) between the root's forward axis and up.
  double up_angle() const;
  /// Stage 2: the root orientation in the bar frame as a rotation vector.
  Eigen::Vector3d bar_frame_rotation() const;

  /// What it has seen, for env checkpoints (exact: doubles as JSON numbers round-trip).
  base::Json state() const;
  void load_state(const base::Json& state);

 private:
  JumpSuite suite_;
  bool seen_ = false, crossed_ = false;
  double last_distance_ = 0.0, closest_ = 0.0;
  Eigen::Quaterniond last_root_ = Eigen::Quaterniond::Identity(), root_ = Eigen::Quaterniond::Identity();
};

}  // namespace podium::tasks::jump
