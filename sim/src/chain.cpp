// Chain ("snake") models for the scaling tests and benchmark (thesis Table 2.1: 36, 72, 195 DoF).
#include <string>

#include "podium/base/error.h"
#include "podium/sim/model.h"

namespace podium::sim {

ModelPtr make_chain(int n_links, JointType joint) {
  if (n_links < 2) throw base::UserError("sim: make_chain: n_links " + std::to_string(n_links) + " is not ≥ 2");
  if (joint == JointType::free) throw base::UserError("sim: make_chain: joints must be revolute or spherical");
  const double length = 0.2, radius = 0.04;
  base::Json bodies = base::Json::array();
  for (int i = 0; i < n_links; ++i) {
    base::Json b = {{"name", "link" + std::to_string(i)},
                    {"geoms", {{{"type", "capsule"}, {"fromto", {0, 0, 0, length, 0, 0}}, {"radius", radius}}}}};
    if (i == 0) {
      b["pos"] = {0.0, 0.0, radius};
    } else {
      b["parent"] = "link" + std::to_string(i - 1);
      b["pos"] = {length, 0.0, 0.0};
      base::Json j = {{"name", "joint" + std::to_string(i)}, {"torque_limit", 50.0}, {"kp", 200.0}, {"kd", 20.0}};
      if (joint == JointType::spherical) {
        j["type"] = "spherical";
      } else {
        j["type"] = "revolute";
        j["axis"] = i % 2 ? base::Json{0, 0, 1} : base::Json{0, 1, 0};
      }
      b["joints"] = {j};
    }
    bodies.push_back(b);
  }
  const std::string kind = joint == JointType::spherical ? "spherical" : "revolute";
  base::Json model = {{"name", "chain" + std::to_string(n_links) + "_" + kind},
                      {"bodies", bodies},
                      {"standing_root_height", radius},
                      {"end_effectors", {"link" + std::to_string(n_links - 1)}}};
  return CharacterModel::from_json(model, "chain model");
}

}  // namespace podium::sim
