// User clips as Start references (user_start.h). Written here: the alignment is the sprint's.
#include "user_start.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "crouch_start.h"
#include "podium/base/error.h"
#include "podium/character/motion.h"
#include "podium/sim/dynamics.h"

namespace podium::tasks::sprint {

std::vector<StartClipSpec> read_start_clips(base::ConfigReader& r) {
  return r.objects(
      "start_clips",
      [](base::ConfigReader& c) {
        StartClipSpec s;
        s.clip =
            c.file("clip", base::required, "a DeepMimic-format motion in humanoid34's (DeepMimic humanoid3d's) joint layout");
        s.blocks = c.choice("blocks", s.blocks, {"none", "left", "right"},
                            "none: aligned to run along +x from the start line, no blocks; left/right: as authored in the "
                            "track's frame, from the blocks with that foot in front");
        return s;
      },
      "Start: user clips as references besides the crouch starts (sprint seed §3.1: \"any user clip\")");
}

namespace {

// The lowest geom point of the model over the clip's frames.
double lowest_point(const character::Clip& clip) {
  const sim::CharacterModel& m = *clip.model;
  double low = std::numeric_limits<double>::infinity();
  for (const Eigen::VectorXd& q : clip.poses) {
    sim::CharacterData d(m);
    d.q = q;
    sim::forward_kinematics(m, d);
    low = std::min(low, sim::lowest_geom_point(m, d));
  }
  return low;
}

// Turns the clip about the vertical through its first root so that the root travels along +x,
// then moves its first root to (0, 0).
void align_along_track(character::Clip& clip) {
  const Eigen::Vector3d first = clip.poses.front().head<3>(), last = clip.poses.back().head<3>();
  const Eigen::Vector2d travel = (last - first).head<2>();
  const double yaw = travel.norm() > 1e-6 ? -std::atan2(travel.y(), travel.x()) : 0.0;
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  for (Eigen::VectorXd& q : clip.poses) {
    Eigen::Vector3d p = turn * (Eigen::Vector3d(q.head<3>()) - first);
    p.z() += first.z();
    q.head<3>() = p;
    const Eigen::Quaterniond root(q(3), q(4), q(5), q(6));
    const Eigen::Quaterniond turned = (turn * root).normalized();
    q(3) = turned.w(), q(4) = turned.x(), q(5) = turned.y(), q(6) = turned.z();
  }
}

}  // namespace

StartReference user_start_reference(const sim::ModelPtr& model, double control_hz, const StartClipSpec& spec) {
  character::Clip clip = character::resample(character::read_deepmimic_clip(model, spec.clip), 1.0 / control_hz);
  if (clip.size() < 2)
    throw base::UserError("sprint start clip " + spec.clip + ": " + std::to_string(clip.size()) +
                          " frame(s) at the control rate; a reference needs 2 or more");
  if (spec.blocks == "none") align_along_track(clip);
  const double lift = -lowest_point(clip);
  for (Eigen::VectorXd& q : clip.poses) q(2) += lift;
  StartReference r;
  r.name = "clip:" + std::filesystem::path(spec.clip).stem().string();
  if (spec.blocks != "none") r.blocks = blocks_for(spec.blocks == "left" ? Foot::left : Foot::right);
  r.clip = std::make_shared<const character::Clip>(std::move(clip));
  return r;
}

}  // namespace podium::tasks::sprint
