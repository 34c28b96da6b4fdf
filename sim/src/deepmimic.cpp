// Loader for DeepMimic's character and PD-controller formats (fields listed in
// characters/*.txt and controllers). DeepMimic is y-up; we rotate everything +90° about x to get z-up.
// Its motion clips are read by character/ (read_deepmimic_clip), the one clip type.
#include <algorithm>
#include <map>

#include "podium/base/error.h"
#include "podium/sim/model.h"

namespace podium::sim {

using base::Json;
using base::UserError;

namespace {

// y-up → z-up: (x, y, z) ↦ (x, −z, y).
Json zup(double x, double y, double z) { return Json{x, -z, y}; }

double field(const Json& obj, const char* key, const std::string& where) {
  if (!obj.contains(key) || !obj[key].is_number()) throw UserError(where + "." + key + ": missing or not a number");
  return obj[key].get<double>();
}

double torque_field(const Json& j, const char* key, const std::string& where) {
  if (!j.contains(key))
    throw UserError(where + "." + key + ": missing (N·m; a moving joint needs TorqueLim, or TorqueLimX/Y/Z if spherical)");
  if (!j[key].is_number() || !(j[key].get<double>() > 0))
    throw UserError(where + "." + key + ": " + j[key].dump() + " is not a number > 0 (N·m)");
  return j[key].get<double>();
}

// The joint's torque limit as our model file's "torque_limit". Spherical joints may give one per
// axis of the joint frame, TorqueLimX/Y/Z (the thesis's jumper: hips 500/50/500 N·m, §3.6.2;
// arpspoof/Jump reads them in place of TorqueLim when TorqueLimX is present); after the y-up →
// z-up turn, DeepMimic's x, y, z axes are our x, z, −y, so [X, Y, Z] becomes [X, Z, Y].
Json torque_limit(const Json& j, bool spherical, const std::string& where) {
  if (spherical && (j.contains("TorqueLimX") || j.contains("TorqueLimY") || j.contains("TorqueLimZ"))) {
    const double x = torque_field(j, "TorqueLimX", where), y = torque_field(j, "TorqueLimY", where),
                 z = torque_field(j, "TorqueLimZ", where);
    return Json{x, z, y};
  }
  return torque_field(j, "TorqueLim", where);
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
    for (const Json& c : ctrl.value("PDControllers", Json::array()))
      gains[c.value("Name", "")] = {c.value("Kp", 0.0), c.value("Kd", 0.0)};
  }

  Json bodies = Json::array();
  std::vector<std::string> names;
  Json end_effectors = Json::array();
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const Json& j = joints[i];
    const std::string name = j.value("Name", "joint" + std::to_string(i));
    const std::string jw = where + ": joint " + name + " (" + base::json_path_index("Skeleton.Joints", i) + ")";
    const std::string type = j.value("Type", "");
    const int parent = j.value("Parent", -1);
    Json body = {{"name", name}};
    if (parent >= 0) {
      if (parent >= static_cast<int>(names.size()))
        throw UserError(jw + ".Parent: " + std::to_string(parent) + " is not an earlier joint");
      body["parent"] = names[parent];
      body["pos"] = zup(field(j, "AttachX", jw), field(j, "AttachY", jw), field(j, "AttachZ", jw));
      Json joint = {{"name", name}};
      if (type == "spherical" || type == "revolute") {
        joint["type"] = type;
        joint["torque_limit"] = torque_limit(j, type == "spherical", jw);
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

}  // namespace podium::sim
