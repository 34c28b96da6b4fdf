// The Start phase's keyframed crouch starts (sprint seed §3.1; ours: the seed's race-video
// references do not exist here). See crouch_start.h for the motion's parts.
#include "crouch_start.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "podium/base/error.h"
#include "podium/sim/data.h"
#include "podium/sim/dynamics.h"

namespace podium::tasks::sprint {
namespace {

using Vec2 = Eigen::Vector2d;  // (x, z) in the sagittal plane

constexpr double kGravity = 9.81;
constexpr double kClearance = 0.0;  // between a sole or a hand and what it rests on at the set, m (touching)
constexpr double kDeg = std::numbers::pi / 180.0;

// A sagittal pose: the root's x, z and every joint's rotation about +y (q-ready); sides: 0 the
// front-block leg's side, 1 the rear-block leg's.
enum Index : int {
  kX,
  kZ,
  kPitch,
  kChest,
  kNeck,
  kHip,
  kKnee = kHip + 2,
  kAnkle = kKnee + 2,
  kShoulder = kAnkle + 2,
  kElbow = kShoulder + 2,
  kSize = kElbow + 2
};
using Pose = Eigen::Matrix<double, kSize, 1>;

// A keyframe in degrees: the pelvis's and chest's forward pitch (the chest's on the pelvis's), the
// neck's; the thigh's and the upper arm's world angle from hanging (+: forward); knee flexion;
// ankle plantarflexion; elbow flexion.
struct Key {
  double t = 0.0;
  double pitch = 0.0, chest = 0.0, neck = 0.0;
  std::array<double, 2> hip{}, knee{}, ankle{}, arm{};
  double elbow = 0.0;
};

Pose key_pose(const Key& k) {
  Pose p = Pose::Zero();
  p(kPitch) = k.pitch * kDeg, p(kChest) = k.chest * kDeg, p(kNeck) = k.neck * kDeg;
  for (int s = 0; s < 2; ++s) {
    p(kHip + s) = -k.hip[s] * kDeg - p(kPitch);  // forward is a negative turn about +y
    p(kKnee + s) = k.knee[s] * kDeg;
    p(kAnkle + s) = k.ankle[s] * kDeg;
    p(kShoulder + s) = -k.arm[s] * kDeg - p(kPitch) - p(kChest);
    p(kElbow + s) = -k.elbow * kDeg;
  }
  return p;
}

struct Joints {
  int chest = -1, neck = -1;
  std::array<int, 2> hip{}, knee{}, ankle{}, shoulder{}, elbow{};
  std::array<int, 2> foot{}, hand{};  // bodies
};

int link_of(const sim::CharacterModel& m, const std::string& name, sim::JointType type) {
  const int l = m.find_link(name);
  if (l < 0 || m.links()[l].joint != type)
    throw base::UserError("sprint crouch start: model " + m.name() + " needs a " +
                          (type == sim::JointType::revolute ? "revolute" : "spherical") + " joint " + name);
  if (type == sim::JointType::revolute && std::abs(std::abs(m.links()[l].axis.y()) - 1.0) > 1e-9)
    throw base::UserError("sprint crouch start: model " + m.name() + ": joint " + name + " must turn about the lateral axis");
  return l;
}

Joints joints_of(const sim::CharacterModel& m, Foot front) {
  using sim::JointType;
  Joints j;
  j.chest = link_of(m, "chest", JointType::spherical);
  j.neck = link_of(m, "neck", JointType::spherical);
  for (int s = 0; s < 2; ++s) {
    const std::string side = (s == 0) == (front == Foot::left) ? "left_" : "right_";
    j.hip[s] = link_of(m, side + "hip", JointType::spherical);
    j.knee[s] = link_of(m, side + "knee", JointType::revolute);
    j.ankle[s] = link_of(m, side + "ankle", JointType::spherical);
    j.shoulder[s] = link_of(m, side + "shoulder", JointType::spherical);
    j.elbow[s] = link_of(m, side + "elbow", JointType::revolute);
    j.foot[s] = m.find_body(side + "foot");
    j.hand[s] = m.find_body(side + "hand");
    if (j.foot[s] < 0 || j.hand[s] < 0)
      throw base::UserError("sprint crouch start: model " + m.name() + " needs bodies " + side + "foot and " + side + "hand");
  }
  return j;
}

void set_turn(const sim::CharacterModel& m, Eigen::VectorXd& q, int link, double angle) {
  const sim::Link& l = m.links()[link];
  if (l.joint == sim::JointType::revolute) q(l.q_index) = angle / l.axis.y();
  else q.segment<4>(l.q_index) << std::cos(0.5 * angle), 0.0, std::sin(0.5 * angle), 0.0;  // wxyz about +y
}

Eigen::VectorXd to_q(const sim::CharacterModel& m, const Joints& j, const Pose& p) {
  Eigen::VectorXd q = m.neutral();
  q(0) = p(kX), q(1) = 0.0, q(2) = p(kZ);
  q.segment<4>(3) << std::cos(0.5 * p(kPitch)), 0.0, std::sin(0.5 * p(kPitch)), 0.0;
  set_turn(m, q, j.chest, p(kChest));
  set_turn(m, q, j.neck, p(kNeck));
  for (int s = 0; s < 2; ++s) {
    set_turn(m, q, j.hip[s], p(kHip + s));
    set_turn(m, q, j.knee[s], p(kKnee + s));
    set_turn(m, q, j.ankle[s], p(kAnkle + s));
    set_turn(m, q, j.shoulder[s], p(kShoulder + s));
    set_turn(m, q, j.elbow[s], p(kElbow + s));
  }
  return q;
}

// The first geom of `body` on its link (the foot's box, the hand's sphere).
const sim::Geom& geom_of(const sim::CharacterModel& m, int body, sim::ShapeType type) {
  for (const sim::Geom& g : m.links()[m.bodies()[body].link].geoms)
    if (g.body == body && g.type == type) return g;
  throw base::UserError("sprint crouch start: model " + m.name() + ": body " + m.bodies()[body].name + " has no " +
                        (type == sim::ShapeType::box ? "box" : "sphere") + " geom");
}

Vec2 xz(const Eigen::Vector3d& v) { return {v.x(), v.z()}; }
// A rotation about +y by a applied to (x, z).
Vec2 turn(double a, const Vec2& v) {
  return {v.x() * std::cos(a) + v.y() * std::sin(a), -v.x() * std::sin(a) + v.y() * std::cos(a)};
}

// Everything the keyframes are solved against.
struct Setting {
  sim::ModelPtr model;
  Joints joints;
  double thigh = 0.0, shin = 0.0;   // hip → knee, knee → ankle, m
  Vec2 sole;                        // the sole's centre in the foot's link frame
  std::array<Vec2, 2> block_ankle;  // where each side's ankle sits on its block
  std::array<double, 2> block_angle{};
};

// The thigh's world turn and the knee's turn that put the ankle at `ankle` from the hip, knee
// forward (a planar two-link solve; beyond reach, the nearest reachable).
std::pair<double, double> leg_solve(const Setting& st, const Vec2& hip, const Vec2& ankle) {
  const Vec2 d = ankle - hip;
  const double a = st.thigh, b = st.shin;
  const double r = std::clamp(d.norm(), std::abs(a - b) + 1e-6, a + b - 1e-6);
  const double knee = std::numbers::pi - std::acos(std::clamp((a * a + b * b - r * r) / (2 * a * b), -1.0, 1.0));
  const double toward = std::atan2(-d.x(), -d.y());
  const double beta = std::acos(std::clamp((a * a + r * r - b * b) / (2 * a * r), -1.0, 1.0));
  return {toward - beta, knee};
}

// Forward kinematics of a pose.
sim::CharacterData kinematics(const Setting& st, const Pose& p) {
  sim::CharacterData d(*st.model);
  d.q = to_q(*st.model, st.joints, p);
  sim::forward_kinematics(*st.model, d);
  return d;
}

// Side s's foot on its block: hip and knee solved, the foot turned to the block's face.
void foot_on_block(const Setting& st, Pose& p, int s) {
  const sim::CharacterData d = kinematics(st, p);
  const Vec2 hip = xz(d.links[st.joints.hip[s]].p);
  const auto [thigh, knee] = leg_solve(st, hip, st.block_ankle[s]);
  p(kHip + s) = thigh - p(kPitch);
  p(kKnee + s) = knee;
  p(kAnkle + s) = st.block_angle[s] - thigh - knee;
}

Setting make_setting(const sim::ModelPtr& model, Foot front, const std::vector<BlockSpec>& blocks) {
  Setting st{model, joints_of(*model, front), 0.0, 0.0, {}, {}, {}};
  const sim::CharacterModel& m = *model;
  st.thigh = m.links()[st.joints.knee[0]].joint_pos.norm();
  st.shin = m.links()[st.joints.ankle[0]].joint_pos.norm();
  const sim::Geom& foot = geom_of(m, st.joints.foot[0], sim::ShapeType::box);
  st.sole = xz(foot.pos + foot.rot * Eigen::Vector3d(0.0, 0.0, -foot.half_extents.z()));
  if (blocks.size() != 2) throw base::UserError("sprint crouch start: needs two blocks (front, rear)");
  const std::vector<sim::BoxProp> props = starting_blocks(blocks);
  for (int s = 0; s < 2; ++s) {
    const sim::BoxProp& b = props[static_cast<std::size_t>(s)];
    const Eigen::Vector3d normal = b.rotation * Eigen::Vector3d::UnitZ();
    const Vec2 face = xz(b.center + normal * (b.half_extents.z() + kClearance));
    st.block_angle[s] = blocks[static_cast<std::size_t>(s)].angle_rad;  // the sole lies on the face
    st.block_ankle[s] = face - turn(st.block_angle[s], st.sole);
  }
  return st;
}

// The set: the hands on the ground 2 cm behind the line, each foot on its block.
Pose set_pose(const Setting& st, const Key& key) {
  Pose p = key_pose(key);
  const sim::CharacterData d = kinematics(st, p);  // root at the origin
  const sim::Geom& hand = geom_of(*st.model, st.joints.hand[0], sim::ShapeType::sphere);
  const sim::LinkData& carrier = d.links[static_cast<std::size_t>(st.model->bodies()[st.joints.hand[0]].link)];
  const Eigen::Vector3d centre = carrier.p + carrier.R * hand.pos;
  p(kX) = -(hand.radius + 0.02) - centre.x();
  p(kZ) = hand.radius + kClearance - centre.z();
  const sim::CharacterData placed = kinematics(st, p);
  for (int s = 0; s < 2; ++s) {
    if ((st.block_ankle[s] - xz(placed.links[st.joints.hip[s]].p)).norm() > st.thigh + st.shin)
      throw base::UserError("sprint crouch start: the set position cannot reach the blocks (check the blocks' x)");
    foot_on_block(st, p, s);
  }
  return p;
}

// The landing: the rear-block foot flat on the ground, its sole's centre at landing_x.
Pose landing_pose(const Setting& st, const Key& key, double landing_x) {
  Pose p = key_pose(key);
  p(kAnkle + 1) = -(p(kPitch) + p(kHip + 1) + p(kKnee + 1));
  const sim::CharacterData d = kinematics(st, p);
  const sim::Geom& foot = geom_of(*st.model, st.joints.foot[1], sim::ShapeType::box);
  const Eigen::Matrix3d& R = d.links[st.joints.ankle[1]].R;
  const Eigen::Vector3d at = d.links[st.joints.ankle[1]].p;
  double low = std::numeric_limits<double>::infinity();
  for (int c = 0; c < 8; ++c) {
    const Eigen::Vector3d corner((c & 1 ? 1 : -1) * foot.half_extents.x(), (c & 2 ? 1 : -1) * foot.half_extents.y(),
                                 (c & 4 ? 1 : -1) * foot.half_extents.z());
    low = std::min(low, (at + R * (foot.pos + foot.rot * corner)).z());
  }
  const Eigen::Vector3d sole = at + R * Eigen::Vector3d(st.sole.x(), 0.0, st.sole.y());
  p(kX) = landing_x - sole.x();
  p(kZ) = 0.001 - low;
  return p;
}

double smoothstep(double s) { return s * s * (3.0 - 2.0 * s); }

Pose eased(const std::vector<std::pair<double, Pose>>& keys, double t) {
  if (t <= keys.front().first) return keys.front().second;
  for (std::size_t k = 1; k < keys.size(); ++k)
    if (t <= keys[k].first) {
      const double s = smoothstep((t - keys[k - 1].first) / (keys[k].first - keys[k - 1].first));
      return keys[k - 1].second + s * (keys[k].second - keys[k - 1].second);
    }
  return keys.back().second;
}

// The keyframes for a left foot in front (side 0: the front block's leg and arm).
// The trunk rises before the arms swing, so that the hands clear the ground; the rear leg folds
// (heel up) as it swings, so that its foot clears it.
std::array<Key, 7> keyframes(ArmAction arms) {
  const double elbow = arms == ArmAction::bent ? 90.0 : 20.0;
  std::array<Key, 7> k;
  k[0] = {0.0, 85.0, 55.0, -30.0, {}, {}, {}, {-25.0, -25.0}, 3.0};   // set (legs solved; hands behind the shoulders)
  k[1] = {0.0, 80.0, 48.0, -27.0, {}, {}, {}, {-25.0, -25.0}, 3.0};   // hands off (legs solved)
  k[2] = {0.0, 70.0, 35.0, -20.0, {}, {}, {}, {40.0, -50.0}, elbow};  // rear foot off (legs solved)
  k[3] = {0.0, 60.0, 25.0, -15.0, {0.0, 10.0}, {0.0, 120.0}, {0.0, -10.0}, {55.0, -55.0}, elbow};  // mid-swing
  k[4] = {0.0, 50.0, 15.0, -10.0, {0.0, 60.0}, {0.0, 110.0}, {0.0, -10.0}, {70.0, -60.0}, elbow};  // take-off
  k[5] = {0.0, 45.0, 10.0, 0.0, {-35.0, 45.0}, {80.0, 70.0}, {20.0, 0.0}, {50.0, -40.0}, elbow};   // mid-flight
  k[6] = {0.0, 42.0, 8.0, 0.0, {-30.0, 30.0}, {100.0, 65.0}, {20.0, 0.0}, {45.0, -40.0}, elbow};   // landing
  return k;
}

}  // namespace

const char* to_string(ArmAction arms) { return arms == ArmAction::bent ? "bent" : "straight"; }

std::vector<BlockSpec> blocks_for(Foot front, const std::vector<BlockSpec>& left_front) {
  std::vector<BlockSpec> blocks = left_front;
  if (front == Foot::right)
    for (BlockSpec& b : blocks) b.y_m = -b.y_m;
  return blocks;
}

character::Clip crouch_start_clip(const sim::ModelPtr& model, const CrouchStartSpec& spec, double control_hz,
                                  const std::vector<BlockSpec>& left_front) {
  if (!(control_hz > 0.0) || !(spec.rear_off_s > 0.0) || !(spec.block_time_s > spec.rear_off_s))
    throw base::UserError("sprint crouch start: needs control_hz > 0 and 0 < rear_off_s < block_time_s");
  // Built for a left front foot, mirrored for a right one.
  const Setting st = make_setting(model, Foot::left, left_front);
  const std::array<Key, 7> k = keyframes(spec.arms);
  const double t1 = spec.rear_off_s, t2 = spec.block_time_s;
  const Pose set = set_pose(st, k[0]);
  // The block phase: the root from rest to the take-off at constant acceleration.
  const Pose off = key_pose(k[4]);
  const Vec2 hip_rel = xz(kinematics(st, off).links[st.joints.hip[0]].p) - Vec2(off(kX), off(kZ));
  const double reach = 0.96 * (st.thigh + st.shin);
  const Vec2 p0(set(kX), set(kZ));
  const Vec2 p2 = st.block_ankle[0] + reach * Vec2(std::sin(spec.takeoff_lean_rad), std::cos(spec.takeoff_lean_rad)) - hip_rel;
  const Vec2 v2 = 2.0 * (p2 - p0) / t2;
  const Pose land = landing_pose(st, k[6], spec.landing_x_m);
  const Vec2 p3(land(kX), land(kZ));
  if (!(p3.x() > p2.x() + 0.05))
    throw base::UserError("sprint crouch start: landing_x_m " + std::to_string(spec.landing_x_m) +
                          " leaves no flight after the take-off (the root leaves the blocks at x = " + std::to_string(p2.x()) +
                          ")");
  // The flight: ballistic from the take-off's vertical speed down to the landing's root height
  // (rounded up to whole control periods, the vertical speed adjusted to it), the horizontal
  // distance made up by a constant acceleration.
  const double rise = v2.y() * v2.y() - 2.0 * kGravity * (p3.y() - p2.y());
  if (rise < 0.0)
    throw base::UserError("sprint crouch start: the landing's root height " + std::to_string(p3.y()) +
                          " m is above the flight's apex (take-off at " + std::to_string(p2.y()) + " m)");
  const double descent = (v2.y() + std::sqrt(rise)) / kGravity;
  const int frames = static_cast<int>(std::ceil((t2 + descent) * control_hz - 1e-9));
  const double t3 = frames / control_hz, flight = t3 - t2;
  const double ax = (p3.x() - p2.x() - v2.x() * flight) / (flight * flight);
  const double vz = (p3.y() - p2.y()) / flight + 0.5 * kGravity * flight;
  const auto root = [&](double t) -> Vec2 {
    if (t <= t2) return p0 + (p2 - p0) * (t / t2) * (t / t2);
    const double u = t - t2;
    return {p2.x() + v2.x() * u + ax * u * u, p2.y() + vz * u - 0.5 * kGravity * u * u};
  };
  std::vector<std::pair<double, Pose>> keys = {{0.0, set},
                                               {0.4 * t1, key_pose(k[1])},
                                               {t1, key_pose(k[2])},
                                               {t1 + 0.4 * (t2 - t1), key_pose(k[3])},
                                               {t2, off},
                                               {t2 + 0.5 * flight, key_pose(k[5])},
                                               {t3, land}};
  const auto at = [&](double t) {
    Pose p = eased(keys, t);
    const Vec2 r = root(t);
    p(kX) = r.x(), p(kZ) = r.y();
    if (t <= t2) foot_on_block(st, p, 0);
    if (t <= t1) foot_on_block(st, p, 1);
    return p;
  };
  keys[2].second = at(t1);  // the rear leg leaves its block where the solve left it
  keys[4].second = at(t2);  // and the front one
  character::Clip clip{model, {}, {}, false};
  for (int f = 0; f <= frames; ++f) {
    const double t = f == frames ? t3 : f / control_hz;
    clip.times_s.push_back(t);
    clip.poses.push_back(to_q(*model, st.joints, f == frames ? land : at(t)));
  }
  return spec.front == Foot::left ? clip : character::mirror(clip);
}

std::vector<CrouchStart> crouch_start_set(const sim::ModelPtr& model, double control_hz, const CrouchStartSpec& base,
                                          const std::vector<BlockSpec>& left_front) {
  std::vector<CrouchStart> set;
  for (const Foot front : {Foot::left, Foot::right})
    for (const ArmAction arms : {ArmAction::straight, ArmAction::bent}) {
      CrouchStart s;
      s.spec = base;
      s.spec.front = front, s.spec.arms = arms;
      s.name = std::string(front == Foot::left ? "left_" : "right_") + to_string(arms);
      s.blocks = blocks_for(front, left_front);
      s.clip = std::make_shared<const character::Clip>(crouch_start_clip(model, s.spec, control_hz, left_front));
      set.push_back(std::move(s));
    }
  return set;
}

std::vector<StartReference> crouch_start_references(const sim::ModelPtr& model, double control_hz, const StartPreset& start) {
  CrouchStartSpec base;
  base.landing_x_m = start.landing_x_m;
  const std::vector<CrouchStart> set = crouch_start_set(model, control_hz, base);
  return {set.begin(), set.end()};
}

}  // namespace podium::tasks::sprint
