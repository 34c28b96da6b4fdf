#include "podium/learn/sac.h"

#include <ATen/Parallel.h>
#include <torch/optim/adam.h>
#include <torch/serialize.h>
#include <torch/types.h>
// clip_grad.h needs torch/types.h first.
#include <torch/nn/utils/clip_grad.h>

#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <numbers>

#include "config_json.h"
#include "nets.h"
#include "podium/base/error.h"
#include "policy_file.h"

namespace podium::learn {

using detail::Mlp;

SacConfig SacConfig::paper() {
  SacConfig c;
  c.hidden = {1024, 1024};
  c.activation = "relu";
  c.critic_lr = 1e-4;
  c.actor_lr = 1e-5;
  c.initial_alpha = 0.1;
  c.alpha_lr = 1e-4;
  c.log_std_min = -5.0;
  c.log_std_max = 2.0;
  c.tau = 5e-3;
  c.batch_size = 1024;
  c.updates_per_step = 1.0;
  c.gamma = 0.97;
  c.reward_scale = 1.0;
  c.max_grad_norm = 0.0;
  c.warmup_steps = 10'000;
  c.log_interval_steps = 20'000;  // §B: evaluated every 20 000 simulation steps
  return c;
}

#define PODIUM_SAC_FIELDS(X) \
  X(hidden)                  \
  X(activation)              \
  X(actor_lr)                \
  X(critic_lr)               \
  X(alpha_lr)                \
  X(initial_alpha)           \
  X(log_std_min)             \
  X(log_std_max)             \
  X(tau)                     \
  X(gamma)                   \
  X(batch_size)              \
  X(updates_per_step)        \
  X(warmup_steps)            \
  X(buffer_capacity)         \
  X(reward_scale)            \
  X(max_grad_norm)           \
  X(normalize_observations)  \
  X(target_entropy)          \
  X(action_bound)            \
  X(log_interval_steps)

PODIUM_CONFIG_JSON(SacConfig, PODIUM_SAC_FIELDS, "sac config")

namespace {
void check_bound(double beta) {
  if (!(beta > 0.0 && beta <= 1.0)) throw base::UserError("sac: action bound β = " + std::to_string(beta) + " is not in (0, 1]");
}
// CPU time of the calling thread (the update's): unlike wall time, not inflated by other
// processes sharing the cores.
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}
// β·s, the bound of one copy's actions (s: that copy's Env::action_scale()), must be in (0, 1].
bool scaled_bound_ok(double beta, double scale) { return scale > 0.0 && beta * scale <= 1.0; }
[[noreturn]] void bad_scaled_bound(double beta, double scale, const std::string& where) {
  throw base::UserError("sac: " + where + ": action_scale " + std::to_string(scale) + " × β " + std::to_string(beta) +
                        " is not in (0, 1]");
}
/// Turns off requires_grad of `params` for its lifetime.
class FrozenParameters {
 public:
  explicit FrozenParameters(std::vector<torch::Tensor>& params) : params_(params) {
    for (auto& p : params_) p.set_requires_grad(false);
  }
  ~FrozenParameters() {
    for (auto& p : params_) p.set_requires_grad(true);
  }
  FrozenParameters(const FrozenParameters&) = delete;
  FrozenParameters& operator=(const FrozenParameters&) = delete;

 private:
  std::vector<torch::Tensor>& params_;
};
}  // namespace

struct Sac::Impl {
  SacConfig config;
  BoxSpace observation_space, action_space;
  std::int64_t n_obs, n_act;
  std::vector<double> center, half;
  base::Rng rng;
  RunningNormalizer normalizer;
  Mlp actor, q1, q2, q1_target, q2_target;
  std::vector<torch::Tensor> critic_params;  // q1's then q2's
  torch::Tensor log_alpha;
  std::unique_ptr<torch::optim::Adam> actor_opt, critic_opt, alpha_opt;
  double bound;
  double target_entropy;
  std::int64_t env_steps = 0, updates = 0;
  std::int64_t skipped_updates = 0;  // updates whose loss was not finite: no step taken
  std::int64_t update_steps = 0;     // env steps taken since updates began; updates = ⌊update_steps · ratio⌋
  // Replay buffer: observations in float64 (normalised when sampled), the rest float32;
  // buf_scale holds the copy's action_scale() s when it acted (its bound is then β·s).
  torch::Tensor buf_obs, buf_next_obs, buf_act, buf_rew, buf_term, buf_scale;
  std::int64_t buf_size = 0, buf_pos = 0;
  SacUpdateTimes times;

  Impl(const SacConfig& c, const BoxSpace& obs, const BoxSpace& act, std::uint64_t seed)
      : config(c),
        observation_space(obs),
        action_space(act),
        n_obs(std::int64_t(obs.size())),
        n_act(std::int64_t(act.size())),
        rng(seed),
        normalizer(obs.size()),
        actor(int(n_obs), c.hidden, int(2 * n_act), detail::parse_activation(c.activation, "sac config: activation")),
        q1(int(n_obs + n_act), c.hidden, 1, actor->activation),
        q2(int(n_obs + n_act), c.hidden, 1, actor->activation),
        q1_target(int(n_obs + n_act), c.hidden, 1, actor->activation),
        q2_target(int(n_obs + n_act), c.hidden, 1, actor->activation),
        bound(c.action_bound),
        target_entropy(c.target_entropy != 0.0 ? c.target_entropy : -double(act.size())) {
    check_bound(bound);
    if (c.batch_size < 1 || c.buffer_capacity < c.batch_size)
      throw base::UserError("sac config: need batch_size ≥ 1 and buffer_capacity ≥ batch_size");
    if (!(c.updates_per_step >= 0.0 && std::isfinite(c.updates_per_step)))
      throw base::UserError("sac config: updates_per_step " + std::to_string(c.updates_per_step) + " is not a finite number ≥ 0");
    if (!(c.initial_alpha > 0))
      throw base::UserError("sac config: initial_alpha " + std::to_string(c.initial_alpha) + " is not > 0");
    for (std::size_t j = 0; j < act.size(); ++j) {
      if (!(act.high[j] > act.low[j]) || !std::isfinite(act.high[j] - act.low[j]))
        throw base::UserError("sac: action_space[" + std::to_string(j) + "] is not a finite, non-empty interval");
      center.push_back(0.5 * (act.high[j] + act.low[j]));
      half.push_back(0.5 * (act.high[j] - act.low[j]));
    }
    at::set_num_threads(1);
    setup_blas();
    detail::keep_freed_memory();
    detail::init_mlp(actor, rng);
    detail::init_mlp(q1, rng);
    detail::init_mlp(q2, rng);
    detail::hard_update(*q1_target, *q1);
    detail::hard_update(*q2_target, *q2);
    for (auto& p : q1_target->parameters()) p.set_requires_grad(false);
    for (auto& p : q2_target->parameters()) p.set_requires_grad(false);
    critic_params = q1->parameters();
    for (auto& p : q2->parameters()) critic_params.push_back(p);
    make_optimizers();
    const auto f64 = torch::kFloat64;
    buf_obs = torch::zeros({c.buffer_capacity, n_obs}, f64);
    buf_next_obs = torch::zeros({c.buffer_capacity, n_obs}, f64);
    buf_act = torch::zeros({c.buffer_capacity, n_act});
    buf_rew = torch::zeros({c.buffer_capacity});
    buf_term = torch::zeros({c.buffer_capacity});
    buf_scale = torch::ones({c.buffer_capacity, 1});
  }

  /// Fresh α = initial_alpha and fresh Adam states.
  void make_optimizers() {
    log_alpha = torch::full({1}, std::log(config.initial_alpha), torch::kFloat32).set_requires_grad(true);
    actor_opt = std::make_unique<torch::optim::Adam>(actor->parameters(), torch::optim::AdamOptions(config.actor_lr));
    critic_opt = std::make_unique<torch::optim::Adam>(critic_params, torch::optim::AdamOptions(config.critic_lr));
    alpha_opt =
        std::make_unique<torch::optim::Adam>(std::vector<torch::Tensor>{log_alpha}, torch::optim::AdamOptions(config.alpha_lr));
  }
  const RunningNormalizer* used_normalizer() const { return config.normalize_observations ? &normalizer : nullptr; }
  detail::PolicyHead head() const { return {int(n_act), true, bound, action_space.low, action_space.high}; }
  base::Json record() const {
    return detail::policy_record("sac", actor, std::size_t(n_obs), action_space, bound, used_normalizer());
  }

  /// The normaliser applied to float64 rows, with the same arithmetic as RunningNormalizer.
  torch::Tensor normalize(const torch::Tensor& raw) const {
    if (!config.normalize_observations) return raw.to(torch::kFloat32);
    auto mean = torch::tensor(normalizer.mean(), torch::kFloat64);
    auto scale = torch::tensor(normalizer.scale(), torch::kFloat64);
    return ((raw - mean) / scale).clamp(-normalizer.clip(), normalizer.clip()).to(torch::kFloat32);
  }

  /// Reparameterised sample a = b·tanh(μ + σ·ε) and its log-density (SAC appendix C, with the
  /// extra log b of the scaled squashing); `bounds` [rows, 1] holds each row's b = β·s.
  std::pair<torch::Tensor, torch::Tensor> sample(const torch::Tensor& obs, const torch::Tensor& bounds) {
    auto out = actor->forward(obs);
    auto mu = out.slice(1, 0, n_act);
    auto log_std = out.slice(1, n_act, 2 * n_act).clamp(config.log_std_min, config.log_std_max);
    auto eps = detail::normal_tensor(rng, {obs.size(0), n_act});
    auto u = mu + log_std.exp() * eps;
    const double log_2pi = std::log(2 * std::numbers::pi);
    auto logp = (-0.5 * eps.pow(2) - log_std - 0.5 * log_2pi).sum(1);
    // log(1 − tanh²u) = 2(log 2 − u − softplus(−2u)), the numerically stable form.
    logp = logp - (torch::log(bounds) + 2.0 * (std::log(2.0) - u - torch::softplus(-2.0 * u))).sum(1);
    return {bounds * torch::tanh(u), logp};
  }

  torch::Tensor q_min(Mlp& a, Mlp& b, const torch::Tensor& o, const torch::Tensor& act) {
    auto x = torch::cat({o, act}, 1);
    return torch::min(a->forward(x), b->forward(x)).reshape({-1});
  }

  void update() {
    double mark = thread_cpu_seconds();
    auto lap = [&](double& part) {
      const double now = thread_cpu_seconds();
      part += now - mark;
      mark = now;
    };
    const std::int64_t B = config.batch_size;
    std::vector<std::int64_t> idx_v(static_cast<std::size_t>(B));
    for (auto& i : idx_v) i = rng.integer(0, buf_size - 1);
    auto idx = torch::from_blob(idx_v.data(), {B}, torch::kInt64);
    auto o = normalize(buf_obs.index_select(0, idx));
    auto o2 = normalize(buf_next_obs.index_select(0, idx));
    auto a = buf_act.index_select(0, idx);
    auto r = buf_rew.index_select(0, idx);
    auto term = buf_term.index_select(0, idx);
    // The transition's own scale s for both its state and its next state (one episode, one β̂).
    auto bounds = bound * buf_scale.index_select(0, idx);
    const double alpha = log_alpha.exp().item<double>();
    lap(times.batch);
    torch::Tensor y;
    {
      torch::NoGradGuard no_grad;
      auto [a2, logp2] = sample(o2, bounds);
      // Soft Bellman target with the smaller of the twin target critics (Fujimoto et al. 2018).
      y = config.reward_scale * r + config.gamma * (1.0 - term) * (q_min(q1_target, q2_target, o2, a2) - alpha * logp2);
    }
    lap(times.target);
    auto x = torch::cat({o, a}, 1);
    auto critic_loss =
        0.5 * ((q1->forward(x).reshape({-1}) - y).pow(2).mean() + (q2->forward(x).reshape({-1}) - y).pow(2).mean());
    // A non-finite loss would turn Adam's moments, and then every weight, into NaN for good: skip
    // the update (it still counts, so the update schedule goes on) and report it.
    if (!std::isfinite(critic_loss.item<double>())) {
      ++skipped_updates, ++updates;
      return;
    }
    critic_opt->zero_grad();
    critic_loss.backward();
    if (config.max_grad_norm > 0) {
      torch::nn::utils::clip_grad_norm_(q1->parameters(), config.max_grad_norm);
      torch::nn::utils::clip_grad_norm_(q2->parameters(), config.max_grad_norm);
    }
    critic_opt->step();
    lap(times.critic);

    auto [a_new, logp] = sample(o, bounds);
    actor_opt->zero_grad();
    {
      // The actor needs ∂Q/∂a only: critics frozen while the graph is built skip their weight
      // gradients (the critic step would zero them before use), a fifth of this step's products.
      FrozenParameters frozen(critic_params);
      auto actor_loss = (alpha * logp - q_min(q1, q2, o, a_new)).mean();
      if (!std::isfinite(actor_loss.item<double>())) {
        ++skipped_updates, ++updates;
        return;
      }
      actor_loss.backward();
    }
    if (config.max_grad_norm > 0) torch::nn::utils::clip_grad_norm_(actor->parameters(), config.max_grad_norm);
    actor_opt->step();
    lap(times.actor);

    // Automatic temperature (Haarnoja et al. 2018b, eq. 18) in log α: α falls while the entropy
    // estimate −logp exceeds the target, at most ≈ alpha_lr in log α per update (Adam).
    auto alpha_loss = -(log_alpha * (logp.detach() + target_entropy)).mean();
    alpha_opt->zero_grad();
    alpha_loss.backward();
    alpha_opt->step();
    lap(times.alpha);

    detail::soft_update(*q1_target, *q1, config.tau);
    detail::soft_update(*q2_target, *q2, config.tau);
    lap(times.polyak);
    ++updates;
  }

  void store(const std::vector<double>& obs, const std::vector<double>& next_obs, const float* action, double reward,
             bool terminated, float scale) {
    // Raw pointers into the contiguous buffers: a tensor index per element costs a dispatch each.
    std::copy_n(obs.begin(), n_obs, buf_obs.data_ptr<double>() + buf_pos * n_obs);
    std::copy_n(next_obs.begin(), n_obs, buf_next_obs.data_ptr<double>() + buf_pos * n_obs);
    std::copy(action, action + n_act, buf_act.data_ptr<float>() + buf_pos * n_act);
    buf_rew.data_ptr<float>()[buf_pos] = float(reward);
    buf_term.data_ptr<float>()[buf_pos] = terminated ? 1.0f : 0.0f;
    buf_scale.data_ptr<float>()[buf_pos] = scale;
    buf_pos = (buf_pos + 1) % config.buffer_capacity;
    buf_size = std::min(buf_size + 1, config.buffer_capacity);
  }
};

Sac::Sac(const SacConfig& config, const BoxSpace& observation_space, const BoxSpace& action_space, std::uint64_t seed)
    : impl_(std::make_unique<Impl>(config, observation_space, action_space, seed)) {}
Sac::~Sac() = default;

std::int64_t Sac::env_steps() const { return impl_->env_steps; }
void Sac::set_action_bound(double beta) {
  check_bound(beta);
  impl_->bound = beta;
}
double Sac::action_bound() const { return impl_->bound; }
double Sac::alpha() const { return impl_->log_alpha.exp().item<double>(); }
std::int64_t Sac::replay_size() const { return impl_->buf_size; }
std::int64_t Sac::updates() const { return impl_->updates; }
std::int64_t Sac::skipped_updates() const { return impl_->skipped_updates; }
SacUpdateTimes Sac::update_times() const { return impl_->times; }

void Sac::train_until(VecEnv& envs, std::int64_t total_env_steps, const TrainCallback& callback) {
  auto& m = *impl_;
  if (std::int64_t(envs.observation_space().size()) != m.n_obs || std::int64_t(envs.action_space().size()) != m.n_act)
    throw base::UserError("sac: the VecEnv's spaces do not match the learner's");
  const std::int64_t K = std::int64_t(envs.size());
  std::vector<double> env_actions(static_cast<std::size_t>(K * m.n_act));
  std::vector<std::vector<double>> obs(static_cast<std::size_t>(K));
  std::vector<float> scales(static_cast<std::size_t>(K));
  std::vector<double> copy_bounds(static_cast<std::size_t>(K));
  TrainStats stats;
  std::int64_t next_log = (m.env_steps / m.config.log_interval_steps + 1) * m.config.log_interval_steps;
  // The transitions each new episode's start took (the get-up seed's fall), stored as they come:
  // not environment steps, so neither the step count nor the updates owed change.
  std::vector<float> start_action(static_cast<std::size_t>(m.n_act));
  const auto store_starts = [&] {
    for (std::size_t i = 0; i < std::size_t(K); ++i)
      for (const Transition& t : envs.take_start_transitions(i)) {
        PODIUM_CHECK(std::int64_t(t.action.size()) == m.n_act && std::int64_t(t.observation.size()) == m.n_obs &&
                         std::int64_t(t.next_observation.size()) == m.n_obs,
                     "sac: a start transition's sizes");
        for (std::size_t j = 0; j < start_action.size(); ++j) start_action[j] = float((t.action[j] - m.center[j]) / m.half[j]);
        m.store(t.observation, t.next_observation, start_action.data(), t.reward, t.terminated, float(envs.action_scale(i)));
      }
  };
  store_starts();  // the episodes begun before this call (the VecEnv's first resets); later ones after each step
  while (m.env_steps < total_env_steps) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<double> raw;
    for (std::int64_t i = 0; i < K; ++i) {
      obs[static_cast<std::size_t>(i)] = envs.observation(static_cast<std::size_t>(i));
      raw.insert(raw.end(), obs[static_cast<std::size_t>(i)].begin(), obs[static_cast<std::size_t>(i)].end());
    }
    for (std::size_t i = 0; i < std::size_t(K); ++i) {
      const double s = envs.action_scale(i);
      if (!scaled_bound_ok(m.bound, s)) bad_scaled_bound(m.bound, s, "environment copy " + std::to_string(i));
      copy_bounds[i] = m.bound * s;
      scales[i] = float(s);
    }
    if (m.config.normalize_observations) m.normalizer.update(raw, static_cast<std::size_t>(K));
    torch::Tensor actions;
    if (m.env_steps < m.config.warmup_steps) {
      actions = torch::empty({K, m.n_act});
      auto p = actions.data_ptr<float>();
      for (std::int64_t k = 0; k < K * m.n_act; ++k) {
        const double b = copy_bounds[static_cast<std::size_t>(k / m.n_act)];
        p[k] = float(m.rng.uniform(-b, b));
      }
    } else {
      torch::NoGradGuard no_grad;
      auto bounds = m.bound * torch::from_blob(scales.data(), {K, 1});
      actions = m.sample(m.normalize(torch::tensor(raw, torch::kFloat64).reshape({K, m.n_obs})), bounds).first.contiguous();
    }
    const float* ap = actions.data_ptr<float>();
    for (std::int64_t k = 0; k < K * m.n_act; ++k)
      env_actions[static_cast<std::size_t>(k)] = m.center[std::size_t(k % m.n_act)] + m.half[std::size_t(k % m.n_act)] * ap[k];
    envs.step(env_actions);
    for (std::int64_t i = 0; i < K; ++i) {
      const StepResult& r = envs.result(static_cast<std::size_t>(i));
      m.store(obs[static_cast<std::size_t>(i)], r.observation, ap + i * m.n_act, r.reward, r.terminated,
              scales[static_cast<std::size_t>(i)]);
    }
    store_starts();
    m.env_steps += K;
    const auto t1 = std::chrono::steady_clock::now();
    if (m.env_steps >= m.config.warmup_steps && m.buf_size >= m.config.batch_size) {
      // Fractional update-to-data ratio: owed updates from exact integer step counts, so a
      // resumed run updates exactly when the uninterrupted one does.
      m.update_steps += K;
      const auto due = std::int64_t(std::floor(double(m.update_steps) * m.config.updates_per_step));
      while (m.updates < due) m.update();
    }
    const auto t2 = std::chrono::steady_clock::now();
    stats.rollout_seconds += std::chrono::duration<double>(t1 - t0).count();
    stats.update_seconds += std::chrono::duration<double>(t2 - t1).count();
    if (m.env_steps >= next_log || m.env_steps >= total_env_steps) {
      next_log = (m.env_steps / m.config.log_interval_steps + 1) * m.config.log_interval_steps;
      const auto returns = envs.take_finished_returns();
      stats.env_steps = m.env_steps;
      stats.episodes = returns.size();
      double sum = 0.0;
      for (double x : returns) sum += x;
      stats.mean_return = returns.empty() ? std::numeric_limits<double>::quiet_NaN() : sum / double(returns.size());
      if (callback) callback(stats);
      stats = TrainStats{};
    }
  }
}

void Sac::act(std::span<const double> observation, std::span<double> action, bool deterministic, double action_scale) {
  auto& m = *impl_;
  PODIUM_CHECK(std::int64_t(observation.size()) == m.n_obs && std::int64_t(action.size()) == m.n_act, "sac act: sizes");
  if (!scaled_bound_ok(m.bound, action_scale)) bad_scaled_bound(m.bound, action_scale, "act");
  if (deterministic)
    return detail::deterministic_action(m.actor, m.used_normalizer(), m.head(), observation, action, action_scale);
  torch::NoGradGuard no_grad;
  auto o = m.normalize(
      torch::tensor(std::vector<double>(observation.begin(), observation.end()), torch::kFloat64).reshape({1, m.n_obs}));
  auto a = m.sample(o, m.bound * torch::full({1, 1}, float(action_scale))).first;
  auto p = a.accessor<float, 2>();
  for (std::int64_t j = 0; j < m.n_act; ++j)
    action[std::size_t(j)] = m.center[std::size_t(j)] + m.half[std::size_t(j)] * double(p[0][j]);
}

void Sac::save_checkpoint(const std::filesystem::path& path, const VecEnv& envs, const base::Json& user_state) const {
  const auto& m = *impl_;
  torch::serialize::OutputArchive archive;
  auto sub = [&](const char* key, auto&& save) {
    torch::serialize::OutputArchive a;
    save(a);
    archive.write(key, a);
  };
  sub("actor", [&](auto& a) { m.actor->save(a); });
  sub("q1", [&](auto& a) { m.q1->save(a); });
  sub("q2", [&](auto& a) { m.q2->save(a); });
  sub("q1_target", [&](auto& a) { m.q1_target->save(a); });
  sub("q2_target", [&](auto& a) { m.q2_target->save(a); });
  sub("actor_opt", [&](auto& a) { m.actor_opt->save(a); });
  sub("critic_opt", [&](auto& a) { m.critic_opt->save(a); });
  sub("alpha_opt", [&](auto& a) { m.alpha_opt->save(a); });
  archive.write("log_alpha", m.log_alpha.detach());
  archive.write("buf_obs", m.buf_obs.slice(0, 0, m.buf_size));
  archive.write("buf_next_obs", m.buf_next_obs.slice(0, 0, m.buf_size));
  archive.write("buf_act", m.buf_act.slice(0, 0, m.buf_size));
  archive.write("buf_rew", m.buf_rew.slice(0, 0, m.buf_size));
  archive.write("buf_term", m.buf_term.slice(0, 0, m.buf_size));
  archive.write("buf_scale", m.buf_scale.slice(0, 0, m.buf_size));
  detail::write_json(archive, "state",
                     {{"config", m.config.to_json()},
                      {"env_steps", m.env_steps},
                      {"updates", m.updates},
                      {"skipped_updates", m.skipped_updates},
                      {"update_steps", m.update_steps},
                      {"bound", m.bound},
                      {"buf_size", m.buf_size},
                      {"buf_pos", m.buf_pos},
                      {"rng", m.rng.save()},
                      {"normalizer", m.normalizer.save()},
                      {"envs", envs.save_state()},
                      {"policy", m.record()},
                      {"user_state", user_state}});
  archive.save_to(path.string());
}

base::Json Sac::load_checkpoint(const std::filesystem::path& path, VecEnv& envs) {
  auto& m = *impl_;
  torch::serialize::InputArchive archive;
  archive.load_from(path.string());
  const base::Json state = detail::read_json(archive, "state");
  if (state.at("config") != m.config.to_json())
    throw base::UserError("sac: checkpoint " + path.string() + " was written with another config: " + state.at("config").dump());
  auto sub = [&](const char* key, auto&& load) {
    torch::serialize::InputArchive a;
    archive.read(key, a);
    load(a);
  };
  sub("actor", [&](auto& a) { m.actor->load(a); });
  sub("q1", [&](auto& a) { m.q1->load(a); });
  sub("q2", [&](auto& a) { m.q2->load(a); });
  sub("q1_target", [&](auto& a) { m.q1_target->load(a); });
  sub("q2_target", [&](auto& a) { m.q2_target->load(a); });
  sub("actor_opt", [&](auto& a) { m.actor_opt->load(a); });
  sub("critic_opt", [&](auto& a) { m.critic_opt->load(a); });
  sub("alpha_opt", [&](auto& a) { m.alpha_opt->load(a); });
  {
    // A fresh tensor per read: InputArchive::read into a defined tensor re-points it (set_).
    torch::NoGradGuard no_grad;
    torch::Tensor alpha;
    archive.read("log_alpha", alpha);
    m.log_alpha.copy_(alpha);
    m.buf_size = state.at("buf_size").get<std::int64_t>();
    for (auto [key, buf] : {std::pair{"buf_obs", &m.buf_obs},
                            {"buf_next_obs", &m.buf_next_obs},
                            {"buf_act", &m.buf_act},
                            {"buf_rew", &m.buf_rew},
                            {"buf_term", &m.buf_term},
                            {"buf_scale", &m.buf_scale}}) {
      torch::Tensor t;
      archive.read(key, t);
      buf->slice(0, 0, m.buf_size).copy_(t);
    }
  }
  m.buf_pos = state.at("buf_pos").get<std::int64_t>();
  m.env_steps = state.at("env_steps").get<std::int64_t>();
  m.updates = state.at("updates").get<std::int64_t>();
  m.skipped_updates = state.value("skipped_updates", std::int64_t{0});  // absent in checkpoints before it existed
  m.update_steps = state.at("update_steps").get<std::int64_t>();
  m.bound = state.at("bound").get<double>();
  m.rng.load(state.at("rng").get<std::string>());
  m.normalizer.load(state.at("normalizer"));
  envs.load_state(state.at("envs"));
  return state.at("user_state");
}

void Sac::warm_start(const std::filesystem::path& policy) {
  auto& m = *impl_;
  auto source = detail::read_policy_file(policy);
  detail::check_warm_start(source, m.record(), policy);
  detail::hard_update(*m.actor, *source.net);
  if (source.normalizer) m.normalizer = *source.normalizer;
  if (source.checkpoint) {
    for (auto [key, net] : {std::pair{"q1", &m.q1}, {"q2", &m.q2}}) {
      torch::serialize::InputArchive a;
      source.archive.read(key, a);
      (*net)->load(a);
    }
  }
  // Targets start equal to the critics, as in a fresh learner.
  detail::hard_update(*m.q1_target, *m.q1);
  detail::hard_update(*m.q2_target, *m.q2);
  m.make_optimizers();
  m.env_steps = m.updates = m.update_steps = 0;
  m.buf_size = m.buf_pos = 0;
}

void Sac::export_torchscript(const std::filesystem::path& path) const {
  const auto& m = *impl_;
  detail::export_policy(path, m.actor, m.used_normalizer(), std::size_t(m.n_obs), m.head(), m.record());
}

std::vector<float> Sac::parameters() const {
  std::vector<float> out;
  for (const Mlp* net : {&impl_->actor, &impl_->q1, &impl_->q2, &impl_->q1_target, &impl_->q2_target})
    detail::append_parameters(**net, out);
  out.push_back(impl_->log_alpha.item<float>());
  return out;
}

}  // namespace podium::learn
