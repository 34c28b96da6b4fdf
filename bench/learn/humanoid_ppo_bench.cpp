// PPO on a humanoid21 balance environment (sim/ World, SPD control) with 2 rollout threads:
// environment steps per second, the share of wall time spent in learner updates, and the
// rollout's simulation throughput next to the raw simulation throughput of the same World
// configuration stepped without learning (Benchmark B's protocol: random SPD targets, one core).
// Usage: learn_humanoid_ppo_bench [ITERATIONS] [THREADS]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "podium/learn/ppo.h"
#include "podium/sim/starts.h"
#include "podium/sim/world.h"

using namespace podium;
using Clock = std::chrono::steady_clock;

namespace {

sim::WorldConfig world_config() {
  sim::WorldConfig c;  // get-up seed: 800 Hz simulation, 40 Hz control
  return c;
}

// Keep the humanoid standing: actions are PD-target offsets (rad) from the standing pose.
class Humanoid21Balance final : public learn::Env {
 public:
  explicit Humanoid21Balance(sim::ModelPtr model) : world_(model, world_config()), model_(std::move(model)) {
    standing_head_m_ = (sim::standing_start(world_), world_.observe().head_height_m);
  }
  learn::BoxSpace observation_space() const override {
    const std::size_t n = std::size_t(model_->nq() - 2 + model_->nv());
    return {std::vector<double>(n, -1e9), std::vector<double>(n, 1e9)};
  }
  learn::BoxSpace action_space() const override {
    const std::size_t n = std::size_t(model_->nq() - 7);
    return {std::vector<double>(n, -0.5), std::vector<double>(n, 0.5)};
  }
  void seed(std::uint64_t seed) override { rng_ = base::Rng(seed); }
  void reset(std::vector<double>& observation) override {
    Eigen::VectorXd q = model_->standing_pose();
    for (int k = 7; k < model_->nq(); ++k) q[k] += rng_.normal(0.0, 0.05);
    world_.set_state(q, Eigen::VectorXd::Zero(model_->nv()));
    t_ = 0;
    observe(observation);
  }
  void step(std::span<const double> action, learn::StepResult& out) override {
    Eigen::VectorXd target = model_->standing_pose();
    for (std::size_t k = 0; k < action.size(); ++k) target[Eigen::Index(7 + k)] += action[k];
    const auto report = world_.control_step(sim::Control::spd_maba, target);
    const double head = world_.observe().head_height_m;
    const double fall = (standing_head_m_ - head) / standing_head_m_;
    out.reward = std::exp(-10.0 * fall * fall);
    out.terminated = !report.ok || head < 0.6 * standing_head_m_;
    out.truncated = !out.terminated && ++t_ >= 200;
    observe(out.observation);
  }

 private:
  void observe(std::vector<double>& o) const {
    const auto& d = world_.data();
    o.clear();
    for (int k = 2; k < model_->nq(); ++k) o.push_back(d.q[k]);
    for (int k = 0; k < model_->nv(); ++k) o.push_back(d.qd[k]);
  }
  sim::World world_;
  sim::ModelPtr model_;
  base::Rng rng_;
  double standing_head_m_ = 1.0;
  int t_ = 0;
};

// Raw simulation throughput of the same World: random SPD targets, ragdoll-free resets, 1 core.
double raw_control_steps_per_s(const sim::ModelPtr& model) {
  sim::World world(model, world_config());
  base::Rng rng(1);
  const int steps = 2000;
  const auto t0 = Clock::now();
  for (int k = 0; k < steps; ++k) {
    if (k % 200 == 0) sim::standing_start(world);
    Eigen::VectorXd target = model->standing_pose();
    for (int j = 7; j < model->nq(); ++j) target[j] += rng.uniform(-0.5, 0.5);
    world.control_step(sim::Control::spd_maba, target);
  }
  return steps / std::chrono::duration<double>(Clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  const int iterations = argc > 1 ? std::atoi(argv[1]) : 5;
  const int threads = argc > 2 ? std::atoi(argv[2]) : 2;
  const auto model = sim::load_shipped_model("humanoid21");
  const double raw = raw_control_steps_per_s(model);
  std::vector<std::unique_ptr<learn::Env>> envs;
  for (int i = 0; i < 2 * threads; ++i) envs.push_back(std::make_unique<Humanoid21Balance>(model));
  learn::VecEnv vec(std::move(envs), threads, 1);
  learn::PpoConfig config;  // 2 × 512 samples per iteration, 256-256 networks
  config.hidden = {256, 256};
  config.rollout_steps = 1024 / int(vec.size());
  config.epochs = 5;
  config.minibatch_size = 256;
  learn::Ppo ppo(config, vec.observation_space(), vec.action_space(), 1);
  double rollout_s = 0, update_s = 0;
  const auto t0 = Clock::now();
  ppo.train_until(vec, std::int64_t(iterations) * config.rollout_steps * std::int64_t(vec.size()),
                  [&](const learn::TrainStats& s) {
                    rollout_s += s.rollout_seconds;
                    update_s += s.update_seconds;
                    std::printf("steps %lld mean return %.1f\n", static_cast<long long>(s.env_steps), s.mean_return);
                  });
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  const double rollout_rate = double(ppo.env_steps()) / rollout_s;
  std::printf("humanoid21 balance, PPO 256-256, %d rollout threads, %zu copies, 800 Hz sim / 40 Hz control\n", threads, vec.size());
  std::printf("raw simulation (one core):   %8.0f control steps/s\n", raw);
  std::printf("rollout (during training):   %8.0f control steps/s = %.0f%% of raw x %d threads\n", rollout_rate,
              100.0 * rollout_rate / (raw * threads), threads);
  std::printf("overall training:            %8.0f env steps/s; updates %.1f%% of wall time (bar: <= 25%%)\n",
              double(ppo.env_steps()) / wall, 100.0 * update_s / wall);
  return 0;
}
