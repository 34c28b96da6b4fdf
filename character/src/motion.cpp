#include "podium/character/motion.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "podium/base/error.h"
#include "podium/base/json.h"
#include "podium/character/frames.h"

namespace podium::character {

using sim::JointType;
using sim::Link;

namespace {

// Index of the first quaternion entry of a rotational link (root: after its position).
int quat_index(const Link& l) { return l.joint == JointType::free ? l.q_index + 3 : l.q_index; }

Eigen::VectorXd interpolate(const sim::CharacterModel& model, const Eigen::VectorXd& a, const Eigen::VectorXd& b, double s) {
  Eigen::VectorXd q = a + s * (b - a);  // root position and hinge angles
  for (const Link& l : model.links()) {
    if (l.joint == JointType::revolute) continue;
    const int i = quat_index(l);
    set_quat(q, i, quat_at(a, i).normalized().slerp(s, quat_at(b, i).normalized()));
  }
  return q;
}

void check_model(const Clip& clip) {
  if (!clip.model) throw base::UserError("motion clip: has no model");
}

}  // namespace

Eigen::VectorXd Clip::sample(double t) const {
  check_model(*this);
  if (poses.empty()) throw base::UserError("motion clip: has no frames");
  if (poses.size() == 1) return poses.front();
  const double T = duration_s();
  if (loop && T > 0) t = std::fmod(std::fmod(t, T) + T, T);
  t = std::clamp(t, 0.0, T);
  const std::size_t k = std::upper_bound(times_s.begin(), times_s.end(), t) - times_s.begin();  // first frame after t
  if (k >= poses.size()) return poses.back();
  const double s = (t - times_s[k - 1]) / (times_s[k] - times_s[k - 1]);
  if (s == 0.0) return poses[k - 1];
  return interpolate(*model, poses[k - 1], poses[k], s);
}

std::vector<Eigen::VectorXd> Clip::velocities() const {
  check_model(*this);
  std::vector<Eigen::VectorXd> out;
  if (poses.size() < 2) return std::vector<Eigen::VectorXd>(poses.size(), Eigen::VectorXd::Zero(model->nv()));
  for (std::size_t f = 0; f < poses.size(); ++f) {
    const std::size_t a = f + 1 < poses.size() ? f : f - 1, b = a + 1;
    const double dt = times_s[b] - times_s[a];
    const Eigen::VectorXd& qa = poses[a];
    const Eigen::VectorXd& qb = poses[b];
    Eigen::VectorXd qd = Eigen::VectorXd::Zero(model->nv());
    for (const Link& l : model->links()) {
      if (l.joint == JointType::revolute) {
        qd(l.v_index) = (qb(l.q_index) - qa(l.q_index)) / dt;
        continue;
      }
      const int i = quat_index(l);
      const Eigen::Quaterniond ra = quat_at(qa, i).normalized();
      // Body-frame ω: q_b = q_a ⊗ exp(ω dt), as sim::integrate advances rotations.
      qd.segment<3>(l.v_index) = log_map(ra.conjugate() * quat_at(qb, i).normalized()) / dt;
      if (l.joint == JointType::free)
        qd.segment<3>(l.v_index + 3) =
            ra.toRotationMatrix().transpose() * (qb.segment<3>(l.q_index) - qa.segment<3>(l.q_index)) / dt;
    }
    out.push_back(qd);
  }
  return out;
}

Clip resample(const Clip& clip, double dt_s) {
  check_model(clip);
  if (!(dt_s > 0)) throw base::UserError("motion clip: resample interval " + std::to_string(dt_s) + " s is not > 0");
  Clip out{clip.model, {}, {}, clip.loop};
  const double T = clip.duration_s();
  const long n = static_cast<long>(std::floor(T / dt_s + 1e-9));
  for (long k = 0; k <= n; ++k) {
    const double t = static_cast<double>(k) * dt_s;
    out.times_s.push_back(t);
    out.poses.push_back(clip.sample(t));
  }
  return out;
}

Clip retime(const Clip& clip, double kappa) {
  if (!(kappa > 0)) throw base::UserError("motion clip: retiming factor κ " + std::to_string(kappa) + " is not > 0");
  Clip slowed = clip;
  for (double& t : slowed.times_s) t /= kappa;
  return slowed;
}

Eigen::VectorXd mirror_pose(const sim::CharacterModel& model, const Eigen::VectorXd& q) {
  // The reflection M = diag(1, −1, 1): positions p ↦ Mp, rotations R ↦ MRM, i.e. quaternion
  // (w, x, y, z) ↦ (w, −x, y, −z); a hinge about a by θ becomes a hinge about −Ma by θ.
  // Every link frame is parallel to the world at q = 0 (model.h), so this holds per joint.
  const Eigen::Vector3d m(1.0, -1.0, 1.0);
  Eigen::VectorXd out = q;
  for (std::size_t li = 0; li < model.links().size(); ++li) {
    const Link& l = model.links()[li];
    if (l.joint == JointType::free) {
      out(l.q_index + 1) = -q(l.q_index + 1);
      const int i = quat_index(l);
      out(i + 1) = -q(i + 1), out(i + 3) = -q(i + 3);
      continue;
    }
    std::string partner = l.name;
    if (auto p = partner.find("left"); p != std::string::npos) {
      partner.replace(p, 4, "right");
    } else if (auto r = partner.find("right"); r != std::string::npos) {
      partner.replace(r, 5, "left");
    }
    const int pi = model.find_link(partner);
    if (pi < 0) throw base::UserError("mirror: model " + model.name() + " has no joint " + partner + " to mirror " + l.name);
    const Link& p = model.links()[pi];
    if (p.joint != l.joint) throw base::UserError("mirror: joints " + l.name + " and " + partner + " differ in type");
    if (l.joint == JointType::revolute) {
      const double sign = p.axis.dot(-(m.asDiagonal() * l.axis));
      if (std::abs(std::abs(sign) - 1.0) > 1e-6)
        throw base::UserError("mirror: the axis of " + partner + " is not the mirrored axis of " + l.name);
      out(p.q_index) = (sign > 0 ? 1.0 : -1.0) * q(l.q_index);
    } else {
      out(p.q_index) = q(l.q_index);
      out(p.q_index + 1) = -q(l.q_index + 1);
      out(p.q_index + 2) = q(l.q_index + 2);
      out(p.q_index + 3) = -q(l.q_index + 3);
    }
  }
  return out;
}

Clip mirror(const Clip& clip) {
  check_model(clip);
  Clip out = clip;
  for (auto& q : out.poses) q = mirror_pose(*clip.model, q);
  return out;
}

Clip read_deepmimic_clip(const sim::ModelPtr& model, const std::filesystem::path& path) {
  const base::Json src = base::read_json_file(path);
  const std::string where = path.string();
  if (!src.contains("Frames") || !src["Frames"].is_array()) throw base::UserError(where + ": Frames: missing or not an array");
  Clip clip{model, {}, {}, false};
  if (src.contains("Loop")) {
    const auto& loop = src["Loop"];
    clip.loop = loop.is_boolean() ? loop.get<bool>() : (loop.is_string() && loop.get<std::string>() != "none");
  }
  const std::size_t width = 1 + static_cast<std::size_t>(model->nq());  // dt + q
  const Eigen::Quaterniond& c = yup_to_zup();
  double t = 0.0;
  for (std::size_t f = 0; f < src["Frames"].size(); ++f) {
    const base::Json& fr = src["Frames"][f];
    const std::string fw = where + ": " + base::json_path_index("Frames", f);
    if (!fr.is_array() || fr.size() != width)
      throw base::UserError(fw + ": has " + std::to_string(fr.is_array() ? fr.size() : 0) + " numbers but model " +
                            model->name() + " needs " + std::to_string(width) + " (dt + nq)");
    Eigen::VectorXd q(model->nq());
    for (int k = 0; k < model->nq(); ++k) {
      if (!fr[k + 1].is_number()) throw base::UserError(fw + "[" + std::to_string(k + 1) + "]: not a number");
      q(k) = fr[k + 1].get<double>();
    }
    q.head<3>() = c * Eigen::Vector3d(q.head<3>());
    for (const Link& l : model->links()) {
      if (l.joint == JointType::revolute) continue;
      const int i = quat_index(l);
      set_quat(q, i, c * quat_at(q, i).normalized() * c.conjugate());  // R' = C R Cᵀ
    }
    clip.times_s.push_back(t);
    clip.poses.push_back(q);
    const double dt = fr[0].is_number() ? fr[0].get<double>() : -1.0;
    if (!(dt > 0) && f + 1 < src["Frames"].size())
      throw base::UserError(fw + "[0]: frame duration " + std::to_string(dt) + " is not > 0");
    t += dt;
  }
  return clip;
}

Clip clip_from_recording(const sim::Recorder& recorder, const sim::ModelPtr& model) {
  if (!model || model->name() != recorder.model().name() || model->nq() != recorder.model().nq())
    throw base::UserError("motion clip: the recording is of model " + recorder.model().name() + ", not of the model given");
  Clip clip{model, {}, {}, false};
  const auto& frames = recorder.frames();
  for (const auto& f : frames) {
    clip.times_s.push_back(f.time_s - frames.front().time_s);
    clip.poses.push_back(f.q);
  }
  return clip;
}

}  // namespace podium::character
