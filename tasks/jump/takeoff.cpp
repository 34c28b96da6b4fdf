#include "takeoff.h"

#include <algorithm>
#include <array>
#include <cstring>
#include <fstream>
#include <limits>

#include "podium/base/error.h"
#include "podium/base/json.h"
#include "podium/character/frames.h"
#include "podium/sim/dynamics.h"

namespace podium::tasks::jump {

using character::exp_map;
using character::quat_at;
using character::set_quat;
using sim::JointType;

namespace {

int quat_slot(const sim::Link& l) { return l.joint == JointType::free ? l.q_index + 3 : l.q_index; }

// Lowest world z of each body's geoms (needs forward kinematics in `d`).
std::vector<double> lowest_by_body(const sim::CharacterModel& model, const sim::CharacterData& d) {
  std::vector<double> low(model.bodies().size(), std::numeric_limits<double>::infinity());
  for (std::size_t li = 0; li < model.links().size(); ++li) {
    const auto& R = d.links[li].R;
    const auto& p = d.links[li].p;
    for (const sim::Geom& g : model.links()[li].geoms) {
      const Eigen::Vector3d c = p + R * g.pos;
      const Eigen::Matrix3d Rg = R * g.rot.toRotationMatrix();
      double z = c.z();
      if (g.type == sim::ShapeType::sphere) z -= g.radius;
      if (g.type == sim::ShapeType::capsule) z -= std::abs(Rg(2, 2)) * g.half_length + g.radius;
      if (g.type == sim::ShapeType::box) z -= Rg.row(2).cwiseAbs().dot(g.half_extents);
      low[g.body] = std::min(low[g.body], z);
    }
  }
  return low;
}

Eigen::Vector3d vec3(const base::Json& j, const std::string& where) {
  if (!j.is_array() || j.size() != 3 || !j[0].is_number() || !j[1].is_number() || !j[2].is_number())
    throw base::UserError(where + ": not an array of 3 numbers");
  return {j[0].get<double>(), j[1].get<double>(), j[2].get<double>()};
}

// One .npy float64 vector from `in` (format 1.0 or 2.0, little-endian, C order).
std::vector<double> read_npy_vector(std::istream& in, const std::string& where) {
  char magic[8];
  if (!in.read(magic, 8) || std::memcmp(magic, "\x93NUMPY", 6) != 0) throw base::UserError(where + ": not a .npy array");
  std::uint32_t header_len = 0;
  unsigned char b[4] = {0, 0, 0, 0};
  in.read(reinterpret_cast<char*>(b), magic[6] == 1 ? 2 : 4);
  header_len = b[0] | (b[1] << 8) | (b[2] << 16) | (static_cast<std::uint32_t>(b[3]) << 24);
  std::string header(header_len, '\0');
  in.read(header.data(), header_len);
  if (header.find("'<f8'") == std::string::npos || header.find("'fortran_order': False") == std::string::npos)
    throw base::UserError(where + ": expected a little-endian float64 array in C order, header " + header);
  const auto open = header.find("'shape': (");
  if (open == std::string::npos) throw base::UserError(where + ": no shape in header " + header);
  const std::size_t n = std::stoul(header.substr(open + 10));
  std::vector<double> v(n);
  if (!in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(n * sizeof(double))))
    throw base::UserError(where + ": ends before its " + std::to_string(n) + " values");
  return v;
}

}  // namespace

Eigen::VectorXd TakeoffState::qd() const {
  const Eigen::Matrix3d Rt = quat_at(q, 3).toRotationMatrix().transpose();
  Eigen::VectorXd out(6 + joint_qd.size());
  out << Rt * root_omega, Rt * root_velocity, joint_qd;
  return out;
}

std::filesystem::path shipped_takeoff_path() { return std::filesystem::path(PODIUM_JUMP_DATA_DIR) / "takeoff_run.json"; }

TakeoffState placed_at_takeoff(const sim::CharacterModel& model, TakeoffState s, int takeoff_foot) {
  if (s.q.size() != model.nq() || s.joint_qd.size() != model.nv() - 6)
    throw base::UserError("jump take-off: a state of " + std::to_string(s.q.size()) + " positions and " +
                          std::to_string(s.joint_qd.size()) + " joint rates for model " + model.name() + " (nq " +
                          std::to_string(model.nq()) + ", nv − 6 = " + std::to_string(model.nv() - 6) + ")");
  const Eigen::Quaterniond root = quat_at(s.q, 3).normalized();
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(-character::heading_yaw(root.toRotationMatrix()), Eigen::Vector3d::UnitZ()));
  set_quat(s.q, 3, turn * root);
  s.root_omega = turn * s.root_omega;
  s.root_velocity = turn * s.root_velocity;
  s.q(0) = s.q(1) = 0.0;
  sim::CharacterData d(model);
  d.q = s.q;
  sim::forward_kinematics(model, d);
  const std::vector<double> low = lowest_by_body(model, d);
  s.q(2) -= low.at(takeoff_foot);
  for (std::size_t b = 0; b < low.size(); ++b)
    if (static_cast<int>(b) != takeoff_foot && low[b] - low[takeoff_foot] < 0.005)
      throw base::UserError("jump take-off: with " + model.bodies()[takeoff_foot].name + " on the ground, " +
                            model.bodies()[b].name + " is " + std::to_string(low[b] - low[takeoff_foot]) +
                            " m above it (need ≥ 0.005: one-leg support)");
  return s;
}

TakeoffState read_takeoff_json(const sim::ModelPtr& model, const std::filesystem::path& path, int takeoff_foot) {
  const std::string where = path.string();
  const base::Json j = base::read_json_file(path);
  TakeoffState s;
  s.q = model->neutral();
  s.joint_qd = Eigen::VectorXd::Zero(model->nv() - 6);
  try {
    if (!j.is_object()) throw base::UserError(where + ": not a JSON object");
    static const std::array<std::string, 6> known = {"description",           "joints",          "root_rotation", "root_velocity",
                                                     "root_angular_velocity", "joint_velocities"};
    for (const auto& [key, value] : j.items())
      if (std::find(known.begin(), known.end(), key) == known.end()) throw base::UserError(where + ": " + key + ": unknown key");
    set_quat(s.q, 3, exp_map(vec3(j.at("root_rotation"), where + ": root_rotation")));
    s.root_velocity = vec3(j.at("root_velocity"), where + ": root_velocity");
    s.root_omega = vec3(j.at("root_angular_velocity"), where + ": root_angular_velocity");
    const auto each_joint = [&](const char* key, auto&& write) {
      if (!j.contains(key)) return;
      for (const auto& [name, value] : j.at(key).items()) {
        const int li = model->find_link(name);
        const std::string at = where + ": " + base::json_path_join(key, name);
        if (li <= 0) throw base::UserError(at + ": model " + model->name() + " has no such joint");
        const sim::Link& l = model->links()[li];
        if (l.joint == JointType::revolute && !value.is_number()) throw base::UserError(at + ": a hinge takes one number");
        write(l, value, at);
      }
    };
    each_joint("joints", [&](const sim::Link& l, const base::Json& v, const std::string& at) {
      if (l.joint == JointType::revolute) s.q(l.q_index) = v.get<double>();
      else set_quat(s.q, quat_slot(l), exp_map(vec3(v, at)));
    });
    each_joint("joint_velocities", [&](const sim::Link& l, const base::Json& v, const std::string& at) {
      if (l.joint == JointType::revolute) s.joint_qd(l.v_index - 6) = v.get<double>();
      else s.joint_qd.segment<3>(l.v_index - 6) = vec3(v, at);
    });
  } catch (const base::Json::exception& e) {
    throw base::UserError(where + ": " + e.what());
  }
  return placed_at_takeoff(*model, s, takeoff_foot);
}

TakeoffState read_takeoff_npy(const sim::ModelPtr& model, const std::filesystem::path& path, int takeoff_foot) {
  const std::string where = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw base::UserError(where + ": cannot open");
  const std::vector<double> pose = read_npy_vector(in, where), vel = read_npy_vector(in, where);
  if (static_cast<int>(pose.size()) != model->nq() || pose.size() != vel.size())
    throw base::UserError(where + ": pose of " + std::to_string(pose.size()) + " and velocity of " + std::to_string(vel.size()) +
                          " values; model " + model->name() + " has nq " + std::to_string(model->nq()) +
                          " (DeepMimic's joint order)");
  // DeepMimic is y-up: every vector, world or joint-local, changes frame by C (read_deepmimic_clip).
  const Eigen::Quaterniond& C = character::yup_to_zup();
  TakeoffState s;
  s.q = Eigen::Map<const Eigen::VectorXd>(pose.data(), model->nq());
  s.joint_qd = Eigen::VectorXd::Zero(model->nv() - 6);
  s.q.head<3>() = C * Eigen::Vector3d(s.q.head<3>());
  s.root_velocity = C * Eigen::Vector3d(vel[0], vel[1], vel[2]);
  s.root_omega = C * Eigen::Vector3d(vel[3], vel[4], vel[5]);
  for (const sim::Link& l : model->links()) {
    if (l.joint == JointType::free) {
      set_quat(s.q, 3, C * quat_at(s.q, 3).normalized() * C.conjugate());
    } else if (l.joint == JointType::spherical) {
      set_quat(s.q, l.q_index, C * quat_at(s.q, l.q_index).normalized() * C.conjugate());
      // The velocity vector has the pose's layout: a ball joint's ω sits in its quaternion's slots.
      s.joint_qd.segment<3>(l.v_index - 6) = C * Eigen::Vector3d(vel[l.q_index], vel[l.q_index + 1], vel[l.q_index + 2]);
    } else {
      s.joint_qd(l.v_index - 6) = vel[l.q_index];
    }
  }
  return placed_at_takeoff(*model, s, takeoff_foot);
}

std::size_t takeoff_frame(const sim::CharacterModel& model, std::span<const Eigen::VectorXd> poses, int takeoff_foot) {
  sim::CharacterData d(model);
  std::vector<double> foot(poses.size()), others(poses.size());
  std::size_t apex = 0;  // the frame of the highest root: the captured jump's flight
  for (std::size_t f = 0; f < poses.size(); ++f) {
    d.q = poses[f];
    sim::forward_kinematics(model, d);
    const std::vector<double> low = lowest_by_body(model, d);
    foot[f] = low.at(static_cast<std::size_t>(takeoff_foot));
    others[f] = std::numeric_limits<double>::infinity();
    for (std::size_t b = 0; b < low.size(); ++b)
      if (static_cast<int>(b) != takeoff_foot) others[f] = std::min(others[f], low[b]);
    if (poses[f](2) > poses[apex](2)) apex = f;
  }
  double ground = std::numeric_limits<double>::infinity();  // before the flight (a landing may be lower: a mat)
  for (std::size_t f = 0; f <= apex; ++f) ground = std::min({ground, foot[f], others[f]});
  constexpr double kContact = 0.03;  // m above the motion's lowest point before its flight
  // Before the apex: a captured run goes on past its take-off (the curved sprint lands and walks
  // out, its last single support is after the landing).
  for (std::size_t f = apex + 1; f-- > 0;)
    if (foot[f] - ground < kContact && others[f] - ground >= kContact) return f;
  throw base::UserError("jump take-off: in the captured motion, " + model.bodies()[static_cast<std::size_t>(takeoff_foot)].name +
                        " is never alone on the ground before the root's highest frame");
}

TakeoffState takeoff_from_clip(const character::Clip& clip, int takeoff_foot) {
  const sim::CharacterModel& model = *clip.model;
  const std::size_t takeoff = takeoff_frame(model, clip.poses, takeoff_foot);
  const Eigen::VectorXd qd = clip.velocities()[takeoff];
  TakeoffState s;
  s.q = clip.poses[takeoff];
  const Eigen::Matrix3d R = quat_at(s.q, 3).toRotationMatrix();
  s.root_omega = R * qd.head<3>();
  s.root_velocity = R * qd.segment<3>(3);
  s.joint_qd = qd.tail(model.nv() - 6);
  return placed_at_takeoff(model, s, takeoff_foot);
}

std::vector<TakeoffFeature> takeoff_features(JumpKind kind) {
  if (kind == JumpKind::high_jump)
    return {{"approach_angle", "rad", -0.5, 2.5},
            {"root_omega_x", "rad/s", -3.0, 3.0},
            {"root_omega_y", "rad/s", -3.0, 3.0},
            {"lateral_speed", "m/s", 0.0, 2.5}};
  return {{"root_omega_x", "rad/s", -4.0, 4.0}, {"root_omega_y", "rad/s", -4.0, 4.0}, {"root_omega_z", "rad/s", -4.0, 4.0}};
}

TakeoffState apply_takeoff_features(JumpKind kind, const TakeoffState& reference, std::span<const double> x) {
  const std::size_t n = takeoff_features(kind).size();
  if (x.size() != n)
    throw base::UserError(std::string("jump take-off: ") + jump_kind_name(kind) + " explores " + std::to_string(n) +
                          " features, got " + std::to_string(x.size()));
  TakeoffState s = reference;
  if (kind == JumpKind::high_jump) {
    s.root_omega = Eigen::Vector3d(x[1], x[2], kHighJumpTurnRate);
    s.root_velocity.y() = x[3];
  } else {
    s.root_omega = Eigen::Vector3d(x[0], x[1], x[2]);
  }
  return s;
}

double approach_angle(JumpKind kind, std::span<const double> x, double fallback) {
  return kind == JumpKind::high_jump && !x.empty() ? x[0] : fallback;
}

void TakeoffStart::begin(character::CharacterEnv& env, base::Rng&) const { env.world().reset(state_.q, qd_); }

}  // namespace podium::tasks::jump
