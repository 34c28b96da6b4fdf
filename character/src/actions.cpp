#include "podium/character/actions.h"

#include <algorithm>

#include "podium/base/error.h"

namespace podium::character {

namespace {

void check_target_mode(sim::Control mode) {
  if (mode == sim::Control::torque) throw base::UserError("character actions: targets need a pd or spd control mode, not torque");
}

learn::BoxSpace symmetric(std::size_t n, double bound) { return {std::vector<double>(n, -bound), std::vector<double>(n, bound)}; }

}  // namespace

learn::BoxSpace TorqueActions::space(const sim::CharacterModel& model) const { return symmetric(model.nv() - 6, 1.0); }

void TorqueActions::command(const CharacterEnv& env, std::span<const double> action, Eigen::VectorXd& out) const {
  const auto& model = env.model();
  const double strength = env.world().config().strength;
  out = Eigen::VectorXd::Zero(model.nv());
  for (int i = 6; i < model.nv(); ++i) out(i) = std::clamp(action[i - 6], -1.0, 1.0) * model.torque_limits()(i) * strength;
}

TargetActions::TargetActions(sim::ModelPtr model, sim::Control mode) : bridge_(std::move(model)), mode_(mode) {
  check_target_mode(mode);
}

learn::BoxSpace TargetActions::space(const sim::CharacterModel&) const { return {bridge_.lower(), bridge_.upper()}; }

void TargetActions::command(const CharacterEnv&, std::span<const double> action, Eigen::VectorXd& out) const {
  std::vector<double> pose(action.begin(), action.end());
  for (std::size_t k = 0; k < pose.size(); ++k) pose[k] = std::clamp(pose[k], bridge_.lower()[k], bridge_.upper()[k]);
  out = bridge_.target(pose);
}

VaeActions::VaeActions(std::shared_ptr<const learn::PoseVae> vae, PoseBridge bridge, sim::Control mode, double latent_bound,
                       double offset_bound, ConditionFn condition)
    : vae_(std::move(vae)),
      bridge_(std::move(bridge)),
      mode_(mode),
      latent_bound_(latent_bound),
      offset_bound_(offset_bound),
      condition_(std::move(condition)) {
  check_target_mode(mode);
  if (!vae_) throw base::UserError("character actions: VaeActions without a VAE");
  if (vae_->pose_size() != bridge_.size())
    throw base::UserError("character actions: the VAE's poses have " + std::to_string(vae_->pose_size()) + " entries, model " +
                          bridge_.model().name() + "'s " + std::to_string(bridge_.size()));
}

learn::BoxSpace VaeActions::space(const sim::CharacterModel&) const {
  learn::BoxSpace box = symmetric(vae_->latent_size(), latent_bound_);
  box.low.insert(box.low.end(), vae_->pose_size(), -offset_bound_);
  box.high.insert(box.high.end(), vae_->pose_size(), offset_bound_);
  return box;
}

void VaeActions::command(const CharacterEnv& env, std::span<const double> action, Eigen::VectorXd& out) const {
  const std::vector<double> condition = condition_ ? condition_(env) : std::vector<double>{};
  out = bridge_.target(learn::pose_action_to_target(*vae_, action, condition));
}

ResidualActions::ResidualActions(sim::ModelPtr model, sim::Control mode, double offset_bound)
    : bridge_(std::move(model)), mode_(mode), offset_bound_(offset_bound) {
  check_target_mode(mode);
}

learn::BoxSpace ResidualActions::space(const sim::CharacterModel&) const { return symmetric(bridge_.size(), offset_bound_); }

void ResidualActions::command(const CharacterEnv& env, std::span<const double> action, Eigen::VectorXd& out) const {
  if (!env.reference()) throw base::UserError("character actions: residual targets need a reference clip");
  std::vector<double> pose = bridge_.pose(env.reference()->sample(env.reference_time_s()));
  for (std::size_t k = 0; k < pose.size(); ++k) pose[k] += action[k];
  out = bridge_.target(pose);
}

}  // namespace podium::character
