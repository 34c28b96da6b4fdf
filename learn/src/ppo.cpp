#include "podium/learn/ppo.h"

#include <ATen/Parallel.h>
#include <torch/optim/adam.h>
#include <torch/serialize.h>
#include <torch/types.h>
// clip_grad.h needs torch/types.h first.
#include <torch/nn/utils/clip_grad.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>

#include "config_json.h"
#include "nets.h"
#include "podium/base/error.h"
#include "policy_file.h"

namespace podium::learn {

using detail::Mlp;

PpoConfig PpoConfig::paper() {
  PpoConfig c;
  c.hidden = {1024, 512};
  c.activation = "relu";
  c.rollout_steps = 4096;  // per copy: divide by the number of copies for 4096 in total
  c.epochs = 5;
  c.minibatch_size = 256;
  c.gamma = 1.0;
  c.lambda = 0.95;
  c.clip = 0.02;
  c.policy_lr_start = c.policy_lr_end = 2.5e-5;
  c.value_lr_start = c.value_lr_end = 1e-2;
  c.sigma_start = 0.5;
  c.sigma_end = 0.1;
  c.sigma_anneal_steps = 10'000'000;
  return c;
}

#define PODIUM_PPO_FIELDS(X) \
  X(hidden)                  \
  X(activation)              \
  X(rollout_steps)           \
  X(epochs)                  \
  X(minibatch_size)          \
  X(gamma)                   \
  X(lambda)                  \
  X(clip)                    \
  X(policy_lr_start)         \
  X(policy_lr_end)           \
  X(value_lr_start)          \
  X(value_lr_end)            \
  X(lr_anneal_steps)         \
  X(sigma_start)             \
  X(sigma_end)               \
  X(sigma_anneal_steps)      \
  X(schedule_levels)         \
  X(max_grad_norm)           \
  X(normalize_observations)  \
  X(normalize_advantages)    \
  X(reward_scale)

PODIUM_CONFIG_JSON(PpoConfig, PODIUM_PPO_FIELDS, "ppo config")

double annealed(double start, double end, std::int64_t step, std::int64_t span, int levels) {
  double f = span <= 0 ? 1.0 : std::min(1.0, double(step) / double(span));
  if (levels >= 2) f = std::min(std::floor(f * levels), double(levels - 1)) / double(levels - 1);
  return start + (end - start) * f;
}

struct Ppo::Impl {
  PpoConfig config;
  BoxSpace observation_space, action_space;
  std::size_t n_obs, n_act;
  std::vector<double> center, half;
  base::Rng rng;
  RunningNormalizer normalizer;
  Mlp policy, value;
  std::unique_ptr<torch::optim::Adam> policy_opt, value_opt;
  std::int64_t env_steps = 0;
  std::int64_t iteration = 0;

  Impl(const PpoConfig& c, const BoxSpace& obs, const BoxSpace& act, std::uint64_t seed)
      : config(c),
        observation_space(obs),
        action_space(act),
        n_obs(obs.size()),
        n_act(act.size()),
        rng(seed),
        normalizer(obs.size()),
        policy(int(obs.size()), c.hidden, int(act.size()), detail::parse_activation(c.activation, "ppo config: activation")),
        value(int(obs.size()), c.hidden, 1, detail::parse_activation(c.activation, "ppo config: activation")) {
    if (c.rollout_steps < 1 || c.epochs < 1 || c.minibatch_size < 1)
      throw base::UserError("ppo config: rollout_steps, epochs and minibatch_size must be ≥ 1");
    if (c.schedule_levels == 1 || c.schedule_levels < 0)
      throw base::UserError("ppo config: schedule_levels " + std::to_string(c.schedule_levels) +
                            " is neither 0 (linear) nor ≥ 2 (stepped)");
    for (std::size_t j = 0; j < n_act; ++j) {
      if (!(act.high[j] > act.low[j]) || !std::isfinite(act.high[j] - act.low[j]))
        throw base::UserError("ppo: action_space[" + std::to_string(j) + "] = [" + std::to_string(act.low[j]) + ", " +
                              std::to_string(act.high[j]) + "] is not a finite, non-empty interval");
      center.push_back(0.5 * (act.high[j] + act.low[j]));
      half.push_back(0.5 * (act.high[j] - act.low[j]));
    }
    at::set_num_threads(1);
    setup_blas();
    detail::init_mlp(policy, rng, 0.01);
    detail::init_mlp(value, rng, 1.0);
    make_optimizers();
  }

  void make_optimizers() {
    policy_opt = std::make_unique<torch::optim::Adam>(policy->parameters(), torch::optim::AdamOptions(config.policy_lr_start));
    value_opt = std::make_unique<torch::optim::Adam>(value->parameters(), torch::optim::AdamOptions(config.value_lr_start));
  }
  const RunningNormalizer* used_normalizer() const { return config.normalize_observations ? &normalizer : nullptr; }
  detail::PolicyHead head() const { return {int(n_act), false, 1.0, action_space.low, action_space.high}; }
  base::Json record() const { return detail::policy_record("ppo", policy, n_obs, action_space, 1.0, used_normalizer()); }
  static double checked_scale(double scale) {
    if (!(scale > 0.0 && scale <= 1.0))
      throw base::UserError("ppo: action_scale " + std::to_string(scale) + " is outside (0, 1]: it shrinks the action box");
    return scale;
  }

  double schedule(double start, double end, std::int64_t step, std::int64_t span) const {
    return annealed(start, end, step, span, config.schedule_levels);
  }
  double sigma() const { return schedule(config.sigma_start, config.sigma_end, env_steps, config.sigma_anneal_steps); }

  torch::Tensor observe(const VecEnv& envs, bool update_normalizer) {
    std::vector<double> raw;
    raw.reserve(envs.size() * n_obs);
    for (std::size_t i = 0; i < envs.size(); ++i) raw.insert(raw.end(), envs.observation(i).begin(), envs.observation(i).end());
    if (config.normalize_observations && update_normalizer) normalizer.update(raw, envs.size());
    return batch(raw, envs.size());
  }
  torch::Tensor batch(const std::vector<double>& raw, std::size_t rows) const {
    if (config.normalize_observations) return detail::normalized_batch(normalizer, raw, rows);
    return torch::tensor(raw, torch::kFloat64).to(torch::kFloat32).reshape({std::int64_t(rows), std::int64_t(n_obs)});
  }

  void iterate(VecEnv& envs, TrainStats& stats) {
    const auto t0 = std::chrono::steady_clock::now();
    const std::int64_t K = std::int64_t(envs.size()), T = config.rollout_steps, A = std::int64_t(n_act);
    const double sig = sigma();
    detail::set_adam_lr(*policy_opt, schedule(config.policy_lr_start, config.policy_lr_end, env_steps, config.lr_anneal_steps));
    detail::set_adam_lr(*value_opt, schedule(config.value_lr_start, config.value_lr_end, env_steps, config.lr_anneal_steps));

    std::vector<torch::Tensor> obs_t, act_t, logp_t;
    std::vector<float> values(static_cast<std::size_t>(T * K)), rewards(static_cast<std::size_t>(T * K)),
        dones(static_cast<std::size_t>(T * K));
    std::vector<double> env_actions(static_cast<std::size_t>(K * A));
    {
      torch::NoGradGuard no_grad;
      for (std::int64_t t = 0; t < T; ++t) {
        auto obs = observe(envs, true);
        auto mu = policy->forward(obs);
        auto v = value->forward(obs).reshape({K});
        auto a = mu + sig * detail::normal_tensor(rng, {K, A});
        // Gaussian log-density with fixed σ (the constant terms cancel in the ratio).
        auto logp = (-0.5 * ((a - mu) / sig).pow(2)).sum(1);
        obs_t.push_back(obs);
        act_t.push_back(a);
        logp_t.push_back(logp);
        auto ap = a.accessor<float, 2>();
        // The policy acts in [−1, 1]; a copy's action_scale shrinks its box (get-up seed §5: torques
        // within ±β times the limits), as SAC's bound does.
        for (std::int64_t i = 0; i < K; ++i) {
          const double scale = checked_scale(envs.action_scale(static_cast<std::size_t>(i)));
          for (std::int64_t j = 0; j < A; ++j)
            env_actions[static_cast<std::size_t>(i * A + j)] =
                center[j] + half[j] * scale * std::clamp<double>(ap[i][j], -1.0, 1.0);
        }
        envs.step(env_actions);
        std::vector<std::int64_t> truncated;
        std::vector<double> final_obs;
        for (std::int64_t i = 0; i < K; ++i) {
          const StepResult& r = envs.result(static_cast<std::size_t>(i));
          const std::size_t k = static_cast<std::size_t>(t * K + i);
          values[k] = v[i].item<float>();
          rewards[k] = float(r.reward * config.reward_scale);
          dones[k] = (r.terminated || r.truncated) ? 1.0f : 0.0f;
          if (r.truncated && !r.terminated) {
            truncated.push_back(i);
            final_obs.insert(final_obs.end(), r.observation.begin(), r.observation.end());
          }
        }
        if (!truncated.empty()) {
          // Time limits are not MDP terminations: bootstrap from the final observation.
          auto vf = value->forward(batch(final_obs, truncated.size())).reshape({-1});
          for (std::size_t m = 0; m < truncated.size(); ++m)
            rewards[static_cast<std::size_t>(t * K + truncated[m])] += float(config.gamma * vf[std::int64_t(m)].item<float>());
        }
        env_steps += K;
      }
    }
    // GAE(λ) (Schulman et al. 2016); returns = advantages + values are the TD(λ) targets.
    std::vector<float> last_values(static_cast<std::size_t>(K));
    {
      torch::NoGradGuard no_grad;
      auto v = value->forward(observe(envs, false)).reshape({K});
      for (std::int64_t i = 0; i < K; ++i) last_values[static_cast<std::size_t>(i)] = v[i].item<float>();
    }
    std::vector<float> adv(static_cast<std::size_t>(T * K)), ret(static_cast<std::size_t>(T * K));
    for (std::int64_t i = 0; i < K; ++i) {
      double gae = 0.0;
      double next_value = last_values[static_cast<std::size_t>(i)];
      for (std::int64_t t = T - 1; t >= 0; --t) {
        const std::size_t k = static_cast<std::size_t>(t * K + i);
        const double not_done = 1.0 - dones[k];
        const double delta = rewards[k] + config.gamma * next_value * not_done - values[k];
        gae = delta + config.gamma * config.lambda * not_done * gae;
        adv[k] = float(gae);
        ret[k] = float(gae + values[k]);
        next_value = values[k];
      }
    }
    const auto t1 = std::chrono::steady_clock::now();

    auto obs_all = torch::cat(obs_t);
    auto act_all = torch::cat(act_t);
    auto logp_all = torch::cat(logp_t);
    auto adv_all = torch::from_blob(adv.data(), {T * K}).clone();
    auto ret_all = torch::from_blob(ret.data(), {T * K}).clone();
    if (config.normalize_advantages) adv_all = (adv_all - adv_all.mean()) / (adv_all.std() + 1e-8);
    const std::int64_t N = T * K;
    std::vector<std::int64_t> perm(static_cast<std::size_t>(N));
    for (int epoch = 0; epoch < config.epochs; ++epoch) {
      std::iota(perm.begin(), perm.end(), 0);
      for (std::int64_t i = N - 1; i > 0; --i)
        std::swap(perm[static_cast<std::size_t>(i)], perm[static_cast<std::size_t>(rng.integer(0, i))]);
      for (std::int64_t s = 0; s < N; s += config.minibatch_size) {
        const std::int64_t e = std::min(N, s + config.minibatch_size);
        auto idx = torch::from_blob(perm.data() + s, {e - s}, torch::kInt64);
        auto o = obs_all.index_select(0, idx);
        auto mu = policy->forward(o);
        auto logp = (-0.5 * ((act_all.index_select(0, idx) - mu) / sig).pow(2)).sum(1);
        auto ratio = torch::exp(logp - logp_all.index_select(0, idx));
        auto a = adv_all.index_select(0, idx);
        // PPO-Clip objective (Schulman et al. 2017, eq. 7).
        auto policy_loss = -torch::min(ratio * a, torch::clamp(ratio, 1.0 - config.clip, 1.0 + config.clip) * a).mean();
        policy_opt->zero_grad();
        policy_loss.backward();
        if (config.max_grad_norm > 0) torch::nn::utils::clip_grad_norm_(policy->parameters(), config.max_grad_norm);
        policy_opt->step();
        auto value_loss = 0.5 * (value->forward(o).reshape({-1}) - ret_all.index_select(0, idx)).pow(2).mean();
        value_opt->zero_grad();
        value_loss.backward();
        if (config.max_grad_norm > 0) torch::nn::utils::clip_grad_norm_(value->parameters(), config.max_grad_norm);
        value_opt->step();
      }
    }
    ++iteration;
    const auto t2 = std::chrono::steady_clock::now();
    stats.rollout_seconds += std::chrono::duration<double>(t1 - t0).count();
    stats.update_seconds += std::chrono::duration<double>(t2 - t1).count();
  }

  base::Json state_json(const VecEnv& envs, const base::Json& user_state) const {
    return {{"config", config.to_json()},      {"env_steps", env_steps},    {"iteration", iteration}, {"rng", rng.save()},
            {"normalizer", normalizer.save()}, {"envs", envs.save_state()}, {"policy", record()},     {"user_state", user_state}};
  }
};

Ppo::Ppo(const PpoConfig& config, const BoxSpace& observation_space, const BoxSpace& action_space, std::uint64_t seed)
    : impl_(std::make_unique<Impl>(config, observation_space, action_space, seed)) {}
Ppo::~Ppo() = default;

std::int64_t Ppo::env_steps() const { return impl_->env_steps; }
double Ppo::sigma() const { return impl_->sigma(); }

void Ppo::train_until(VecEnv& envs, std::int64_t total_env_steps, const TrainCallback& callback) {
  if (envs.observation_space().size() != impl_->n_obs || envs.action_space().size() != impl_->n_act)
    throw base::UserError("ppo: the VecEnv's spaces do not match the learner's (observation " +
                          std::to_string(envs.observation_space().size()) + " vs " + std::to_string(impl_->n_obs) + ", action " +
                          std::to_string(envs.action_space().size()) + " vs " + std::to_string(impl_->n_act) + ")");
  while (impl_->env_steps < total_env_steps) {
    TrainStats stats;
    impl_->iterate(envs, stats);
    const auto returns = envs.take_finished_returns();
    stats.env_steps = impl_->env_steps;
    stats.episodes = returns.size();
    double sum = 0.0;
    for (double r : returns) sum += r;
    stats.mean_return = returns.empty() ? std::numeric_limits<double>::quiet_NaN() : sum / double(returns.size());
    if (callback) callback(stats);
  }
}

void Ppo::act(std::span<const double> observation, std::span<double> action, bool deterministic, double action_scale) {
  auto& m = *impl_;
  PODIUM_CHECK(observation.size() == m.n_obs && action.size() == m.n_act, "ppo act: observation/action sizes");
  m.checked_scale(action_scale);
  if (deterministic)
    return detail::deterministic_action(m.policy, m.used_normalizer(), m.head(), observation, action, action_scale);
  torch::NoGradGuard no_grad;
  auto mu = m.policy->forward(m.batch(std::vector<double>(observation.begin(), observation.end()), 1));
  mu = mu + m.sigma() * detail::normal_tensor(m.rng, {1, std::int64_t(m.n_act)});
  auto p = mu.accessor<float, 2>();
  for (std::size_t j = 0; j < m.n_act; ++j)
    action[j] = m.center[j] + m.half[j] * action_scale * std::clamp<double>(p[0][std::int64_t(j)], -1.0, 1.0);
}

void Ppo::save_checkpoint(const std::filesystem::path& path, const VecEnv& envs, const base::Json& user_state) const {
  torch::serialize::OutputArchive archive, policy, value, policy_opt, value_opt;
  impl_->policy->save(policy);
  impl_->value->save(value);
  impl_->policy_opt->save(policy_opt);
  impl_->value_opt->save(value_opt);
  archive.write("policy", policy);
  archive.write("value", value);
  archive.write("policy_opt", policy_opt);
  archive.write("value_opt", value_opt);
  detail::write_json(archive, "state", impl_->state_json(envs, user_state));
  archive.save_to(path.string());
}

base::Json Ppo::load_checkpoint(const std::filesystem::path& path, VecEnv& envs) {
  torch::serialize::InputArchive archive, policy, value, policy_opt, value_opt;
  archive.load_from(path.string());
  const base::Json state = detail::read_json(archive, "state");
  if (state.at("config") != impl_->config.to_json())
    throw base::UserError("ppo: checkpoint " + path.string() + " was written with another config: " + state.at("config").dump());
  archive.read("policy", policy);
  archive.read("value", value);
  archive.read("policy_opt", policy_opt);
  archive.read("value_opt", value_opt);
  impl_->policy->load(policy);
  impl_->value->load(value);
  impl_->policy_opt->load(policy_opt);
  impl_->value_opt->load(value_opt);
  impl_->env_steps = state.at("env_steps").get<std::int64_t>();
  impl_->iteration = state.at("iteration").get<std::int64_t>();
  impl_->rng.load(state.at("rng").get<std::string>());
  impl_->normalizer.load(state.at("normalizer"));
  envs.load_state(state.at("envs"));
  return state.at("user_state");
}

void Ppo::warm_start(const std::filesystem::path& policy) {
  auto& m = *impl_;
  auto source = detail::read_policy_file(policy);
  detail::check_warm_start(source, m.record(), policy);
  detail::hard_update(*m.policy, *source.net);
  if (source.normalizer) m.normalizer = *source.normalizer;
  if (source.checkpoint) {
    torch::serialize::InputArchive value;
    source.archive.read("value", value);
    m.value->load(value);
  }
  m.make_optimizers();
  m.env_steps = 0;
  m.iteration = 0;
}

void Ppo::export_torchscript(const std::filesystem::path& path) const {
  detail::export_policy(path, impl_->policy, impl_->used_normalizer(), impl_->n_obs, impl_->head(), impl_->record());
}

std::vector<float> Ppo::parameters() const {
  std::vector<float> out;
  detail::append_parameters(*impl_->policy, out);
  detail::append_parameters(*impl_->value, out);
  return out;
}

}  // namespace podium::learn
