#include "podium/learn/frozen_policy.h"

#include <ATen/Parallel.h>

#include "podium/base/error.h"
#include "podium/learn/learner.h"
#include "policy_file.h"

namespace podium::learn {

struct FrozenPolicy::Impl {
  detail::PolicyFile file;
  std::size_t n_obs;
};

FrozenPolicy::FrozenPolicy(const std::filesystem::path& file)
    : impl_(std::make_unique<Impl>(Impl{detail::read_policy_file(file), 0})) {
  impl_->n_obs = impl_->file.record.at("observation_size").get<std::size_t>();
  impl_->file.archive = torch::serialize::InputArchive();  // frees a checkpoint's replay buffer
  for (auto& p : impl_->file.net->parameters()) p.set_requires_grad(false);
  at::set_num_threads(1);
  setup_blas();
}
FrozenPolicy::~FrozenPolicy() = default;
FrozenPolicy::FrozenPolicy(FrozenPolicy&&) noexcept = default;
FrozenPolicy& FrozenPolicy::operator=(FrozenPolicy&&) noexcept = default;

std::string FrozenPolicy::algorithm() const { return impl_->file.record.at("algorithm").get<std::string>(); }
std::size_t FrozenPolicy::observation_size() const { return impl_->n_obs; }
std::size_t FrozenPolicy::action_size() const { return std::size_t(impl_->file.head.action_size); }

void FrozenPolicy::act(std::span<const double> observation, std::span<double> action, double action_scale) const {
  const auto& f = impl_->file;
  if (observation.size() != impl_->n_obs || action.size() != action_size())
    throw base::UserError("learn: FrozenPolicy.act: observation " + std::to_string(observation.size()) + " / action " +
                          std::to_string(action.size()) + " values, the policy has " + std::to_string(impl_->n_obs) + " / " +
                          std::to_string(action_size()));
  // The range the learners' act() allows (PPO's β is 1): a scale only shrinks the action box.
  if (!(action_scale > 0.0 && f.head.bound * action_scale <= 1.0))
    throw base::UserError("learn: FrozenPolicy.act: action_scale " + std::to_string(action_scale) + " is not allowed for this " +
                          algorithm() + " policy (β·s in (0, 1])");
  detail::deterministic_action(f.net, f.normalizer ? &*f.normalizer : nullptr, f.head, observation, action, action_scale);
}

}  // namespace podium::learn
