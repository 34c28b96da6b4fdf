#include "captured_techniques.h"

#include <cmath>

#include "podium/base/error.h"
#include "podium/character/motion.h"
#include "podium/sim/data.h"
#include "podium/sim/dynamics.h"
#include "strategy_feature.h"

namespace podium::tasks::jump {

namespace fs = std::filesystem;

std::vector<CapturedTechnique> captured_techniques(const fs::path& motions_dir, const sim::ModelPtr& model) {
  const std::vector<std::pair<std::string, std::string>> files = {{"Fosbury flop", "VC5_high_jump__fosbury_flop_06.txt"},
                                                                  {"straddle", "VC5_high_jump__straddle_02.txt"},
                                                                  {"scissor", "VC5_high_jump__scissor_01.txt"}};
  std::vector<CapturedTechnique> out;
  for (const auto& [name, file] : files) {
    const fs::path path = motions_dir / file;
    if (!fs::is_regular_file(path)) throw base::UserError("captured techniques: " + path.string() + ": no such file");
    const character::Clip clip = character::read_deepmimic_clip(model, path);
    // The frame where the centre of mass peaks: the captures have no bar to cross.
    sim::CharacterData data(*model);
    CapturedTechnique t{name, file, 0.0, -1e9};
    Eigen::Vector3d com, com_vel;
    for (const Eigen::VectorXd& q : clip.poses) {
      data.q = q;
      data.qd.setZero();
      sim::forward_kinematics(*model, data);
      sim::center_of_mass(*model, data, com, com_vel);
      const double com_z = com.z();
      if (com_z <= t.peak_com_m) continue;
      t.peak_com_m = com_z;
      t.up_angle_rad = up_angle(Eigen::Quaterniond(q(3), q(4), q(5), q(6)).normalized());
    }
    out.push_back(t);
  }
  return out;
}

const CapturedTechnique& nearest_technique(const std::vector<CapturedTechnique>& techniques, double up_angle_rad) {
  if (techniques.empty()) throw base::UserError("captured techniques: none to compare with");
  const CapturedTechnique* best = &techniques.front();
  for (const auto& t : techniques)
    if (std::abs(t.up_angle_rad - up_angle_rad) < std::abs(best->up_angle_rad - up_angle_rad)) best = &t;
  return *best;
}

}  // namespace podium::tasks::jump
