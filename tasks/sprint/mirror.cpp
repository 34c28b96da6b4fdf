// The mirror M and r_mirror (sprint seed §3.2 "Learn motion symmetry").
#include "mirror.h"

#include <cmath>
#include <string>

#include "podium/base/error.h"

namespace podium::tasks::sprint {
namespace {

std::string twin_name(const std::string& name) {
  if (name.rfind("left_", 0) == 0) return "right_" + name.substr(5);
  if (name.rfind("right_", 0) == 0) return "left_" + name.substr(6);
  return name;
}

// (w, x, y, z) ↦ (w, −x, y, −z): the rotation P R P, P = diag(1, −1, 1).
void mirror_quat(const Eigen::VectorXd& from, int i, Eigen::VectorXd& to, int j) {
  to(j) = from(i);
  to(j + 1) = -from(i + 1);
  to(j + 2) = from(i + 2);
  to(j + 3) = -from(i + 3);
}

// The angle of the rotation a⁻¹b between two unit quaternions at a[i..], b[i..]: 2·atan2(‖v‖, |w|)
// (exactly 0 for equal ones, unlike acos of the dot product).
double quat_angle(const Eigen::VectorXd& a, const Eigen::VectorXd& b, int i) {
  const Eigen::Quaterniond qa(a(i), a(i + 1), a(i + 2), a(i + 3)), qb(b(i), b(i + 1), b(i + 2), b(i + 3));
  const Eigen::Quaterniond d = qa.conjugate() * qb;
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

}  // namespace

Mirror::Mirror(const sim::CharacterModel& model) : model_(&model) {
  const auto& links = model.links();
  twin_.resize(links.size());
  sign_.assign(links.size(), 1.0);
  for (std::size_t l = 0; l < links.size(); ++l) {
    const std::string twin = twin_name(links[l].name);
    twin_[l] = l == 0 ? 0 : model.find_link(twin);
    if (twin_[l] < 0)
      throw base::UserError("sprint: mirror of model " + model.name() + ": joint " + links[l].name + " has no twin " + twin);
    if (links[l].joint != sim::JointType::revolute) continue;
    // A hinge about a turns by θ; its mirror image turns about −P a by θ; read on the twin's axis b.
    const Eigen::Vector3d mirrored = -Eigen::Vector3d(links[l].axis.x(), -links[l].axis.y(), links[l].axis.z());
    const double s = mirrored.dot(links[twin_[l]].axis);
    if (std::abs(std::abs(s) - 1.0) > 1e-9)
      throw base::UserError("sprint: mirror of model " + model.name() + ": hinge " + links[l].name +
                            "'s axis does not mirror onto " + links[twin_[l]].name + "'s");
    sign_[l] = s > 0 ? 1.0 : -1.0;
  }
}

Eigen::VectorXd Mirror::apply(const Eigen::VectorXd& q) const {
  Eigen::VectorXd m = q;
  m(1) = -q(1);
  mirror_quat(q, 3, m, 3);
  const auto& links = model_->links();
  for (std::size_t l = 1; l < links.size(); ++l) {
    const sim::Link& to = links[twin_[l]];
    if (links[l].joint == sim::JointType::spherical) mirror_quat(q, links[l].q_index, m, to.q_index);
    else m(to.q_index) = sign_[l] * q(links[l].q_index);
  }
  return m;
}

double Mirror::distance2(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const {
  double sum = 0.0;
  for (const sim::Link& l : model_->links()) {
    double angle = 0.0;
    if (l.joint == sim::JointType::revolute) angle = a(l.q_index) - b(l.q_index);
    else angle = quat_angle(a, b, l.joint == sim::JointType::free ? l.q_index + 3 : l.q_index);
    sum += angle * angle;
  }
  return sum;
}

void StepAlignedPoses::reset() {
  current_.clear();
  previous_.clear();
  started_ = false;
}

void StepAlignedPoses::touchdown() {
  // Poses before the first touchdown are a partial step: only whole steps are compared.
  if (started_) previous_.swap(current_);
  started_ = true;
  current_.clear();
}

const Eigen::VectorXd* StepAlignedPoses::aligned_previous() const {
  if (previous_.empty()) return nullptr;
  return &previous_[std::min(current_.size(), previous_.size() - 1)];
}

namespace {

base::Json poses_json(const std::vector<Eigen::VectorXd>& poses) {
  base::Json rows = base::Json::array();
  for (const Eigen::VectorXd& q : poses) rows.push_back(base::Json(std::vector<double>(q.data(), q.data() + q.size())));
  return rows;
}

std::vector<Eigen::VectorXd> poses_of(const base::Json& rows) {
  std::vector<Eigen::VectorXd> poses;
  for (const base::Json& row : rows) {
    const auto v = row.get<std::vector<double>>();
    poses.emplace_back(Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size())));
  }
  return poses;
}

}  // namespace

base::Json StepAlignedPoses::state() const {
  return {{"started", started_}, {"current", poses_json(current_)}, {"previous", poses_json(previous_)}};
}

void StepAlignedPoses::load_state(const base::Json& state) {
  try {
    started_ = state.at("started").get<bool>();
    current_ = poses_of(state.at("current"));
    previous_ = poses_of(state.at("previous"));
  } catch (const base::Json::exception& e) {
    throw base::UserError(std::string("sprint: step-aligned poses state: ") + e.what());
  }
}

double mirror_reward(const Mirror& mirror, const Eigen::VectorXd& q_t, const Eigen::VectorXd& q_prev, double k) {
  return std::exp(-k * mirror.distance2(q_t, mirror.apply(q_prev)));  // sprint seed §3.2
}

}  // namespace podium::tasks::sprint
