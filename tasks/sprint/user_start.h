#pragma once
/// User clips as Start references (sprint seed §3.1: the Start imitates reference starts, the
/// project's keyframed crouch starts — crouch_start.h — "and any user clip"). A clip is a
/// DeepMimic-format motion in humanoid34's joint layout (DeepMimic's humanoid3d), read onto
/// humanoid34, resampled at the control rate and moved vertically so that its lowest geom point
/// over the whole clip touches the ground (humanoid34 is humanoid3d scaled up: its root heights
/// would otherwise sink the feet). Then, by its `blocks`:
///   "none": turned about the vertical so its root travels along +x (first to last frame) and
///     moved so its first root lies on the start line at the lane's centre: a start without
///     blocks (standing, crouched or rolling);
///   "left" / "right": taken as authored in the track's frame (x along the track, the start
///     line at x = 0, the lane's centre at y = 0), from the default blocks with that foot in the
///     front block: its first frame must be the set position in them.
/// The Start mode treats such a reference as a crouch start: drawn uniformly with the others, its
/// first frame (and frame velocity) the episode's start, DeepMimic's tracking against it, the
/// episode ending at the first counted landing.
#include <string>
#include <vector>

#include "podium/base/config.h"
#include "sprint_env.h"

namespace podium::tasks::sprint {

struct StartClipSpec {
  std::string clip;             ///< the DeepMimic-format motion file
  std::string blocks = "none";  ///< none, left or right (the foot in the front block)
};

/// The config key `start_clips` (an array of {"clip", "blocks"}); errors name the JSON path.
std::vector<StartClipSpec> read_start_clips(base::ConfigReader& r);

/// The reference of `spec` on `model`, named "clip:<file stem>". Throws base::UserError naming
/// the file (unreadable, another joint layout, fewer than 2 frames).
StartReference user_start_reference(const sim::ModelPtr& model, double control_hz, const StartClipSpec& spec);

}  // namespace podium::tasks::sprint
