#include "podium/learn/pose_data.h"

#include <algorithm>
#include <cmath>

#include "podium/base/error.h"

namespace podium::learn {

void PoseDataset::append(const PoseDataset& other) {
  if (other.dof_names != dof_names || other.condition_names != condition_names)
    throw base::UserError("pose dataset: cannot append a dataset with other DoFs or conditions");
  poses.insert(poses.end(), other.poses.begin(), other.poses.end());
  conditions.insert(conditions.end(), other.conditions.begin(), other.conditions.end());
}

PoseDataset read_pose_dataset(const std::filesystem::path& path) {
  const base::Json j = base::read_json_file(path);
  const std::string where = path.string();
  PoseDataset d;
  try {
    d.dof_names = j.at("dof_names").get<std::vector<std::string>>();
    d.lower = j.at("lower").get<std::vector<double>>();
    d.upper = j.at("upper").get<std::vector<double>>();
    d.condition_names = j.value("condition_names", std::vector<std::string>{});
    d.poses = j.at("poses").get<std::vector<std::vector<double>>>();
    d.conditions = j.value("conditions", std::vector<std::vector<double>>{});
  } catch (const base::Json::exception& e) {
    throw base::UserError(where + ": " + e.what());
  }
  const std::size_t n = d.dof_names.size();
  if (d.lower.size() != n || d.upper.size() != n)
    throw base::UserError(where + ": lower/upper have " + std::to_string(d.lower.size()) + "/" +
                          std::to_string(d.upper.size()) + " entries but dof_names has " + std::to_string(n));
  for (std::size_t k = 0; k < n; ++k)
    if (!(d.lower[k] < d.upper[k]))
      throw base::UserError(where + ": " + d.dof_names[k] + ": limits [" + std::to_string(d.lower[k]) + ", " +
                            std::to_string(d.upper[k]) + "] are not an interval");
  for (std::size_t i = 0; i < d.poses.size(); ++i)
    if (d.poses[i].size() != n)
      throw base::UserError(where + ": poses[" + std::to_string(i) + "] has " + std::to_string(d.poses[i].size()) +
                            " values, expected " + std::to_string(n));
  if (!d.condition_names.empty() && d.conditions.size() != d.poses.size())
    throw base::UserError(where + ": " + std::to_string(d.conditions.size()) + " conditions for " +
                          std::to_string(d.poses.size()) + " poses");
  for (std::size_t i = 0; i < d.conditions.size(); ++i)
    if (d.conditions[i].size() != d.condition_names.size())
      throw base::UserError(where + ": conditions[" + std::to_string(i) + "] has " +
                            std::to_string(d.conditions[i].size()) + " values, expected " +
                            std::to_string(d.condition_names.size()));
  return d;
}

std::vector<DeepMimicJoint> read_deepmimic_character(const std::filesystem::path& path) {
  const base::Json j = base::read_json_file(path);
  std::vector<DeepMimicJoint> joints;
  const auto& list = j.at("Skeleton").at("Joints");
  for (std::size_t i = 0; i < list.size(); ++i) {
    const auto& js = list[i];
    DeepMimicJoint joint;
    joint.name = js.at("Name").get<std::string>();
    const std::string type = js.at("Type").get<std::string>();
    int dofs = 0;
    if (type == "none") {
      joint.type = DeepMimicJoint::Type::root;
    } else if (type == "spherical") {
      joint.type = DeepMimicJoint::Type::spherical;
      dofs = 3;
    } else if (type == "revolute") {
      joint.type = DeepMimicJoint::Type::revolute;
      dofs = 1;
    } else if (type == "fixed") {
      joint.type = DeepMimicJoint::Type::fixed;
    } else {
      throw base::UserError(path.string() + ": Skeleton.Joints[" + std::to_string(i) + "].Type: \"" + type +
                            "\" is not one of none, spherical, revolute, fixed");
    }
    for (int k = 0; k < dofs; ++k) {
      joint.lower.push_back(js.at("LimLow" + std::to_string(k)).get<double>());
      joint.upper.push_back(js.at("LimHigh" + std::to_string(k)).get<double>());
    }
    joints.push_back(std::move(joint));
  }
  return joints;
}

MotionClip read_motion_clip(const std::filesystem::path& path) {
  const base::Json j = base::read_json_file(path);
  MotionClip clip;
  const auto& loop = j.at("Loop");
  clip.loop = loop.is_boolean() ? loop.get<bool>() : loop.get<std::string>() != "none";
  clip.frames = j.at("Frames").get<std::vector<std::vector<double>>>();
  return clip;
}

namespace {

// Unit quaternion (w, x, y, z) → exponential map (axis · angle), angle in [0, π].
void quat_to_expmap(double w, double x, double y, double z, double out[3]) {
  const double n = std::sqrt(w * w + x * x + y * y + z * z);
  w /= n, x /= n, y /= n, z /= n;
  if (w < 0) w = -w, x = -x, y = -y, z = -z;  // q and −q are the same rotation: take the short one
  const double s = std::sqrt(x * x + y * y + z * z);
  const double angle = 2.0 * std::atan2(s, w);
  const double k = s < 1e-12 ? 2.0 : angle / s;
  out[0] = k * x, out[1] = k * y, out[2] = k * z;
}

// Rotates the vector v by the unit quaternion (w, x, y, z).
void rotate(const double q[4], const double v[3], double out[3]) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const double tx = 2 * (y * v[2] - z * v[1]), ty = 2 * (z * v[0] - x * v[2]), tz = 2 * (x * v[1] - y * v[0]);
  out[0] = v[0] + w * tx + (y * tz - z * ty);
  out[1] = v[1] + w * ty + (z * tx - x * tz);
  out[2] = v[2] + w * tz + (x * ty - y * tx);
}

}  // namespace

PoseDataset clip_to_poses(const MotionClip& clip, const std::vector<DeepMimicJoint>& joints, const std::string& where) {
  PoseDataset d;
  std::size_t values = 8;  // dt, root position, root quaternion
  for (const auto& j : joints) {
    if (j.type == DeepMimicJoint::Type::spherical) {
      for (const char* axis : {"_x", "_y", "_z"}) d.dof_names.push_back(j.name + axis);
      values += 4;
    } else if (j.type == DeepMimicJoint::Type::revolute) {
      d.dof_names.push_back(j.name);
      values += 1;
    }
    if (j.type == DeepMimicJoint::Type::spherical || j.type == DeepMimicJoint::Type::revolute) {
      d.lower.insert(d.lower.end(), j.lower.begin(), j.lower.end());
      d.upper.insert(d.upper.end(), j.upper.begin(), j.upper.end());
    }
  }
  d.condition_names = {"root_height_m", "root_pitch_rad", "root_roll_rad"};
  for (std::size_t f = 0; f < clip.frames.size(); ++f) {
    const auto& fr = clip.frames[f];
    if (fr.size() != values)
      throw base::UserError(where + ": Frames[" + std::to_string(f) + "] has " + std::to_string(fr.size()) +
                            " values, the character needs " + std::to_string(values));
    std::vector<double> pose;
    std::size_t at = 8;
    for (const auto& j : joints) {
      if (j.type == DeepMimicJoint::Type::spherical) {
        double e[3];
        quat_to_expmap(fr[at], fr[at + 1], fr[at + 2], fr[at + 3], e);
        for (int k = 0; k < 3; ++k) pose.push_back(e[k]);
        at += 4;
      } else if (j.type == DeepMimicJoint::Type::revolute) {
        pose.push_back(fr[at]);
        at += 1;
      }
    }
    for (std::size_t k = 0; k < pose.size(); ++k) pose[k] = std::clamp(pose[k], d.lower[k], d.upper[k]);
    // DeepMimic is y-up with the character facing +x: the root's up axis (local y) in the world
    // gives the torso pitch (tilt about z) and roll (tilt about x).
    const double q[4] = {fr[4], fr[5], fr[6], fr[7]};
    const double up_local[3] = {0, 1, 0};
    double up[3];
    rotate(q, up_local, up);
    d.conditions.push_back({fr[2], std::atan2(up[0], up[1]), std::atan2(up[2], up[1])});
    d.poses.push_back(std::move(pose));
  }
  return d;
}

}  // namespace podium::learn
