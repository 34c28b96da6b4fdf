// PPO on a humanoid21 balance environment (sim/ World, SPD control) with 2 rollout threads:
// environment steps per second, the share of wall time spent in learner updates, and the
// rollout's simulation throughput next to the raw simulation throughput of the same World
// configuration stepped without learning (Benchmark B's protocol: random SPD targets, one core).
// Usage: learn_humanoid_ppo_bench [ITERATIONS] [THREADS] [ROUNDS]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "bench_args.h"
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
    const std::size_t n = std::size_t(model_->nq()) - 2 + std::size_t(model_->nv());
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
double raw_control_steps_per_s(const sim::ModelPtr& model, std::uint64_t seed) {
  sim::World world(model, world_config());
  base::Rng rng(seed);
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

struct Round {
  double raw = 0, rollout = 0, overall = 0, update_share = 0;
};

// One round: raw simulation on one core, then PPO training with `threads` rollout threads.
Round run_round(const sim::ModelPtr& model, int iterations, int threads, std::uint64_t seed) {
  Round r;
  r.raw = raw_control_steps_per_s(model, seed);
  std::vector<std::unique_ptr<learn::Env>> envs;
  for (int i = 0; i < 2 * threads; ++i) envs.push_back(std::make_unique<Humanoid21Balance>(model));
  learn::VecEnv vec(std::move(envs), threads, seed);
  learn::PpoConfig config;  // 2 × 512 samples per iteration, 256-256 networks
  config.hidden = {256, 256};
  config.rollout_steps = 1024 / int(vec.size());
  config.epochs = 5;
  config.minibatch_size = 256;
  learn::Ppo ppo(config, vec.observation_space(), vec.action_space(), seed);
  double rollout_s = 0, update_s = 0;
  const auto t0 = Clock::now();
  ppo.train_until(vec, std::int64_t(iterations) * config.rollout_steps * std::int64_t(vec.size()),
                  [&](const learn::TrainStats& s) {
                    rollout_s += s.rollout_seconds;
                    update_s += s.update_seconds;
                  });
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  r.rollout = double(ppo.env_steps()) / rollout_s;
  r.overall = double(ppo.env_steps()) / wall;
  r.update_share = update_s / wall;
  return r;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

// Rounds alternate raw and training measurements so machine noise hits both alike; medians are
// reported. Seeds 1..ROUNDS.
int main(int argc, char** argv) {
  int iterations = 5, threads = 2, rounds = 5;
  const auto fail = [&](const std::string& error) {
    std::fprintf(stderr, "%s: %s\nusage: %s [ITERATIONS ≥ 1] [THREADS 1..512] [ROUNDS ≥ 1]\n", argv[0], error.c_str(), argv[0]);
    return 2;
  };
  // argv[i], if given, as a count in [1, max].
  const auto count = [&](int i, long long max, int& out) { return i >= argc || bench::count(argv[i], 1, max, out); };
  if (argc > 4) return fail("unexpected argument '" + std::string(argv[4]) + "'");
  // A million at most (far beyond a useful run); at most 512 threads: their 2 × threads copies
  // share 1024 rollout steps, at least one each.
  if (!count(1, 1'000'000, iterations)) return fail("bad value '" + std::string(argv[1]) + "' for ITERATIONS");
  if (!count(2, 512, threads)) return fail("bad value '" + std::string(argv[2]) + "' for THREADS");
  if (!count(3, 1'000'000, rounds)) return fail("bad value '" + std::string(argv[3]) + "' for ROUNDS");
  const auto model = sim::load_shipped_model("humanoid21");
  std::vector<double> raw, rollout, overall, share, per_core, per_thread;
  std::printf(
      "humanoid21 balance, PPO 256-256, %d rollout threads, %d copies, 800 Hz sim / 40 Hz control, %d iterations x 1024 steps\n",
      threads, 2 * threads, iterations);
  std::printf("%5s %12s %12s %12s %9s %14s %16s\n", "seed", "raw/s 1 core", "rollout/s", "overall/s", "updates", "rollout/raw",
              "per thread");
  for (int k = 1; k <= rounds; ++k) {
    const Round r = run_round(model, iterations, threads, std::uint64_t(k));
    raw.push_back(r.raw);
    rollout.push_back(r.rollout);
    overall.push_back(r.overall);
    share.push_back(r.update_share);
    per_core.push_back(r.rollout / r.raw);
    per_thread.push_back(r.rollout / (r.raw * threads));
    std::printf("%5d %12.0f %12.0f %12.0f %8.1f%% %13.0f%% %15.0f%%\n", k, r.raw, r.rollout, r.overall, 100 * r.update_share,
                100 * per_core.back(), 100 * per_thread.back());
  }
  const double share_m = median(share), per_core_m = median(per_core);
  std::printf("median: raw %.0f control steps/s (one core), rollout %.0f, overall %.0f env steps/s\n", median(raw),
              median(rollout), median(overall));
  std::printf(
      "updates %.1f%% of wall time (bar <= 25%%: %s); rollout %.0f%% of one-core raw (bar >= 80%%: %s); %.0f%% per rollout "
      "thread\n",
      100 * share_m, share_m <= 0.25 ? "met" : "NOT met", 100 * per_core_m, per_core_m >= 0.8 ? "met" : "NOT met",
      100 * median(per_thread));
  return 0;
}
