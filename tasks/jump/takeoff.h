#pragma once
/// Take-off states (thesis §3.4.1, §3.6.1): every jump episode starts at take-off — one-leg
/// support on the take-off foot at running speed — and Stage 1 explores a few features of that
/// state on top of a reference take-off state:
///   high jump x = (α, ω_x, ω_y, v_y): the approach angle α (turns the suite, jump_suite.h), the
///     root angular velocity about the forward (x) and lateral (y) axes, and the lateral speed
///     towards the left (the inside of the curve); ω_z (vertical) is fixed at 3 rad/s, a left turn
///     (§3.6.1, from the curved sprint);
///   obstacle x = (ω_x, ω_y, ω_z), the root angular velocity.
/// Axes are ours: z up, the take-off state faces +x, y to its left. The thesis's y-up frame has
/// (ω_x, ω_y, ω_z)_thesis = (ω_x, ω_z, −ω_y)_ours, so Table 3.3's ω_z is our −ω_y and its v_z
/// (negative: towards the bar side) is our −v_y. The thesis calls v_z "the Z component of the
/// root linear velocity": in its frame that is the lateral component, not the vertical one.
#include <Eigen/Core>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "jump_schedules.h"
#include "podium/character/motion.h"
#include "podium/character/starts.h"

namespace podium::tasks::jump {

struct TakeoffState {
  Eigen::VectorXd q;  ///< nq; root over the take-off point (x = y = 0), facing +x, foot on the ground
  Eigen::Vector3d root_omega = Eigen::Vector3d::Zero();     ///< world, rad/s
  Eigen::Vector3d root_velocity = Eigen::Vector3d::Zero();  ///< of the root origin, world, m/s
  Eigen::VectorXd joint_qd;                                 ///< nv − 6, sim's convention
  /// sim's q̇ (root ω and v in the root frame, then joint_qd).
  Eigen::VectorXd qd() const;
};

/// The project's own reference take-off state (tasks/jump/data/takeoff_run.json; a right-foot
/// take-off at 6 m/s, authored for this project).
std::filesystem::path shipped_takeoff_path();
/// Reads a take-off state file: {"joints": {name: angle | rotation vector (z-up, the joint's
/// frame)}, "root_rotation": rotation vector, "root_velocity", "root_angular_velocity" (world),
/// "joint_velocities": {name: rate | ω}} — joints not named stay at zero — and places it
/// (placed_at_takeoff). Errors name the file and the key.
TakeoffState read_takeoff_json(const sim::ModelPtr& model, const std::filesystem::path& path, int takeoff_foot);
/// A captured run-up's end state as arpspoof/Jump stores it (data/states/*.npy): two .npy float64
/// arrays in one file, the DeepMimic pose (root position, root quaternion, per joint a quaternion
/// or an angle; y-up) and velocity (root v, root ω + 1 pad, per ball joint ω + 1 pad, per hinge a
/// rate). Needs a model in DeepMimic's joint order (humanoid34, the athlete). Placed.
TakeoffState read_takeoff_npy(const sim::ModelPtr& model, const std::filesystem::path& path, int takeoff_foot);
/// The take-off frame of a captured motion (a jump, or a run that ends in one): the last frame
/// before the root's highest at which `takeoff_foot` is within 3 cm of the motion's lowest point
/// before that frame and every other body at least 3 cm above it (one-leg support). The one rule
/// for Stage 1's take-off from a clip and the run-up's hand-over (runup_rewards.h). Throws
/// base::UserError when no frame is.
std::size_t takeoff_frame(const sim::CharacterModel& model, std::span<const Eigen::VectorXd> poses, int takeoff_foot);
/// The take-off state of a captured jump or run (arpspoof/Jump data/motions/beyond/*.txt, read with
/// character::read_deepmimic_clip) at its takeoff_frame; velocities by the clip's differences.
/// Placed.
TakeoffState takeoff_from_clip(const character::Clip& clip, int takeoff_foot);
/// Turns the state about the vertical so the root faces +x, moves the root over the origin, and
/// lifts it so the take-off foot's lowest point is on the ground (z = 0). Throws base::UserError
/// naming another body that would then be within 5 mm of the ground or below it.
TakeoffState placed_at_takeoff(const sim::CharacterModel& model, TakeoffState state, int takeoff_foot);

/// One explored feature: name, unit and the range Stage 1 searches (documented defaults: α covers
/// Table 3.3's −0.05…2.09 rad with margin; angular velocities ±3 rad/s for the high jump as Table
/// 3.3's ω_x ∈ [−3, 1], ±4 rad/s for the obstacle as Table 3.4's up to 3.89; |v_y| up to 2.5 m/s
/// as Table 3.3's 0.5…2.4).
struct TakeoffFeature {
  std::string name, unit;
  double low = 0.0, high = 0.0;
};
std::vector<TakeoffFeature> takeoff_features(JumpKind kind);
/// The fixed vertical root angular velocity of the high jump (§3.6.1: 3 rad/s).
constexpr double kHighJumpTurnRate = 3.0;

/// The reference state with the features x applied (sizes: takeoff_features(kind)): root angular
/// velocity replaced, and for the high jump the lateral velocity too. Throws base::UserError for a
/// wrong size.
TakeoffState apply_takeoff_features(JumpKind kind, const TakeoffState& reference, std::span<const double> x);
/// The approach angle α the features ask for (high jump: x[0]); `fallback` for the obstacle jump.
double approach_angle(JumpKind kind, std::span<const double> x, double fallback);

/// The episode's start: World::reset at the take-off state.
class TakeoffStart : public character::Start {
 public:
  explicit TakeoffStart(TakeoffState state) : state_(std::move(state)), qd_(state_.qd()) {}
  void begin(character::CharacterEnv& env, base::Rng& rng) const override;
  const TakeoffState& state() const { return state_; }

 private:
  TakeoffState state_;
  Eigen::VectorXd qd_;
};

}  // namespace podium::tasks::jump
