#pragma once
/// Motion clips: the one clip type of the project, for DeepMimic clips and recorded rollouts
/// alike — poses q (nq, z-up) at increasing times. Sampling interpolates (hinges linearly, root
/// and ball joints by slerp), so clips can be retimed (get-up seed §6: τ_slow is τ_fast slowed by
/// κ "by interpolation"), resampled to a control rate, differentiated and mirrored.
#include <Eigen/Core>
#include <filesystem>
#include <vector>

#include "podium/sim/model.h"
#include "podium/sim/recorder.h"

namespace podium::character {

struct Clip {
  sim::ModelPtr model;                 ///< the character whose q the poses are
  std::vector<double> times_s;         ///< frame times, strictly increasing, times_s[0] = 0
  std::vector<Eigen::VectorXd> poses;  ///< q per frame (nq), z-up
  bool loop = false;                   ///< DeepMimic's "Loop": the clip repeats

  std::size_t size() const { return poses.size(); }
  double duration_s() const { return times_s.empty() ? 0.0 : times_s.back(); }
  /// The pose at time t (clamped to [0, duration], or wrapped when `loop`).
  Eigen::VectorXd sample(double t) const;
  /// Generalised velocities per frame (nv, sim's convention: root ω and v in the root frame,
  /// ball ω in the child frame), by forward differences (the last frame repeats the previous).
  std::vector<Eigen::VectorXd> velocities() const;
};

/// Frames at 0, dt, 2dt, ... up to the clip's duration (to 1e-9 s), interpolated.
Clip resample(const Clip& clip, double dt_s);
/// Slowed by κ ∈ (0, ∞) (κ < 1 slower; get-up seed §6, Algorithm 2): the same frames at times
/// t_i/κ, so it lasts T/κ, passes through every original frame, and sample() interpolates
/// between them. resample(retime(clip, κ), dt) gives its frames at a control rate.
Clip retime(const Clip& clip, double kappa);
/// Mirrored left ↔ right across the world x–z plane (y ↦ −y): joints whose names differ by
/// "left"/"right" exchange their values. Throws base::UserError when the model is not
/// mirror-symmetric (a partner is missing or its axis is not the mirrored axis).
Clip mirror(const Clip& clip);
Eigen::VectorXd mirror_pose(const sim::CharacterModel& model, const Eigen::VectorXd& q);

/// Reads a DeepMimic motion file (`Loop`, `Frames`: dt, root position, root quaternion wxyz, then
/// per joint a quaternion or an angle) for a model made by sim::load_deepmimic, converting y-up
/// to z-up. Errors name the file and the frame.
Clip read_deepmimic_clip(const sim::ModelPtr& model, const std::filesystem::path& path);
/// The recorded frames of a rollout as a clip (times from the first frame); `model` is the
/// recorder's model (sim::Recorder exposes it by reference only).
Clip clip_from_recording(const sim::Recorder& recorder, const sim::ModelPtr& model);

}  // namespace podium::character
