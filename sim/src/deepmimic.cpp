// Loader for DeepMimic's character, PD-controller and motion formats (fields listed in
// ../shared/data/README.md). DeepMimic is y-up; we rotate everything +90° about x to get z-up.
#include <cmath>
#include <algorithm>
#include <map>
#include <numbers>

#include "podium/base/error.h"
#include "podium/sim/motion.h"

namespace podium::sim {

using base::Json;
using base::UserError;

namespace {

// y-up → z-up: (x, y, z) ↦ (x, −z, y).
Json zup(double x, double y, double z) { return Json{x, -z, y}; }
const Eigen::Quaterniond& yup_to_zup() {
  static const Eigen::Quaterniond q(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitX()));
  return q;
}

double field(const Json& obj, const char* key, const std::string& where) {
  if (!obj.contains(key) || !obj[key].is_number()) throw UserError(where + "." + key + ": missing or not a number");
  return obj[key].get<double>();
}

}  // namespace

ModelPtr load_deepmimic(const std::filesystem::path& character, const std::filesystem::path& controller) {
  const Json src = base::read_json_file(character);
  const std::string where = "deepmimic character " + character.filename().string();
  if (!src.contains("Skeleton") || !src["Skeleton"].contains("Joints")) throw UserError(where + ": Skeleton.Joints: missing");
  const Json& joints = src["Skeleton"]["Joints"];
  std::map<int, Json> body_defs;
  if (src.contains("BodyDefs"))
    for (const Json& b : src["BodyDefs"]) body_defs[b.value("ID", -1)] = b;
  std::map<std::string, std::pair<double, double>> gains;
  if (!controller.empty()) {
    const Json ctrl = base::read_json_file(controller);
    for (const Json& c : ctrl.value("PDControllers", Json::array())) gains[c.value("Name", "")] = {c.value("Kp", 0.0), c.value("Kd", 0.0)};
  }

  Json bodies = Json::array();
  std::vector<std::string> names;
  Json end_effectors = Json::array();
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const Json& j = joints[i];
    const std::string jw = where + ": " + base::json_path_index("Skeleton.Joints", i);
    const std::string name = j.value("Name", "joint" + std::to_string(i));
    const std::string type = j.value("Type", "");
    const int parent = j.value("Parent", -1);
    Json body = {{"name", name}};
    if (parent >= 0) {
      if (parent >= static_cast<int>(names.size())) throw UserError(jw + ".Parent: " + std::to_string(parent) + " is not an earlier joint");
      body["parent"] = names[parent];
      body["pos"] = zup(field(j, "AttachX", jw), field(j, "AttachY", jw), field(j, "AttachZ", jw));
      Json joint = {{"name", name}};
      const double torque = j.contains("TorqueLim") && j["TorqueLim"].is_number() ? j["TorqueLim"].get<double>() : 0.0;
      if (type == "spherical" || type == "revolute") {
        joint["type"] = type;
        joint["torque_limit"] = torque > 0 ? torque : 1.0;
        if (gains.count(name)) {
          joint["kp"] = gains[name].first;
          joint["kd"] = gains[name].second;
        }
        if (type == "revolute") {
          joint["axis"] = zup(0, 0, 1);  // DeepMimic revolute joints turn about their local z
          const double lo = j.value("LimLow0", 1.0), hi = j.value("LimHigh0", 0.0);
          if (lo < hi) joint["range"] = {lo, hi};
        }
        body["joints"] = {joint};
      } else if (type != "fixed") {
        throw UserError(jw + ".Type: \"" + type + "\" is not one of none, spherical, revolute, fixed");
      }
    } else if (i != 0) {
      throw UserError(jw + ".Parent: only the first joint may be the root");
    }
    if (j.value("IsEndEffector", 0) != 0) end_effectors.push_back(name);
    const int id = j.value("ID", static_cast<int>(i));
    if (body_defs.count(id)) {
      const Json& b = body_defs[id];
      const std::string bw = where + ": BodyDefs[" + std::to_string(id) + "]";
      const Json center = zup(field(b, "AttachX", bw), field(b, "AttachY", bw), field(b, "AttachZ", bw));
      const std::string shape = b.value("Shape", "");
      const double p0 = field(b, "Param0", bw), p1 = field(b, "Param1", bw), p2 = field(b, "Param2", bw);
      Json geom;
      if (shape == "sphere") {
        geom = {{"type", "sphere"}, {"pos", center}, {"radius", 0.5 * p0}};
      } else if (shape == "capsule") {
        // Capsule along DeepMimic's local y (z after conversion), Param1 = cylinder length.
        const double cx = center[0].get<double>(), cy = center[1].get<double>(), cz = center[2].get<double>();
        geom = {{"type", "capsule"}, {"fromto", {cx, cy, cz - 0.5 * p1, cx, cy, cz + 0.5 * p1}}, {"radius", 0.5 * p0}};
      } else if (shape == "box") {
        geom = {{"type", "box"}, {"pos", center}, {"half_extents", {0.5 * p0, 0.5 * p2, 0.5 * p1}}};
      } else {
        throw UserError(bw + ".Shape: \"" + shape + "\" is not one of sphere, capsule, box");
      }
      body["geoms"] = {geom};
      body["mass"] = field(b, "Mass", bw);
    }
    names.push_back(name);
    bodies.push_back(body);
  }
  Json model = {{"name", character.stem().string()}, {"bodies", bodies}, {"end_effectors", end_effectors}};
  for (const char* head : {"neck", "head"})
    if (std::find(names.begin(), names.end(), head) != names.end()) model["head"] = head;
  if (std::find(names.begin(), names.end(), "chest") != names.end()) model["torso"] = "chest";
  return CharacterModel::from_json(model, where);
}

MotionClip load_deepmimic_motion(const CharacterModel& model, const std::filesystem::path& path) {
  const Json src = base::read_json_file(path);
  const std::string where = "deepmimic motion " + path.filename().string();
  if (!src.contains("Frames") || !src["Frames"].is_array()) throw UserError(where + ": Frames: missing or not an array");
  // Frame width: dt + root 7 + per joint 4 (spherical) or 1 (revolute) = 1 + nq.
  const std::size_t width = 1 + static_cast<std::size_t>(model.nq());
  const Eigen::Quaterniond& c = yup_to_zup();
  MotionClip clip;
  for (std::size_t f = 0; f < src["Frames"].size(); ++f) {
    const Json& fr = src["Frames"][f];
    if (!fr.is_array() || fr.size() != width)
      throw UserError(where + ": Frames[" + std::to_string(f) + "]: has " + std::to_string(fr.size()) + " numbers but model " + model.name() +
                      " needs " + std::to_string(width) + " (dt + nq)");
    Eigen::VectorXd q(model.nq());
    for (int k = 0; k < model.nq(); ++k) q(k) = fr[k + 1].get<double>();
    q.head<3>() = c * Eigen::Vector3d(q.head<3>());
    for (const Link& l : model.links()) {
      if (l.joint == JointType::revolute) continue;
      const int i = l.joint == JointType::free ? l.q_index + 3 : l.q_index;
      // Rotations conjugate with the frame change: R' = C R Cᵀ.
      const Eigen::Quaterniond r = (c * Eigen::Quaterniond(q(i), q(i + 1), q(i + 2), q(i + 3)).normalized() * c.conjugate());
      q.segment<4>(i) << r.w(), r.x(), r.y(), r.z();
    }
    clip.frame_dt_s.push_back(fr[0].get<double>());
    clip.poses.push_back(q);
  }
  return clip;
}

}  // namespace podium::sim
