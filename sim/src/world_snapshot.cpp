// WorldSnapshot as JSON, exact: a checkpoint written by one process replays bitwise in another.
// nlohmann writes a double as the shortest decimal that reads back to the same bits (Grisu2,
// to_chars) and reads it with a correctly rounded strtod, so finite values round-trip as plain
// numbers (tests/sim: world_snapshot_test); JSON has no NaN or infinity, so those are strings.
// Only the state is stored of CharacterData: every step ends with forward kinematics, and the
// other caches are rewritten before they are read.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>

#include "contact_solver.h"
#include "podium/base/error.h"
#include "podium/sim/world.h"

namespace podium::sim {

namespace {

using base::Json;

constexpr int kVersion = 1;

Json number(double x) {
  if (std::isfinite(x)) return x;
  return std::isnan(x) ? "nan" : (x > 0 ? "inf" : "-inf");
}

double read_number(const Json& j, const std::string& where) {
  if (j.is_number()) return j.get<double>();
  if (j.is_string()) {
    const std::string s = j.get<std::string>();
    if (s == "nan") return std::nan("");
    if (s == "inf") return std::numeric_limits<double>::infinity();
    if (s == "-inf") return -std::numeric_limits<double>::infinity();
  }
  throw base::UserError("sim: snapshot JSON: " + where + ": " + j.dump() + " is not a number");
}

template <class V>
Json numbers(const V& v) {
  Json out = Json::array();
  for (Eigen::Index i = 0; i < static_cast<Eigen::Index>(v.size()); ++i) out.push_back(number(v[i]));
  return out;
}

const Json& field(const Json& j, const std::string& key, const std::string& where) {
  if (!j.is_object() || !j.contains(key))
    throw base::UserError("sim: snapshot JSON: " + base::json_path_join(where, key) + ": missing");
  return j[key];
}

const Json& array_field(const Json& j, const std::string& key, const std::string& where) {
  const Json& a = field(j, key, where);
  if (!a.is_array())
    throw base::UserError("sim: snapshot JSON: " + base::json_path_join(where, key) + ": " + a.type_name() +
                          ", expected an array");
  return a;
}

// An array of `size` numbers (−1: any size) at j[key].
std::vector<double> read_numbers(const Json& j, const std::string& key, const std::string& where, long size) {
  const Json& a = field(j, key, where);
  const std::string path = base::json_path_join(where, key);
  if (!a.is_array() || (size >= 0 && static_cast<long>(a.size()) != size))
    throw base::UserError("sim: snapshot JSON: " + path + ": expected an array of " +
                          (size >= 0 ? std::to_string(size) : std::string("any number of")) + " numbers, got " +
                          (a.is_array() ? std::to_string(a.size()) + " entries" : a.type_name()));
  std::vector<double> out;
  for (std::size_t i = 0; i < a.size(); ++i) out.push_back(read_number(a[i], base::json_path_index(path, i)));
  return out;
}

Eigen::VectorXd read_vector(const Json& j, const std::string& key, const std::string& where, long size) {
  const std::vector<double> v = read_numbers(j, key, where, size);
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

Eigen::Vector3d read_vector3(const Json& j, const std::string& key, const std::string& where) {
  return read_vector(j, key, where, 3);
}

template <class T>
T read(const Json& j, const std::string& key, const std::string& where) {
  try {
    return field(j, key, where).get<T>();
  } catch (const Json::exception& e) {
    throw base::UserError("sim: snapshot JSON: " + base::json_path_join(where, key) + ": " + e.what());
  }
}

Json quaternion(const Eigen::Quaterniond& r) { return numbers(Eigen::Vector4d(r.w(), r.x(), r.y(), r.z())); }
Eigen::Quaterniond read_quaternion(const Json& j, const std::string& key, const std::string& where) {
  const Eigen::VectorXd v = read_vector(j, key, where, 4);
  return Eigen::Quaterniond(v(0), v(1), v(2), v(3));
}

// FNV-1a of the model-file JSON: equal for models built from the same file and edits.
std::string fingerprint(const CharacterModel& model) {
  std::uint64_t h = 14695981039346656037ull;
  for (const unsigned char c : model.source().dump()) h = (h ^ c) * 1099511628211ull;
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

const char* kind_name(TerrainRegion::Kind k) {
  switch (k) {
    case TerrainRegion::Kind::flat:
      return "flat";
    case TerrainRegion::Kind::rough:
      return "rough";
    case TerrainRegion::Kind::slope:
      return "slope";
  }
  return "flat";
}

Json terrain_json(const TerrainConfig& t) {
  Json regions = Json::array(), boxes = Json::array();
  for (const TerrainRegion& r : t.regions)
    regions.push_back({{"kind", kind_name(r.kind)},
                       {"min", numbers(r.min)},
                       {"max", numbers(r.max)},
                       {"height_m", number(r.height_m)},
                       {"tile_size_m", number(r.tile_size_m)},
                       {"min_tile_height_m", number(r.min_tile_height_m)},
                       {"max_tile_height_m", number(r.max_tile_height_m)},
                       {"seed", r.seed},
                       {"slope_rad", number(r.slope_rad)}});
  for (const BoxProp& b : t.boxes) {
    boxes.push_back({{"name", b.name},
                     {"center", numbers(b.center)},
                     {"half_extents", numbers(b.half_extents)},
                     {"rotation", quaternion(b.rotation)},
                     {"friction", number(b.friction)}});
    if (!b.kind.empty()) boxes.back()["kind"] = b.kind;  // absent from snapshots written before kinds
  }
  return {{"regions", regions}, {"boxes", boxes}};
}

TerrainConfig read_terrain(const Json& j, const std::string& where) {
  TerrainConfig t;
  const Json& regions = array_field(j, "regions", where);
  for (std::size_t i = 0; i < regions.size(); ++i) {
    const Json& r = regions[i];
    const std::string w = base::json_path_index(base::json_path_join(where, "regions"), i);
    TerrainRegion region;
    const std::string kind = read<std::string>(r, "kind", w);
    if (kind == "flat") region.kind = TerrainRegion::Kind::flat;
    else if (kind == "rough") region.kind = TerrainRegion::Kind::rough;
    else if (kind == "slope") region.kind = TerrainRegion::Kind::slope;
    else throw base::UserError("sim: snapshot JSON: " + w + ".kind: \"" + kind + "\" is not flat, rough or slope");
    region.min = read_vector(r, "min", w, 2);
    region.max = read_vector(r, "max", w, 2);
    region.height_m = read_number(field(r, "height_m", w), w + ".height_m");
    region.tile_size_m = read_number(field(r, "tile_size_m", w), w + ".tile_size_m");
    region.min_tile_height_m = read_number(field(r, "min_tile_height_m", w), w + ".min_tile_height_m");
    region.max_tile_height_m = read_number(field(r, "max_tile_height_m", w), w + ".max_tile_height_m");
    region.seed = read<std::uint64_t>(r, "seed", w);
    region.slope_rad = read_number(field(r, "slope_rad", w), w + ".slope_rad");
    t.regions.push_back(region);
  }
  const Json& boxes = array_field(j, "boxes", where);
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const Json& b = boxes[i];
    const std::string w = base::json_path_index(base::json_path_join(where, "boxes"), i);
    BoxProp box;
    box.name = read<std::string>(b, "name", w);
    box.center = read_vector3(b, "center", w);
    box.half_extents = read_vector3(b, "half_extents", w);
    box.rotation = read_quaternion(b, "rotation", w);
    box.friction = read_number(field(b, "friction", w), w + ".friction");
    if (b.contains("kind")) box.kind = read<std::string>(b, "kind", w);
    t.boxes.push_back(box);
  }
  return t;
}

Json config_json(const WorldConfig& c) {
  Json joints = Json::array();
  for (const auto& [name, keys] : c.edits.joints) joints.push_back({name, keys});
  return {{"sim_hz", number(c.sim_hz)},         {"control_hz", number(c.control_hz)},
          {"friction", number(c.friction)},     {"self_collision", c.self_collision},
          {"joint_limits", c.joint_limits},     {"torque_limits", c.torque_limits},
          {"strength", number(c.strength)},     {"gravity", numbers(c.gravity)},
          {"terrain", terrain_json(c.terrain)}, {"edits", {{"remove", c.edits.remove}, {"joints", joints}}}};
}

WorldConfig read_config(const Json& j, const std::string& where) {
  WorldConfig c;
  const auto num = [&](const char* key) { return read_number(field(j, key, where), base::json_path_join(where, key)); };
  c.sim_hz = num("sim_hz");
  c.control_hz = num("control_hz");
  c.friction = num("friction");
  c.self_collision = read<bool>(j, "self_collision", where);
  c.joint_limits = read<bool>(j, "joint_limits", where);
  c.torque_limits = read<bool>(j, "torque_limits", where);
  c.strength = num("strength");
  c.gravity = read_vector3(j, "gravity", where);
  c.terrain = read_terrain(field(j, "terrain", where), base::json_path_join(where, "terrain"));
  const std::string ew = base::json_path_join(where, "edits");
  const Json& edits = field(j, "edits", where);
  c.edits.remove = read<std::vector<std::string>>(edits, "remove", ew);
  for (const Json& e : array_field(edits, "joints", ew)) {
    if (!e.is_array() || e.size() != 2 || !e[0].is_string())
      throw base::UserError("sim: snapshot JSON: " + ew + ".joints: expected [name, keys] pairs");
    c.edits.joints.emplace_back(e[0].get<std::string>(), e[1]);
  }
  return c;
}

Json warm_json(const WarmStarts& w) {
  Json ground = Json::array(), manifold = Json::array();
  for (const auto& g : w.ground) ground.push_back(numbers(g));
  for (const ManifoldContact& m : w.manifold)
    manifold.push_back({{"key", m.key},
                        {"link_a", m.link_a},
                        {"link_b", m.link_b},
                        {"point_a", numbers(m.point_a)},
                        {"point_b", numbers(m.point_b)},
                        {"normal", numbers(m.normal)},
                        {"local_a", numbers(m.local_a)},
                        {"distance", number(m.distance)},
                        {"friction", number(m.friction)},
                        {"warm", numbers(m.warm)}});
  return {{"ground", ground}, {"limits", numbers(w.limits)}, {"locks", numbers(w.locks)}, {"manifold", manifold}};
}

WarmStarts read_warm(const Json& j, const std::string& where) {
  WarmStarts w;
  const Json& ground = array_field(j, "ground", where);
  for (std::size_t i = 0; i < ground.size(); ++i) {
    const std::string gw = base::json_path_index(base::json_path_join(where, "ground"), i);
    if (!ground[i].is_array() || ground[i].size() != 3)
      throw base::UserError("sim: snapshot JSON: " + gw + ": expected 3 numbers");
    w.ground.push_back({read_number(ground[i][0], gw), read_number(ground[i][1], gw), read_number(ground[i][2], gw)});
  }
  w.limits = read_numbers(j, "limits", where, -1);
  w.locks = read_numbers(j, "locks", where, -1);
  const Json& manifold = array_field(j, "manifold", where);
  for (std::size_t i = 0; i < manifold.size(); ++i) {
    const Json& m = manifold[i];
    const std::string mw = base::json_path_index(base::json_path_join(where, "manifold"), i);
    ManifoldContact c;
    c.key = read<std::array<int, 5>>(m, "key", mw);
    c.link_a = read<int>(m, "link_a", mw);
    c.link_b = read<int>(m, "link_b", mw);
    c.point_a = read_vector3(m, "point_a", mw);
    c.point_b = read_vector3(m, "point_b", mw);
    c.normal = read_vector3(m, "normal", mw);
    c.local_a = read_vector3(m, "local_a", mw);
    c.distance = read_number(field(m, "distance", mw), mw + ".distance");
    c.friction = read_number(field(m, "friction", mw), mw + ".friction");
    const std::vector<double> warm = read_numbers(m, "warm", mw, 3);
    c.warm = {warm[0], warm[1], warm[2]};
    w.manifold.push_back(c);
  }
  return w;
}

}  // namespace

Json WorldSnapshot::to_json() const {
  Json forces_json = Json::array();
  for (const Eigen::Vector3d& f : forces) forces_json.push_back(numbers(f));
  return {{"version", kVersion},
          {"model", model->name()},
          {"model_fingerprint", fingerprint(*model)},
          {"config", config_json(config)},
          {"q", numbers(data.q)},
          {"qd", numbers(data.qd)},
          {"qdd", numbers(data.qdd)},
          {"tau", numbers(data.tau)},
          {"kp", numbers(gains.kp)},
          {"kd", numbers(gains.kd)},
          {"step_count", step_count},
          {"failure", {{"ok", failure.ok}, {"bad_dof", failure.bad_dof}, {"bad_step", failure.bad_step}}},
          {"forces", forces_json},
          {"warm", warm_json(*warm)}};
}

WorldSnapshot WorldSnapshot::from_json(const Json& json, const ModelPtr& model) {
  if (read<int>(json, "version", "") != kVersion)
    throw base::UserError("sim: snapshot JSON: version " + json["version"].dump() + " is not " + std::to_string(kVersion));
  const std::string name = read<std::string>(json, "model", "");
  if (name != model->name() || read<std::string>(json, "model_fingerprint", "") != fingerprint(*model))
    throw base::UserError("sim: snapshot JSON: model: the snapshot is of another model (" + name + ", or other edits) than " +
                          model->name());
  CharacterData data(*model);
  const long nq = model->nq(), nv = model->nv();
  data.q = read_vector(json, "q", "", nq);
  data.qd = read_vector(json, "qd", "", nv);
  data.qdd = read_vector(json, "qdd", "", nv);
  data.tau = read_vector(json, "tau", "", nv);
  WorldSnapshot s(data);
  s.model = model;
  s.config = read_config(field(json, "config", ""), "config");
  s.data.gravity = s.config.gravity;
  forward_kinematics(*model, s.data);
  s.gains.kp = read_vector(json, "kp", "", nv);
  s.gains.kd = read_vector(json, "kd", "", nv);
  s.step_count = read<long long>(json, "step_count", "");
  const Json& failure = field(json, "failure", "");
  s.failure = StepReport{read<bool>(failure, "ok", "failure"), read<int>(failure, "bad_dof", "failure"),
                         read<long long>(failure, "bad_step", "failure")};
  const Json& forces = array_field(json, "forces", "");
  if (forces.size() != model->bodies().size())
    throw base::UserError("sim: snapshot JSON: forces: expected one per body (" + std::to_string(model->bodies().size()) + ")");
  for (std::size_t k = 0; k < forces.size(); ++k) {
    const std::string fw = base::json_path_index("forces", k);
    if (!forces[k].is_array() || forces[k].size() != 3)
      throw base::UserError("sim: snapshot JSON: " + fw + ": expected 3 numbers");
    s.forces.emplace_back(read_number(forces[k][0], fw), read_number(forces[k][1], fw), read_number(forces[k][2], fw));
  }
  s.warm = std::make_shared<const WarmStarts>(read_warm(field(json, "warm", ""), "warm"));
  return s;
}

}  // namespace podium::sim
