// Times one SAC update at the get-up's sizes (humanoid21, 21 torque actions,
// 256-256 networks, batch 256) and splits it into its parts. The environment is a stand-in that
// returns random observations and rewards (its cost is negligible), so only the update is timed.
// One intra-op thread and one BLAS thread, as every learner runs.
// Usage: learn_sac_update_bench [OBSERVATIONS] [UPDATES] [CONFIG_JSON]
// e.g. learn_sac_update_bench 150 2000 '{"hidden": [1024, 1024], "batch_size": 1024}'
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <exception>
#include <memory>
#include <string>
#include <vector>

#include "bench_args.h"
#include "podium/base/rng.h"
#include "podium/learn/sac.h"

using namespace podium::learn;

namespace {

class RandomEnv final : public Env {
 public:
  explicit RandomEnv(std::size_t observations) : n_(observations) {}
  BoxSpace observation_space() const override { return {std::vector<double>(n_, -1e9), std::vector<double>(n_, 1e9)}; }
  BoxSpace action_space() const override { return {std::vector<double>(21, -1.0), std::vector<double>(21, 1.0)}; }
  void seed(std::uint64_t seed) override { rng_ = podium::base::Rng(seed); }
  void reset(std::vector<double>& observation) override { fill(observation); }
  void step(std::span<const double>, StepResult& out) override {
    fill(out.observation);
    out.reward = rng_.uniform(0.0, 1.0);
    out.terminated = rng_.uniform(0.0, 1.0) < 0.004;  // one episode in 250 steps
  }

 private:
  void fill(std::vector<double>& o) {
    o.resize(n_);
    for (auto& x : o) x = rng_.normal();
  }
  std::size_t n_;
  podium::base::Rng rng_;
};

// This thread's CPU time, as Sac's update_times(): robust to other processes sharing the cores.
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

double quantile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[std::size_t(q * double(v.size() - 1))];
}

}  // namespace

int main(int argc, char** argv) {
  long long observations = 150, updates = 1000;
  if (argc > 4 || (argc > 1 && !podium::bench::whole_number(argv[1], 1, observations)) ||
      (argc > 2 && !podium::bench::whole_number(argv[2], 1, updates))) {
    std::fprintf(stderr, "usage: learn_sac_update_bench [OBSERVATIONS>0] [UPDATES>0] [CONFIG_JSON]\n");
    return 2;
  }
  podium::base::Json config = {{"hidden", {256, 256}},
                               {"batch_size", 256},
                               {"warmup_steps", 1000},
                               {"updates_per_step", 1.0},
                               {"buffer_capacity", 100000}};
  SacConfig c;
  try {
    if (argc > 3) config.merge_patch(podium::base::Json::parse(argv[3]));
    c = SacConfig::from_json(config);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "learn_sac_update_bench: CONFIG_JSON: %s\n", error.what());
    return 2;
  }
  std::vector<std::unique_ptr<Env>> copies;
  copies.push_back(std::make_unique<RandomEnv>(static_cast<std::size_t>(observations)));
  VecEnv envs(std::move(copies), 1, 1);
  RandomEnv probe(static_cast<std::size_t>(observations));
  Sac sac(c, probe.observation_space(), probe.action_space(), 1);
  sac.train_until(envs, c.warmup_steps + 50);  // fill the buffer; the first updates warm caches
  // One environment step = one update; each part's median over the updates.
  const char* names[] = {"batch", "target", "critic", "actor", "alpha", "polyak", "total", "cpu"};
  std::vector<std::vector<double>> samples(8);
  rusage usage0{};
  getrusage(RUSAGE_THREAD, &usage0);
  for (std::int64_t i = 0; i < updates; ++i) {
    const SacUpdateTimes before = sac.update_times();
    const double cpu0 = thread_cpu_seconds();
    sac.train_until(envs, sac.env_steps() + 1);
    samples[7].push_back(thread_cpu_seconds() - cpu0);
    const SacUpdateTimes after = sac.update_times();
    const double parts[] = {after.batch - before.batch, after.target - before.target, after.critic - before.critic,
                            after.actor - before.actor, after.alpha - before.alpha,   after.polyak - before.polyak};
    double total = 0.0;
    for (int p = 0; p < 6; ++p) {
      samples[std::size_t(p)].push_back(parts[p]);
      total += parts[p];
    }
    samples[6].push_back(total);
  }
  rusage usage1{};
  getrusage(RUSAGE_THREAD, &usage1);
  std::printf("SAC update, %lld observations, 21 actions, config %s: ms over %lld updates\n", observations,
              c.to_json().dump().c_str(), static_cast<long long>(updates));
  std::printf(
      "(CPU ms of the updating thread per part; cpu: per environment step + update)\n"
      "         median   10%%\n");
  for (std::size_t p = 0; p < 8; ++p)
    std::printf("  %-7s %7.3f %7.3f\n", names[p], 1e3 * quantile(samples[p], 0.5), 1e3 * quantile(samples[p], 0.1));
  std::printf("page faults per update: %.1f\n", double(usage1.ru_minflt - usage0.ru_minflt) / double(updates));
  // The learner's state after a fixed number of updates: a faster update must leave it bitwise
  // unchanged (same hash) or say why it moves by round-off (compare the sums).
  const std::vector<float> params = sac.parameters();
  std::uint64_t hash = 1469598103934665603ull;  // FNV-1a over the parameter bytes
  double sum = 0.0;
  for (float x : params) {
    unsigned char bytes[sizeof x];
    std::memcpy(bytes, &x, sizeof x);
    for (unsigned char b : bytes) hash = (hash ^ b) * 1099511628211ull;
    sum += double(x);
  }
  std::printf("parameters: %zu, sum %.9g, FNV-1a %016llx, alpha %.9g\n", params.size(), sum,
              static_cast<unsigned long long>(hash), sac.alpha());
  return 0;
}
