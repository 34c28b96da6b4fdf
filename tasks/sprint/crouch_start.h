#pragma once
/// The Start phase's references (sprint seed §3.1): crouch starts from the set position in the
/// blocks to the first foot landing. These are ours, keyframed in code on humanoid34: the seed's
/// references are poses extracted from race videos by 3D pose estimation, a data set that does
/// not exist here (and pose estimation is out of scope).
///
/// A start is built for a left foot in the front block (the default blocks, sprint_env.h) and
/// mirrored (character::mirror, blocks y ↦ −y) for a right one. It is sagittal: every joint turns
/// about the lateral axis only. Its frames, at the control rate:
///   set (t = 0): hands on the ground behind the line, the shoulders ahead of them, each foot's
///     sole on its block's face (a planar two-link solve of hip and knee, the foot turned to the
///     face); the pelvis and chest pitches are the keyframe's, the root placed by the hands;
///   block phase (to `block_time_s`): the root from rest to the front foot's take-off with
///     constant acceleration (x and z quadratic in t), the front foot held on its block by the
///     same solve until then, the rear one until `rear_off_s`; the rear leg swings forward;
///   flight: the root ballistic (gravity 9.81 m/s²) from the take-off's vertical speed down to the
///     landing's height, the distance to the landing made up by a constant horizontal acceleration;
///   landing (the last frame): the rear-block foot flat on the ground with its sole's centre at
///     `landing_x_m`, the other leg trailing.
/// Angles other than the solved ones come from a handful of keyframes (set, rear foot off, take-
/// off, mid-flight, landing), eased between them (smoothstep), so the motion rests at the set.
/// The two arm actions differ in the crook of the elbow (the seed's "crook of elbow"): `straight`
/// (about 20°) or `bent` (about 90°); both swing the arms in opposition to the legs.
///
/// The seed says the start "lasts about 2.5 meters (i.e. the first step after the departure)". A
/// first landing that far out cannot follow a push from these blocks: the constant-acceleration
/// push over the root's 0.37 m in the blocks leaves at about 2.1 m/s, whose flight comes down
/// about 0.4 m past the line; a landing at 2.5 m would need some 1 s in the air or, as the flight
/// is built here, a large horizontal acceleration in the air. So the landing distance is a setting
/// (preset data, `start.landing_x_m`), 0.5 m by default: athletics' first touchdown, about half a
/// metre past the line.
#include <memory>
#include <string>
#include <vector>

#include "podium/character/motion.h"
#include "sprint_env.h"
#include "steps.h"

namespace podium::tasks::sprint {

enum class ArmAction { straight, bent };
const char* to_string(ArmAction arms);

/// One crouch start's settings.
struct CrouchStartSpec {
  Foot front = Foot::left;               ///< the foot in the front block
  ArmAction arms = ArmAction::straight;  ///< the elbow's crook
  double landing_x_m = 0.5;              ///< the first landing's sole centre (the rear-block foot), m past the line
  double block_time_s = 0.36;            ///< set to the front foot's take-off, s
  double rear_off_s = 0.16;              ///< set to the rear foot's take-off, s
  double takeoff_lean_rad = 0.70;        ///< the front leg's lean from vertical at its take-off (≈ 40°)
};

/// A reference of the set (SprintEnv's StartReference: its name — "left_straight", ... —, the
/// blocks it starts from, front block first, and its clip) with its settings.
struct CrouchStart : StartReference {
  CrouchStartSpec spec;
};

/// The blocks for a front foot: `left_front` (front block first, as default_blocks()) itself for
/// the left foot, mirrored across the lane's centre line (y ↦ −y) for the right one.
std::vector<BlockSpec> blocks_for(Foot front, const std::vector<BlockSpec>& left_front = default_blocks());

/// The crouch start of `spec` on `model` (humanoid34: its joint names and sagittal hinges) with
/// frames every 1/control_hz s, from the blocks `blocks_for(spec.front, left_front)`. Throws
/// base::UserError for a model without the joints, an unreachable set position or bad timings.
character::Clip crouch_start_clip(const sim::ModelPtr& model, const CrouchStartSpec& spec, double control_hz,
                                  const std::vector<BlockSpec>& left_front = default_blocks());

/// The project's set: left/right front foot × straight/bent arms (4 starts), each with `base`'s
/// timings and landing distance.
std::vector<CrouchStart> crouch_start_set(const sim::ModelPtr& model, double control_hz, const CrouchStartSpec& base = {},
                                          const std::vector<BlockSpec>& left_front = default_blocks());
/// The set as SprintEnv's Start-mode references, with the preset's landing distance.
std::vector<StartReference> crouch_start_references(const sim::ModelPtr& model, double control_hz, const StartPreset& start);

}  // namespace podium::tasks::sprint
