#include "podium/character/imitation.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "podium/base/error.h"
#include "podium/character/frames.h"
#include "podium/character/starts.h"
#include "podium/sim/dynamics.h"

namespace podium::character {

using sim::JointType;
using sim::Link;

// DeepMimic §5: r_I = w_p r_p + w_v r_v + w_e r_e + w_c r_c, each r = exp(−k · squared error).
ImitationTerms imitation_terms(const TrackingErrors& e, const ImitationWeights& w) {
  ImitationTerms t;
  t.pose = exp_kernel(e.pose, w.pose_scale);
  t.velocity = exp_kernel(e.velocity, w.velocity_scale);
  t.end_effector = exp_kernel(e.end_effector, w.end_effector_scale);
  t.com = exp_kernel(e.com, w.com_scale);
  t.total = w.pose * t.pose + w.velocity * t.velocity + w.end_effector * t.end_effector + w.com * t.com;
  return t;
}

namespace {

std::shared_ptr<const Clip> checked(std::shared_ptr<const Clip> clip) {
  if (!clip || !clip->model) throw base::UserError("imitation: the reference clip has no model");
  if (clip->size() < 2)
    throw base::UserError("imitation: the reference clip has " + std::to_string(clip->size()) + " frames, not ≥ 2");
  return clip;
}

// Σ_j ŵ_j ‖q̂_j ⊖ q_j‖² and the unweighted Σ_j ‖q̂_j ⊖ q_j‖²: the rotation angle between the two
// orientations of every ball joint and the root, the angle difference of every hinge.
struct PoseSums {
  double weighted = 0.0, unweighted = 0.0;
};
PoseSums pose_error(const sim::CharacterModel& model, const Eigen::VectorXd& q, const Eigen::VectorXd& ref,
                    const std::vector<double>& weight) {
  PoseSums out;
  for (std::size_t j = 0; j < model.links().size(); ++j) {
    const Link& l = model.links()[j];
    double e = 0.0;
    if (l.joint == JointType::revolute) {
      const double d = ref(l.q_index) - q(l.q_index);
      e = d * d;
    } else {
      const int i = l.joint == JointType::free ? l.q_index + 3 : l.q_index;
      e = log_map(quat_at(ref, i).normalized().conjugate() * quat_at(q, i).normalized()).squaredNorm();
    }
    out.weighted += weight[j] * e, out.unweighted += e;
  }
  return out;
}

// Σ_j ŵ_j ‖q̇̂_j − q̇_j‖² over every rotational DoF: the root's ω (not its linear velocity) and the joints.
double velocity_error(const sim::CharacterModel& model, const Eigen::VectorXd& qd, const Eigen::VectorXd& ref,
                      const std::vector<double>& weight) {
  double sum = 0.0;
  for (std::size_t j = 0; j < model.links().size(); ++j) {
    const Link& l = model.links()[j];
    const int n = l.joint == JointType::free ? 3 : l.nv;
    sum += weight[j] * (ref.segment(l.v_index, n) - qd.segment(l.v_index, n)).squaredNorm();
  }
  return sum;
}

// DeepMimic's DiffWeight per joint of its humanoid3d.txt (the free joint: "root").
double deepmimic_joint_weight(const std::string& joint) {
  static const std::map<std::string, double> weights = {
      {"root", 1.0},        {"chest", 0.5},          {"neck", 0.3},          {"right_hip", 0.5},   {"right_knee", 0.3},
      {"right_ankle", 0.2}, {"right_shoulder", 0.3}, {"right_elbow", 0.2},   {"right_wrist", 0.0}, {"left_hip", 0.5},
      {"left_knee", 0.3},   {"left_ankle", 0.2},     {"left_shoulder", 0.3}, {"left_elbow", 0.2},  {"left_wrist", 0.0}};
  const auto it = weights.find(joint);
  return it == weights.end() ? 1.0 : it->second;
}

// ŵ per link, normalised to sum 1 (DeepMimic's CalcJointWeights).
std::vector<double> normalised_joint_weights(const sim::CharacterModel& model, bool deepmimic) {
  std::vector<double> w;
  for (const Link& l : model.links())
    w.push_back(deepmimic ? deepmimic_joint_weight(l.joint == JointType::free ? "root" : l.name) : 1.0);
  double sum = 0.0;
  for (double v : w) sum += v;
  if (!(sum > 0.0)) throw base::UserError("imitation: the joint weights of model " + model.name() + " sum to 0");
  for (double& v : w) v /= sum;
  return w;
}

// An end effector's position from its root (d after forward kinematics), in the root's heading
// frame, its height above the (flat) ground in place of the vertical offset (DeepMimic's
// CalcRewardImitate).
Eigen::Vector3d from_root(const sim::CharacterData& d, const Eigen::Vector3d& p) {
  const Eigen::Matrix3d heading = heading_rotation(heading_yaw(d.links[0].R));
  Eigen::Vector3d rel = heading.transpose() * (p - d.links[0].p);
  rel.z() = p.z();
  return rel;
}

}  // namespace

ImitationReference::ImitationReference(std::shared_ptr<const Clip> clip, ImitationWeights weights)
    : clip_(checked(std::move(clip))),
      weights_(weights),
      joint_weight_(normalised_joint_weights(*clip_->model, weights_.deepmimic_joint_weights)),
      velocities_(clip_->velocities()),
      sim_(*clip_->model),
      ref_(*clip_->model) {}

std::size_t ImitationReference::frame_at(double t_s) const {
  const Clip& c = *clip_;
  const double T = c.duration_s();
  if (c.loop && T > 0) t_s = std::fmod(std::fmod(t_s, T) + T, T);
  const auto k = std::upper_bound(c.times_s.begin(), c.times_s.end(), t_s) - c.times_s.begin();
  return static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(k - 1, 0, static_cast<std::ptrdiff_t>(c.size()) - 1));
}

const Eigen::VectorXd& ImitationReference::velocity(double t_s) const { return velocities_[frame_at(t_s)]; }

double ImitationReference::phase(double t_s) const {
  const double T = clip_->duration_s();
  if (clip_->loop) return std::fmod(std::fmod(t_s, T) + T, T) / T;
  return std::clamp(t_s / T, 0.0, 1.0);
}

TrackingErrors ImitationReference::errors(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, double t_s) const {
  const sim::CharacterModel& model = *clip_->model;
  sim_.q = q, sim_.qd = qd;
  ref_.q = pose(t_s), ref_.qd = velocity(t_s);
  TrackingErrors e;
  const PoseSums pose_sums = pose_error(model, q, ref_.q, joint_weight_);
  e.pose = pose_sums.weighted;
  e.pose_rms_rad = std::sqrt(pose_sums.unweighted / static_cast<double>(model.links().size()));
  e.velocity = velocity_error(model, qd, ref_.qd, joint_weight_);
  sim::forward_kinematics(model, sim_);
  sim::forward_kinematics(model, ref_);
  for (int b : model.end_effector_bodies())
    e.end_effector += (from_root(ref_, sim::body_point(model, ref_, b, Eigen::Vector3d::Zero())) -
                       from_root(sim_, sim::body_point(model, sim_, b, Eigen::Vector3d::Zero())))
                          .squaredNorm();
  Eigen::Vector3d com, com_ref, vel;
  sim::center_of_mass(model, sim_, com, vel);
  sim::center_of_mass(model, ref_, com_ref, vel);
  e.com = (com_ref - com).squaredNorm();
  return e;
}

ImitationTerms ImitationReference::terms(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, double t_s) const {
  return imitation_terms(errors(q, qd, t_s), weights_);
}

TrackingErrors ImitationReference::errors(const CharacterEnv& env) const {
  return errors(env.world().data().q, env.world().data().qd, env.reference_time_s());
}

std::size_t ReferenceStateStart::draw_frame(const Clip& clip, base::Rng& rng) const {
  const int last = last_ < 0 ? static_cast<int>(clip.size()) - 1 : last_;
  if (first_ < 0 || last >= static_cast<int>(clip.size()) || first_ > last)
    throw base::UserError("imitation: reference start frames [" + std::to_string(first_) + ", " + std::to_string(last) +
                          "] are not within the clip's " + std::to_string(clip.size()) + " frames");
  return static_cast<std::size_t>(rng.integer(first_, last));
}

void ReferenceStateStart::begin(CharacterEnv& env, base::Rng& rng) const {
  const Clip* clip = env.reference();
  if (!clip) throw base::UserError("imitation: a reference start needs the env's reference clip");
  // The frame's own time: Clip::sample returns that frame exactly, ReferenceStart its velocity.
  ReferenceStart(noise_, false, clip->times_s[draw_frame(*clip, rng)]).begin(env, rng);
}

const char* to_string(Termination termination) {
  switch (termination) {
    case Termination::none:
      return "none";
    case Termination::fell:
      return "fell";
    case Termination::deviated:
      return "deviated";
  }
  return "?";
}

std::vector<int> fall_bodies_except(const sim::CharacterModel& model, const std::vector<std::string>& allowed) {
  std::vector<char> keep(model.bodies().size(), 1);
  for (const std::string& name : allowed) {
    const int b = model.find_body(name);
    if (b < 0) throw base::UserError("imitation: model " + model.name() + " has no body " + name + " (allowed on the ground)");
    keep[static_cast<std::size_t>(b)] = 0;
  }
  std::vector<int> out;
  for (std::size_t b = 0; b < keep.size(); ++b)
    if (keep[b]) out.push_back(static_cast<int>(b));
  return out;
}

Termination early_termination(const EarlyTermination& rule, const sim::Observation& features, const TrackingErrors& errors,
                              const ImitationTerms& terms) {
  for (int b : rule.fall_bodies)
    if (features.touches(b, sim::Contact::Partner::ground)) return Termination::fell;
  if (std::sqrt(errors.com) >= rule.max_com_deviation_m) return Termination::deviated;
  if (rule.min_pose_reward > 0 && terms.pose <= rule.min_pose_reward) return Termination::deviated;
  return Termination::none;
}

void ReferencePhase::write(const CharacterEnv& env, std::span<double> out) const {
  out[0] = reference_->phase(env.reference_time_s());
}

}  // namespace podium::character
