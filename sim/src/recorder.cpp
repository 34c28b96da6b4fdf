#include "podium/sim/recorder.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <numbers>

#include "podium/base/error.h"
#include "podium/base/json.h"

namespace podium::sim {

using base::Json;

namespace {

// Rounds to 5 decimals (0.01 mm, 1e-5 rad): enough for replay, keeps files compact.
double r5(double x) { return std::round(x * 1e5) / 1e5; }

Json shape_json(const Geom& g) {
  Json j = {{"body", g.body},
            {"pos", {r5(g.pos.x()), r5(g.pos.y()), r5(g.pos.z())}},
            {"quat", {r5(g.rot.w()), r5(g.rot.x()), r5(g.rot.y()), r5(g.rot.z())}}};
  switch (g.type) {
    case ShapeType::capsule:
      j["type"] = "capsule";
      j["radius"] = g.radius;
      j["half_length"] = g.half_length;
      break;
    case ShapeType::sphere:
      j["type"] = "sphere";
      j["radius"] = g.radius;
      break;
    case ShapeType::box:
      j["type"] = "box";
      j["half_extents"] = {g.half_extents.x(), g.half_extents.y(), g.half_extents.z()};
      break;
  }
  return j;
}

Json vec_json(const Eigen::Vector3d& v) { return {r5(v.x()), r5(v.y()), r5(v.z())}; }
Json quat_json(const Eigen::Quaterniond& q) { return {r5(q.w()), r5(q.x()), r5(q.y()), r5(q.z())}; }

// Props and the boxes the terrain regions are made of, in world coordinates (what a viewer draws).
Json props_json(const TerrainConfig& config) {
  Json props = Json::array();
  for (const BoxProp& b : config.boxes)
    props.push_back({{"name", b.name},
                     {"type", "box"},
                     {"kind", b.kind.empty() ? "box" : b.kind},
                     {"pos", vec_json(b.center)},
                     {"quat", quat_json(b.rotation.normalized())},
                     {"half_extents", vec_json(b.half_extents)},
                     {"friction", b.friction}});
  return props;
}

Json terrain_json(const TerrainConfig& config) {
  static const char* kinds[] = {"flat", "rough", "slope"};
  const Terrain terrain(config);
  Json regions = Json::array(), pieces = Json::array();
  for (const TerrainRegion& r : config.regions)
    regions.push_back(
        {{"kind", kinds[static_cast<int>(r.kind)]}, {"min", {r.min.x(), r.min.y()}}, {"max", {r.max.x(), r.max.y()}}});
  for (const TerrainPiece& p : terrain.pieces())
    pieces.push_back({{"region", p.region},
                      {"type", "box"},
                      {"pos", vec_json(p.center)},
                      {"quat", quat_json(p.rotation)},
                      {"half_extents", vec_json(p.half_extents)}});
  return {{"regions", regions}, {"pieces", pieces}};
}

std::ofstream open_out(const std::filesystem::path& path) {
  std::ofstream out(path);
  if (!out) throw base::RuntimeError("sim: cannot write " + path.string());
  return out;
}

// ZXY Euler angles (degrees) of R = Rz(z) Rx(x) Ry(y), BVH's common "Zrotation Xrotation Yrotation".
Eigen::Vector3d euler_zxy_deg(const Eigen::Matrix3d& R) {
  const double x = std::asin(std::clamp(R(2, 1), -1.0, 1.0));
  const double z = std::atan2(-R(0, 1), R(1, 1));
  const double y = std::atan2(-R(2, 0), R(2, 2));
  return Eigen::Vector3d(z, x, y) * (180.0 / std::numbers::pi);
}

}  // namespace

void Recorder::record(World& world) {
  const CharacterData& d = world.data();
  Frame f;
  f.time_s = world.time_s();
  f.q = d.q;
  f.qd = d.qd;
  terrain_ = world.terrain().config();
  for (std::size_t i = 0; i < model_->links().size(); ++i) {
    const Eigen::Quaterniond r(d.links[i].R);
    Eigen::Matrix<double, 7, 1> pose;
    pose << d.links[i].p, r.w(), r.x(), r.y(), r.z();
    f.links.push_back(pose);
  }
  const Observation o = world.observe();
  f.com = o.com;
  f.body_contacts = o.body_contacts;
  frames_.push_back(std::move(f));
}

void write_trajectory(const Recorder& recorder, const std::filesystem::path& path) {
  const CharacterModel& m = recorder.model();
  std::ofstream out = open_out(path);
  Json links = Json::array();
  for (const Link& l : m.links()) {
    Json shapes = Json::array();
    for (const Geom& g : l.geoms) shapes.push_back(shape_json(g));
    links.push_back({{"name", l.name}, {"parent", l.parent}, {"shapes", shapes}});
  }
  Json bodies = Json::array();
  for (const Body& b : m.bodies()) bodies.push_back(b.name);
  Json joints = Json::array();
  for (const Link& l : m.links())
    joints.push_back({{"name", l.name},
                      {"type", l.joint == JointType::free       ? "free"
                               : l.joint == JointType::revolute ? "revolute"
                                                                : "spherical"},
                      {"q_index", l.q_index}});
  out << Json{{"format", "podium-trajectory"},
              {"version", 2},
              {"model", m.name()},
              {"links", links},
              {"bodies", bodies},
              {"joints", joints},
              {"ground", true},
              {"props", props_json(recorder.terrain())},
              {"terrain", terrain_json(recorder.terrain())}}
             .dump()
      << '\n';
  for (const Frame& f : recorder.frames()) {
    Json q = Json::array(), qd = Json::array(), poses = Json::array(), contacts = Json::array();
    for (int i = 0; i < f.q.size(); ++i) q.push_back(r5(f.q(i)));
    for (int i = 0; i < f.qd.size(); ++i) qd.push_back(r5(f.qd(i)));
    for (const auto& p : f.links) poses.push_back({r5(p(0)), r5(p(1)), r5(p(2)), r5(p(3)), r5(p(4)), r5(p(5)), r5(p(6))});
    for (std::size_t b = 0; b < f.body_contacts.size(); ++b)
      if (f.body_contacts[b]) contacts.push_back(b);
    out << Json{{"t", r5(f.time_s)},
                {"root", {q[0], q[1], q[2], q[3], q[4], q[5], q[6]}},
                {"q", q},
                {"qd", qd},
                {"links", poses},
                {"com", {r5(f.com.x()), r5(f.com.y()), r5(f.com.z())}},
                {"contacts", contacts}}
               .dump()
        << '\n';
  }
  if (!out) throw base::RuntimeError("sim: writing " + path.string() + " failed");
}

void write_bvh(const Recorder& recorder, const std::filesystem::path& path, double frame_time_s) {
  const CharacterModel& m = recorder.model();
  const auto& links = m.links();
  std::ofstream out = open_out(path);
  out << std::fixed << std::setprecision(6);
  // Children lists for the hierarchy.
  std::vector<std::vector<int>> children(links.size());
  for (std::size_t i = 1; i < links.size(); ++i) children[links[i].parent].push_back(static_cast<int>(i));
  out << "HIERARCHY\n";
  auto write_joint = [&](auto&& self, int i, int depth) -> void {
    const std::string pad(static_cast<std::size_t>(depth) * 2, ' ');
    const Eigen::Vector3d off = i == 0 ? Eigen::Vector3d::Zero() : links[i].joint_pos;
    out << pad << (i == 0 ? "ROOT " : "JOINT ") << links[i].name << "\n" << pad << "{\n";
    out << pad << "  OFFSET " << off.x() << ' ' << off.y() << ' ' << off.z() << "\n";
    out << pad << "  CHANNELS " << (i == 0 ? "6 Xposition Yposition Zposition " : "3 ") << "Zrotation Xrotation Yrotation\n";
    for (int c : children[i]) self(self, c, depth + 1);
    if (children[i].empty()) out << pad << "  End Site\n" << pad << "  {\n" << pad << "    OFFSET 0 0 0\n" << pad << "  }\n";
    out << pad << "}\n";
  };
  write_joint(write_joint, 0, 0);
  out << "MOTION\nFrames: " << recorder.frames().size() << "\nFrame Time: " << frame_time_s << "\n";
  for (const Frame& f : recorder.frames()) {
    for (std::size_t i = 0; i < links.size(); ++i) {
      // Local rotation = parent world rotationᵀ · own world rotation.
      const Eigen::Quaterniond own(f.links[i](3), f.links[i](4), f.links[i](5), f.links[i](6));
      Eigen::Matrix3d local = own.toRotationMatrix();
      if (links[i].parent >= 0) {
        const auto& p = f.links[links[i].parent];
        local = Eigen::Quaterniond(p(3), p(4), p(5), p(6)).toRotationMatrix().transpose() * local;
      } else {
        out << f.links[0](0) << ' ' << f.links[0](1) << ' ' << f.links[0](2) << ' ';
      }
      const Eigen::Vector3d e = euler_zxy_deg(local);
      out << e.x() << ' ' << e.y() << ' ' << e.z() << (i + 1 < links.size() ? ' ' : '\n');
    }
  }
  if (!out) throw base::RuntimeError("sim: writing " + path.string() + " failed");
}

}  // namespace podium::sim
