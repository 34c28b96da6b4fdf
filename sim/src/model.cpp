// Builds a CharacterModel from the project's JSON model format (sim/README.md): parses bodies,
// expands multi-hinge bodies into chains of links, welds jointless bodies into their parent,
// and accumulates link masses and inertias from geom volumes.
#include "podium/sim/model.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <numbers>
#include <set>
#include <sstream>

#include "podium/base/error.h"
#include "shapes.h"

namespace podium::sim {

using base::Json;
using base::UserError;

namespace {

std::string show(const Json& j) { return j.dump(); }

Eigen::Vector3d vec3(const Json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
    throw UserError(where + ": " + show(j) + " is not an array of 3 numbers");
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

double number(const Json& obj, const char* key, double fallback, const std::string& where) {
  if (!obj.contains(key)) return fallback;
  if (!obj[key].is_number()) throw UserError(base::json_path_join(where, key) + ": " + show(obj[key]) + " is not a number");
  return obj[key].get<double>();
}

double positive(const Json& obj, const char* key, const std::string& where) {
  const double v = number(obj, key, -1.0, where);
  if (!(v > 0.0))
    throw UserError(base::json_path_join(where, key) + ": " + (obj.contains(key) ? show(obj[key]) : "missing") + " is not > 0");
  return v;
}

Geom parse_geom(const Json& g, const std::string& where) {
  Geom geom;
  const std::string type = g.value("type", "");
  if (type == "capsule") {
    geom.type = ShapeType::capsule;
    geom.radius = positive(g, "radius", where);
    if (!g.contains("fromto")) throw UserError(where + ".fromto: missing (capsules are given by their end points)");
    const Json& ft = g["fromto"];
    if (!ft.is_array() || ft.size() != 6) throw UserError(where + ".fromto: " + show(ft) + " is not an array of 6 numbers");
    const Eigen::Vector3d a = vec3(Json{ft[0], ft[1], ft[2]}, where + ".fromto");
    const Eigen::Vector3d b = vec3(Json{ft[3], ft[4], ft[5]}, where + ".fromto");
    geom.pos = 0.5 * (a + b);
    geom.half_length = 0.5 * (b - a).norm();
    if (geom.half_length > 0) geom.rot = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), b - a);
  } else if (type == "sphere") {
    geom.type = ShapeType::sphere;
    geom.radius = positive(g, "radius", where);
    if (g.contains("pos")) geom.pos = vec3(g["pos"], where + ".pos");
  } else if (type == "box") {
    geom.type = ShapeType::box;
    geom.half_extents = vec3(g.value("half_extents", Json()), where + ".half_extents");
    if (geom.half_extents.minCoeff() <= 0)
      throw UserError(where + ".half_extents: " + show(g["half_extents"]) + " has an entry ≤ 0");
    if (g.contains("pos")) geom.pos = vec3(g["pos"], where + ".pos");
    if (g.contains("quat")) {
      const Json& q = g["quat"];
      if (!q.is_array() || q.size() != 4) throw UserError(where + ".quat: " + show(q) + " is not [w, x, y, z]");
      geom.rot = Eigen::Quaterniond(q[0].get<double>(), q[1].get<double>(), q[2].get<double>(), q[3].get<double>()).normalized();
    }
  } else {
    throw UserError(where + ".type: \"" + type + "\" is not one of capsule, sphere, box");
  }
  return geom;
}

// "torque_limit": N·m for every DoF of the joint, or for a spherical joint [x, y, z] about the
// link's axes (the thesis's jumper has hips 500/500/50 N·m, §3.6.2; DeepMimic's TorqueLimX/Y/Z).
Eigen::Vector3d parse_torque_limit(const Json& j, JointType type, const std::string& where) {
  if (!j.contains("torque_limit") || j["torque_limit"].is_number())
    return Eigen::Vector3d::Constant(positive(j, "torque_limit", where));
  const Json& t = j["torque_limit"];
  const std::string w = base::json_path_join(where, "torque_limit");
  if (type != JointType::spherical)
    throw UserError(w + ": " + show(t) + " is not a number > 0 (N·m" +
                    (t.is_array() ? "; per-axis limits are for spherical joints)" : ")"));
  if (!t.is_array() || t.size() != 3 ||
      !std::all_of(t.begin(), t.end(), [](const Json& x) { return x.is_number() && x.get<double>() > 0; }))
    throw UserError(w + ": " + show(t) + " is not a number > 0 or [x, y, z] of numbers > 0 (N·m about the link's axes)");
  return {t[0].get<double>(), t[1].get<double>(), t[2].get<double>()};
}

double angle_in(const Json& j, double lo, double hi, const std::string& where) {
  if (!j.is_number() || !(j.get<double>() >= lo && j.get<double>() <= hi))
    throw UserError(where + ": " + show(j) + " is not an angle in [" + std::to_string(lo) + ", " + std::to_string(hi) + "] rad");
  return j.get<double>();
}

// "axis" (twist axis, default z), "swing" (cone half-angle), "twist" ([lower, upper]).
void parse_spherical_limits(const Json& j, const std::string& where, Link& link) {
  if (j.contains("axis")) {
    link.axis = vec3(j["axis"], where + ".axis");
    if (link.axis.norm() < 1e-9) throw UserError(where + ".axis: " + show(j["axis"]) + " is not a direction (zero length)");
    link.axis.normalize();
  }
  if (j.contains("swing")) link.swing_limit = angle_in(j["swing"], 1e-3, std::numbers::pi, where + ".swing");
  if (j.contains("twist")) {
    const Json& t = j["twist"];
    if (!t.is_array() || t.size() != 2) throw UserError(where + ".twist: " + show(t) + " is not [lower, upper] (radians)");
    link.twist_lower = angle_in(t[0], -std::numbers::pi, std::numbers::pi, where + ".twist[0]");
    link.twist_upper = angle_in(t[1], -std::numbers::pi, std::numbers::pi, where + ".twist[1]");
    if (!(link.twist_lower < link.twist_upper))
      throw UserError(where + ".twist: " + show(t) + " is not [lower, upper] with lower < upper");
  }
}

// "lock": an angle (revolute) or a quaternion [w, x, y, z] (spherical) the joint is held at.
void parse_lock(const Json& j, const std::string& where, Link& link) {
  link.locked = true;
  if (link.joint == JointType::revolute) {
    if (!j.is_number()) throw UserError(where + ": " + show(j) + " is not an angle (radians) for a revolute joint");
    link.lock(0) = j.get<double>();
    if (link.lower < link.upper && (link.lock(0) < link.lower || link.lock(0) > link.upper))
      throw UserError(where + ": " + show(j) + " is outside the joint's range");
    return;
  }
  if (!j.is_array() || j.size() != 4 || !std::all_of(j.begin(), j.end(), [](const Json& x) { return x.is_number(); }))
    throw UserError(where + ": " + show(j) + " is not a quaternion [w, x, y, z] for a spherical joint");
  const Eigen::Vector4d q(j[0].get<double>(), j[1].get<double>(), j[2].get<double>(), j[3].get<double>());
  if (q.norm() < 1e-9) throw UserError(where + ": " + show(j) + " is not a rotation (zero length)");
  link.lock = q.normalized();
}

// Names listed in the top-level "remove" and every body below them (parents come first).
std::set<std::string> removed_bodies(const Json& json, const std::string& where) {
  std::set<std::string> removed;
  if (!json.contains("remove")) return removed;
  const Json& r = json["remove"];
  if (!r.is_array()) throw UserError(where + ": remove: " + show(r) + " is not an array of body names");
  std::set<std::string> names;
  for (const Json& b : json["bodies"]) names.insert(b.value("name", ""));
  for (std::size_t i = 0; i < r.size(); ++i) {
    if (!r[i].is_string() || !names.count(r[i].get<std::string>()))
      throw UserError(where + ": " + base::json_path_index("remove", i) + ": " + show(r[i]) + " is not a body");
    if (r[i].get<std::string>() == json["bodies"][0].value("name", ""))
      throw UserError(where + ": " + base::json_path_index("remove", i) + ": the root cannot be removed");
    removed.insert(r[i].get<std::string>());
  }
  for (const Json& b : json["bodies"])
    if (b.contains("parent") && b["parent"].is_string() && removed.count(b["parent"].get<std::string>()))
      removed.insert(b.value("name", ""));
  return removed;
}

// A body's mass, first moment and inertia about its origin, in its own frame, from its geoms:
// either a density, or a total mass spread over the geoms' volume.
struct BodyMass {
  double mass = 0.0;
  Eigen::Vector3d moment = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia_origin = Eigen::Matrix3d::Zero();  // about the body origin
};

BodyMass body_mass_properties(const std::vector<Geom>& geoms, double mass, double density, const std::string& where) {
  BodyMass out;
  double volume = 0.0;
  for (const Geom& g : geoms) volume += geom_volume(g);
  const double scale = mass > 0 ? (volume > 0 ? mass / volume : 0.0) : density;
  if (mass > 0 && volume <= 0) throw UserError(where + ".mass: a body with mass needs at least one geom");
  for (const Geom& g : geoms) {
    const double gm = scale * geom_volume(g);
    const Eigen::Matrix3d Ic = g.rot.toRotationMatrix() * geom_unit_inertia(g) * g.rot.toRotationMatrix().transpose() * gm;
    out.mass += gm;
    out.moment += gm * g.pos;
    out.inertia_origin += Ic + gm * (g.pos.squaredNorm() * Eigen::Matrix3d::Identity() - g.pos * g.pos.transpose());
  }
  return out;
}

// A joint's type, range, limits, lock and gains, and its anchor "pos" in the body frame (not its
// place in the tree).
struct ParsedJoint {
  Link link;
  Eigen::Vector3d anchor = Eigen::Vector3d::Zero();
};

ParsedJoint parse_joint(const Json& j, const std::string& jw, const CharacterModel& m) {
  ParsedJoint out;
  Link& link = out.link;
  link.name = j.value("name", "");
  if (link.name.empty()) throw UserError(jw + ".name: missing or empty");
  if (m.find_link(link.name) >= 0) throw UserError(jw + ".name: \"" + link.name + "\" is used by an earlier joint");
  const std::string type = j.value("type", "");
  if (j.contains("pos")) out.anchor = vec3(j["pos"], jw + ".pos");
  if (type == "revolute") {
    link.joint = JointType::revolute;
    link.axis = vec3(j.value("axis", Json()), jw + ".axis");
    if (link.axis.norm() < 1e-9) throw UserError(jw + ".axis: " + show(j["axis"]) + " is not a direction (zero length)");
    link.axis.normalize();
    if (j.contains("range")) {
      const Json& r = j["range"];
      if (!r.is_array() || r.size() != 2 || !(r[0].get<double>() < r[1].get<double>()))
        throw UserError(jw + ".range: " + show(r) + " is not [lower, upper] with lower < upper (radians)");
      link.lower = r[0].get<double>();
      link.upper = r[1].get<double>();
    } else {
      link.lower = 1.0;
      link.upper = -1.0;
    }
  } else if (type == "spherical") {
    link.joint = JointType::spherical;
    link.lower = 1.0;
    link.upper = -1.0;
    parse_spherical_limits(j, jw, link);
  } else {
    throw UserError(jw + ".type: \"" + type + "\" is not one of revolute, spherical");
  }
  if (j.contains("lock")) parse_lock(j["lock"], jw + ".lock", link);
  link.torque_limit_nm = parse_torque_limit(j, link.joint, jw);
  // Default kp = the torque limit (get-up seed App. D); per-axis limits: the largest (one
  // stiffness per joint, as DeepMimic's controller files give).
  link.kp = number(j, "kp", link.torque_limit_nm.maxCoeff(), jw);
  link.kd = number(j, "kd", 0.1 * link.kp, jw);
  if (link.kp < 0 || link.kd < 0) throw UserError(jw + ": kp and kd must be ≥ 0");
  link.damping = number(j, "damping", 0.0, jw);
  link.stiffness = number(j, "stiffness", 0.0, jw);
  if (link.damping < 0 || link.stiffness < 0) throw UserError(jw + ": damping and stiffness must be ≥ 0");
  if (link.joint != JointType::revolute && (link.damping > 0 || link.stiffness > 0))
    throw UserError(jw + ": damping and stiffness are for revolute joints (this one is " + type + ")");
  link.armature = number(j, "armature", 0.0, jw);
  if (!(link.armature >= 0)) throw UserError(jw + ".armature: " + show(j["armature"]) + " is not ≥ 0 (kg·m²)");
  return out;
}

// Where a body's frame sits: the link that carries it and the body origin in that link's frame.
struct Carrier {
  int link = -1;
  Eigen::Vector3d origin_in_link = Eigen::Vector3d::Zero();
};

}  // namespace

// Builds a CharacterModel body by body: each body either starts the tree (the root's free
// joint), rides on its parent's link (no joints), or hangs from a chain of one link per joint.
class ModelBuilder {
 public:
  static ModelPtr build(const Json& json, const std::string& where);

 private:
  ModelBuilder(const Json& json, const std::string& where);
  void add_body(std::size_t bi);
  Carrier add_joint_chain(const std::vector<Json>& joints, int parent_body, int body_id, const Eigen::Vector3d& pos,
                          const std::string& bw);
  void merge_into_link(const Carrier& carrier, const BodyMass& mass, std::vector<Geom> geoms, int body_id);
  void layout_dofs();
  void collision_filter();
  void named_bodies();

  const Json& json_;
  const std::string& where_;
  std::shared_ptr<CharacterModel> model_ = std::make_shared<CharacterModel>();
  CharacterModel& m_ = *model_;
  double hinge_mass_ = 0.0, hinge_radius_ = 0.0;
  std::set<std::string> removed_;
  std::map<std::string, int> body_index_;
  // body -> link carrying its frame, and that body's origin in that link's frame
  std::vector<int> body_link_;
  std::vector<Eigen::Vector3d> body_offset_;
};

ModelPtr CharacterModel::from_json(const Json& json, const std::string& where) { return ModelBuilder::build(json, where); }

ModelPtr ModelBuilder::build(const Json& json, const std::string& where) {
  ModelBuilder b(json, where);
  const Json& bodies = json["bodies"];
  for (std::size_t bi = 0; bi < bodies.size(); ++bi) b.add_body(bi);
  b.layout_dofs();
  b.collision_filter();
  b.named_bodies();
  return b.model_;
}

ModelBuilder::ModelBuilder(const Json& json, const std::string& where) : json_(json), where_(where) {
  if (!json.is_object()) throw UserError(where + ": the model is not a JSON object");
  m_.name_ = json.value("name", "character");
  if (!json.contains("bodies") || !json["bodies"].is_array() || json["bodies"].empty())
    throw UserError(where + ": bodies: missing or empty (a model needs at least a root body)");
  if (json.contains("hinge_link")) {
    hinge_mass_ = number(json["hinge_link"], "mass", 0.0, where + ": hinge_link");
    hinge_radius_ = number(json["hinge_link"], "radius", 0.0, where + ": hinge_link");
    if (hinge_mass_ < 0 || hinge_radius_ < 0) throw UserError(where + ": hinge_link: mass and radius must be ≥ 0");
  }
  if (json.contains("self_contact_friction")) {
    const double mu = number(json, "self_contact_friction", -1.0, where);
    if (!(mu >= 0)) throw UserError(where + ": self_contact_friction: " + show(json["self_contact_friction"]) + " is not ≥ 0");
    m_.self_contact_friction_ = mu;
  }
  m_.source_ = json;
  removed_ = removed_bodies(json, where);
}

void ModelBuilder::add_body(std::size_t bi) {
  const Json& b = json_["bodies"][bi];
  const std::string bw = where_ + ": " + base::json_path_index("bodies", bi);
  const std::string name = b.value("name", "");
  if (removed_.count(name)) return;
  if (name.empty()) throw UserError(bw + ".name: missing or empty");
  if (body_index_.count(name)) throw UserError(bw + ".name: \"" + name + "\" is used by an earlier body");
  int parent_body = -1;
  if (bi == 0) {
    if (b.contains("parent") && !b["parent"].is_null())
      throw UserError(bw + ".parent: the first body is the root and has no parent");
  } else {
    const std::string parent = b.value("parent", "");
    auto it = body_index_.find(parent);
    if (it == body_index_.end())
      throw UserError(bw + ".parent: \"" + parent + "\" is not an earlier body (list parents before children)");
    parent_body = it->second;
  }
  const Eigen::Vector3d pos = b.contains("pos") ? vec3(b["pos"], bw + ".pos") : Eigen::Vector3d::Zero();

  std::vector<Geom> geoms;
  if (b.contains("geoms")) {
    for (std::size_t gi = 0; gi < b["geoms"].size(); ++gi)
      geoms.push_back(parse_geom(b["geoms"][gi], bw + "." + base::json_path_index("geoms", gi)));
  }
  const double density = number(b, "density", 1000.0, bw);
  const double mass = number(b, "mass", -1.0, bw);
  if (b.contains("mass") && !(mass > 0)) throw UserError(bw + ".mass: " + show(b["mass"]) + " is not > 0");
  if (!(density > 0)) throw UserError(bw + ".density: " + show(b["density"]) + " is not > 0");
  const BodyMass body_mass = body_mass_properties(geoms, mass, density, bw);

  const int body_id = static_cast<int>(m_.bodies_.size());
  body_index_[name] = body_id;

  std::vector<Json> joints;
  if (b.contains("joints"))
    for (const Json& j : b["joints"]) joints.push_back(j);
  if (bi == 0 && !joints.empty())
    throw UserError(bw + ".joints: the root body moves by its free joint and takes no other joints");

  Carrier carrier;
  if (bi == 0) {
    Link root;
    root.name = name;
    root.joint = JointType::free;
    root.body = body_id;
    m_.links_.push_back(root);
    carrier.link = 0;
  } else if (joints.empty()) {
    carrier.link = body_link_[parent_body];
    carrier.origin_in_link = body_offset_[parent_body] + pos;
  } else {
    carrier = add_joint_chain(joints, parent_body, body_id, pos, bw);
  }
  merge_into_link(carrier, body_mass, std::move(geoms), body_id);
  Body body;
  body.name = name;
  body.link = carrier.link;
  body.offset = carrier.origin_in_link;
  m_.bodies_.push_back(body);
  body_link_.push_back(carrier.link);
  body_offset_.push_back(carrier.origin_in_link);
}

// One link per joint, each child of the previous; the anchor of the body frame moves along the chain.
Carrier ModelBuilder::add_joint_chain(const std::vector<Json>& joints, int parent_body, int body_id, const Eigen::Vector3d& pos,
                                      const std::string& bw) {
  int parent_link = body_link_[parent_body];
  Eigen::Vector3d prev_anchor_in_parent = body_offset_[parent_body] + pos;  // body origin in parent link frame
  Eigen::Vector3d prev_joint_pos = Eigen::Vector3d::Zero();                 // previous anchor in body frame
  for (std::size_t ji = 0; ji < joints.size(); ++ji) {
    const Json& j = joints[ji];
    const std::string jw = bw + "." + base::json_path_index("joints", ji);
    auto [link, anchor] = parse_joint(j, jw, m_);
    link.parent = parent_link;
    link.body = body_id;
    link.joint_pos = prev_anchor_in_parent + (anchor - prev_joint_pos);
    if (ji + 1 < joints.size()) {
      // Intermediate hinge link: a small sphere at the anchor (massless links destabilise
      // Bullet's contact solver; MuJoCo regularises the same way with joint armature).
      link.mass = hinge_mass_;
      link.inertia = Eigen::Matrix3d::Identity() * (0.4 * hinge_mass_ * hinge_radius_ * hinge_radius_);
    }
    m_.links_.push_back(link);
    parent_link = static_cast<int>(m_.links_.size()) - 1;
    prev_anchor_in_parent = Eigen::Vector3d::Zero();
    prev_joint_pos = anchor;
  }
  return {parent_link, -prev_joint_pos};
}

// Adds a body's mass and geoms to the link carrying it (inertia about the link COM, link frame).
void ModelBuilder::merge_into_link(const Carrier& carrier, const BodyMass& bm, std::vector<Geom> geoms, int body_id) {
  Link& link = m_.links_[carrier.link];
  const Eigen::Vector3d body_com = bm.mass > 0 ? Eigen::Vector3d(bm.moment / bm.mass) : Eigen::Vector3d::Zero();
  if (bm.mass > 0) {
    // Move body inertia from body origin to body COM, then combine with the link (parallel axis).
    const Eigen::Matrix3d Ib =
        bm.inertia_origin - bm.mass * (body_com.squaredNorm() * Eigen::Matrix3d::Identity() - body_com * body_com.transpose());
    const Eigen::Vector3d cb = carrier.origin_in_link + body_com;
    const double total = link.mass + bm.mass;
    const Eigen::Vector3d c = (link.mass * link.com + bm.mass * cb) / total;
    auto shift = [](double mass_kg, const Eigen::Vector3d& d) {
      return Eigen::Matrix3d(mass_kg * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()));
    };
    link.inertia = link.inertia + shift(link.mass, link.com - c) + Ib + shift(bm.mass, cb - c);
    link.com = c;
    link.mass = total;
  }
  for (Geom& g : geoms) {
    g.pos += carrier.origin_in_link;
    g.body = body_id;
    link.geoms.push_back(g);
  }
}

// DoF layout and the per-DoF vectors.
void ModelBuilder::layout_dofs() {
  CharacterModel& m = m_;
  int nq = 0, nv = 0;
  for (Link& l : m.links_) {
    l.q_index = nq;
    l.v_index = nv;
    l.nq = l.joint == JointType::free ? 7 : l.joint == JointType::spherical ? 4 : 1;
    l.nv = l.joint == JointType::free ? 6 : l.joint == JointType::spherical ? 3 : 1;
    nq += l.nq;
    nv += l.nv;
    m.total_mass_ += l.mass;
  }
  m.nq_ = nq;
  m.nv_ = nv;
  if (m.links_.size() < 2) throw UserError(where_ + ": bodies: the model has no joints");
  if (m.links_[0].mass <= 0) throw UserError(where_ + ": bodies[0]: the root body has no mass (give it geoms or a mass)");
  m.torque_limits_ = Eigen::VectorXd::Zero(nv);
  m.kp_ = Eigen::VectorXd::Zero(nv);
  m.kd_ = Eigen::VectorXd::Zero(nv);
  m.damping_ = Eigen::VectorXd::Zero(nv);
  m.stiffness_ = Eigen::VectorXd::Zero(nv);
  m.armature_ = Eigen::VectorXd::Zero(nv);
  for (const Link& l : m.links_) {
    if (l.joint == JointType::free) continue;
    m.torque_limits_.segment(l.v_index, l.nv) = l.torque_limit_nm.head(l.nv);
    m.kp_.segment(l.v_index, l.nv).setConstant(l.kp);
    m.kd_.segment(l.v_index, l.nv).setConstant(l.kd);
    m.damping_.segment(l.v_index, l.nv).setConstant(l.damping);
    m.stiffness_.segment(l.v_index, l.nv).setConstant(l.stiffness);
    m.armature_.segment(l.v_index, l.nv).setConstant(l.armature);
    m.has_armature_ = m.has_armature_ || l.armature > 0;
  }
}

// Self-collision filter: every pair except a link with itself, its parent, links of the same
// body (massless hinge chains) and pairs the file excludes.
void ModelBuilder::collision_filter() {
  CharacterModel& m = m_;
  const std::size_t L = m.links_.size();
  m.collide_.assign(L * L, 1);
  auto forbid = [&](std::size_t a, std::size_t b) { m.collide_[a * L + b] = m.collide_[b * L + a] = 0; };
  for (std::size_t a = 0; a < L; ++a) {
    forbid(a, a);
    // Walk up through massless links so a body never collides with its parent body.
    int p = m.links_[a].parent;
    while (p >= 0) {
      forbid(a, static_cast<std::size_t>(p));
      if (!m.links_[p].geoms.empty()) break;
      p = m.links_[p].parent;
    }
  }
  if (!json_.contains("contact_exclude")) return;
  for (std::size_t i = 0; i < json_["contact_exclude"].size(); ++i) {
    const Json& pair = json_["contact_exclude"][i];
    const std::string pw = where_ + ": " + base::json_path_index("contact_exclude", i);
    if (!pair.is_array() || pair.size() != 2) throw UserError(pw + ": " + show(pair) + " is not a pair of body names");
    const int a = m.find_body(pair[0].get<std::string>()), b = m.find_body(pair[1].get<std::string>());
    if ((a < 0 && removed_.count(pair[0].get<std::string>())) || (b < 0 && removed_.count(pair[1].get<std::string>()))) continue;
    if (a < 0 || b < 0) throw UserError(pw + ": " + show(pair) + " names an unknown body");
    forbid(m.bodies_[a].link, m.bodies_[b].link);
  }
}

// The head, torso and end effectors the file names, and the standing pose.
void ModelBuilder::named_bodies() {
  CharacterModel& m = m_;
  auto body_by_key = [&](const char* key, int fallback) {
    if (!json_.contains(key)) return fallback;
    const int id = m.find_body(json_[key].get<std::string>());
    if (id < 0) throw UserError(where_ + ": " + key + ": \"" + json_[key].get<std::string>() + "\" is not a body");
    return id;
  };
  m.head_ = body_by_key("head", 0);
  m.torso_ = body_by_key("torso", 0);
  if (json_.contains("end_effectors")) {
    for (const Json& e : json_["end_effectors"]) {
      if (removed_.count(e.get<std::string>())) continue;
      const int id = m.find_body(e.get<std::string>());
      if (id < 0) throw UserError(where_ + ": end_effectors: \"" + e.get<std::string>() + "\" is not a body");
      m.end_effectors_.push_back(id);
    }
  }
  m.standing_ = m.neutral();
  m.standing_(2) = number(json_, "standing_root_height", 0.0, where_);
}

int CharacterModel::find_body(const std::string& name) const {
  for (std::size_t i = 0; i < bodies_.size(); ++i)
    if (bodies_[i].name == name) return static_cast<int>(i);
  return -1;
}

int CharacterModel::find_link(const std::string& name) const {
  for (std::size_t i = 0; i < links_.size(); ++i)
    if (links_[i].name == name) return static_cast<int>(i);
  return -1;
}

const Link& CharacterModel::link(const std::string& name) const {
  const int i = find_link(name);
  if (i < 0) throw UserError("model " + name_ + " has no joint \"" + name + "\"");
  return links_[static_cast<std::size_t>(i)];
}

Eigen::VectorXd CharacterModel::neutral() const {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(nq_);
  for (const Link& l : links_) {
    if (l.joint == JointType::free) q(l.q_index + 3) = 1.0;
    if (l.joint == JointType::spherical) q(l.q_index) = 1.0;
  }
  return q;
}

std::filesystem::path shipped_models_dir() {
  if (const char* env = std::getenv("PODIUM_SIM_MODELS")) return env;
  return PODIUM_SIM_MODELS_DIR;
}

ModelPtr edit_model(const ModelPtr& model, const ModelEdits& edits) {
  if (edits.empty()) return model;
  Json json = model->source();
  Json& remove = json["remove"];
  if (!remove.is_array()) remove = Json::array();
  for (const std::string& name : edits.remove) remove.push_back(name);
  for (const auto& [joint, keys] : edits.joints) {
    if (!keys.is_object())
      throw UserError("sim: edits of joint \"" + joint + "\": " + show(keys) + " is not an object of model-file keys");
    bool found = false;
    for (Json& body : json["bodies"]) {
      if (!body.contains("joints")) continue;
      for (Json& j : body["joints"]) {
        if (j.value("name", "") != joint) continue;
        j.update(keys);
        found = true;
      }
    }
    if (!found) throw UserError("sim: edits: \"" + joint + "\" is not a joint of model " + model->name());
  }
  if (edits.mass_scale != 1.0) {
    if (!(edits.mass_scale > 0.0) || !std::isfinite(edits.mass_scale))
      throw UserError("sim: edits: mass_scale " + show(edits.mass_scale) + " is not a finite number > 0");
    for (Json& body : json["bodies"]) {
      if (body.contains("mass") && body["mass"].is_number()) body["mass"] = body["mass"].get<double>() * edits.mass_scale;
      else body["density"] = body.value("density", 1000.0) * edits.mass_scale;
    }
    if (json.contains("hinge_link") && json["hinge_link"].contains("mass") && json["hinge_link"]["mass"].is_number())
      json["hinge_link"]["mass"] = json["hinge_link"]["mass"].get<double>() * edits.mass_scale;
  }
  return CharacterModel::from_json(json, "model " + model->name() + " with edits");
}

ModelPtr load_model(const std::filesystem::path& path) {
  return CharacterModel::from_json(base::read_json_file(path), "model " + path.filename().string());
}

ModelPtr load_shipped_model(const std::string& name) {
  const auto path = shipped_models_dir() / (name + ".json");
  if (!std::filesystem::exists(path))
    throw UserError("sim: model \"" + name + "\" is not shipped (looked for " + path.string() + ")");
  return load_model(path);
}

}  // namespace podium::sim
