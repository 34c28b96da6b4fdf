// The lowest simulation rate that gives the thesis's 600 Hz jump outcomes (the jump `quick` rate): the
// same action sequences from the same take-off states at 600 Hz and lower rates, compared by
// outcome (success / touched obstacle / touched ground / timed out, and the control step it came
// at), the crossing feature (up-angle at the bar, over sequences that cross at both rates with the
// same outcome) and the COM's peak height.
//
//   jump_sim_rate_bench [--sequences N] [--seed S]
//
// Sequences: random take-off features (uniform in takeoff_features' ranges) and target poses that
// wander smoothly around the take-off pose (u_t = 0.8·u_{t−1} + 0.2·N(0, 1) per joint, the target
// the take-off pose + 0.3·u half-widths of the action box), plus the take-off pose held at the
// middle of the ranges; the same per control step at every rate, so a rate is compared only where
// its control rate equals 600 Hz's (f_control is rounded to a divisor of sim_hz). Untrained
// actions: most jumps end within a few control steps (a body other than the take-off foot
// touches the ground), so this measures the take-off and flight, not a trained clearance.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "bench_args.h"
#include "jump_env.h"
#include "podium/base/rng.h"
#include "podium/character/pose_bridge.h"

namespace jump = podium::tasks::jump;

namespace {

struct Episode {
  jump::Outcome outcome = jump::Outcome::in_flight;
  int steps = 0;
  double up_angle = 0.0, com_peak = 0.0;
  bool crossed = false;
};

struct Sequence {
  std::vector<double> features;
  std::vector<std::vector<double>> actions;  // per control step
};

Episode run(jump::JumpSettings s, const Sequence& seq) {
  s.takeoff_features = seq.features;
  jump::JumpEnv env(s);
  env.seed(1);
  std::vector<double> obs;
  env.reset(obs);
  podium::learn::StepResult r;
  Episode e;
  for (const auto& a : seq.actions) {
    env.step(a, r);
    ++e.steps;
    e.com_peak = std::max(e.com_peak, env.features().com.z());
    if (r.terminated || r.truncated) break;
  }
  e.outcome = env.outcome();
  e.up_angle = env.crossing().up_angle();
  e.crossed = env.crossing().crossed();
  return e;
}

std::vector<Sequence> sequences(jump::JumpKind kind, int n, std::uint64_t seed, const jump::JumpEnv& env, int steps) {
  const podium::learn::BoxSpace box = env.action_space();
  const std::vector<double> takeoff = podium::character::PoseBridge(env.world().model_ptr()).pose(env.takeoff().q);
  std::vector<Sequence> out;
  for (int k = 0; k <= n; ++k) {
    podium::base::Rng rng(podium::base::derive_seed(seed, static_cast<std::uint64_t>(k)));
    Sequence s;
    for (const auto& f : jump::takeoff_features(kind))
      s.features.push_back(k == 0 ? 0.5 * (f.low + f.high) : rng.uniform(f.low, f.high));
    std::vector<double> u(box.size(), 0.0);
    for (int t = 0; t < steps; ++t) {
      std::vector<double> a(box.size());
      for (std::size_t j = 0; j < box.size(); ++j) {
        if (k > 0) u[j] = 0.8 * u[j] + 0.2 * rng.normal();  // k = 0: the take-off pose held
        a[j] = std::clamp(takeoff[j] + 0.3 * 0.5 * (box.high[j] - box.low[j]) * u[j], box.low[j], box.high[j]);
      }
      s.actions.push_back(std::move(a));
    }
    out.push_back(std::move(s));
  }
  return out;
}

void compare(jump::JumpKind kind, double z, int n, std::uint64_t seed) {
  jump::JumpSettings s;
  s.kind = kind;
  s.difficulty_m = z;
  const double rho = jump::difficulty_ratio(kind, z);
  const double reference_hz = jump::control_hz_for(rho, 600.0);
  const auto seqs = sequences(kind, n, seed, jump::JumpEnv(s), static_cast<int>(std::ceil(2.0 * reference_hz)));
  std::printf("\n%s, z = %.2f m (control %.0f Hz at 600 Hz), %zu sequences\n", jump::jump_kind_name(kind), z, reference_hz,
              seqs.size());
  std::printf("  sim_hz  control  same outcome+step  same outcome  max |Δ up-angle|  max |Δ COM peak|  mean steps  ms/episode\n");
  std::vector<Episode> reference;
  for (double hz : {600.0, 300.0, 200.0, 150.0, 120.0, 100.0}) {
    s.sim_hz = hz;
    const double control = jump::control_hz_for(rho, hz);
    if (control != reference_hz) {
      std::printf("  %6.0f  %5.0f Hz  (control rate differs from 600 Hz's: not comparable)\n", hz, control);
      continue;
    }
    std::vector<Episode> episodes;
    const auto t0 = std::chrono::steady_clock::now();
    for (const auto& seq : seqs) episodes.push_back(run(s, seq));
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() /
                      static_cast<double>(seqs.size());
    if (reference.empty()) reference = episodes;
    int same_step = 0, same = 0;
    double angle = 0.0, peak = 0.0, steps = 0.0;
    for (std::size_t i = 0; i < episodes.size(); ++i) {
      const Episode &a = episodes[i], &b = reference[i];
      if (a.outcome == b.outcome) {
        ++same;
        if (a.steps == b.steps) ++same_step;
        if (a.crossed && b.crossed) angle = std::max(angle, std::abs(a.up_angle - b.up_angle));
      }
      peak = std::max(peak, std::abs(a.com_peak - b.com_peak));
      steps += a.steps / static_cast<double>(episodes.size());
    }
    std::printf("  %6.0f  %5.0f Hz  %8d/%zu          %6d/%zu      %8.3f rad      %8.3f m     %6.1f    %7.2f\n", hz, control,
                same_step, episodes.size(), same, episodes.size(), angle, peak, steps, ms);
  }
}

}  // namespace

int main(int argc, char** argv) {
  int sequences_n = 20;
  long long seed = 7;
  bool ok = argc % 2 == 1;
  for (int i = 1; ok && i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--sequences")) ok = podium::bench::count(argv[i + 1], 1, 100'000, sequences_n);
    else if (!std::strcmp(argv[i], "--seed")) ok = podium::bench::whole_number(argv[i + 1], 0, seed);
    else ok = false;
  }
  if (!ok) {
    std::fprintf(stderr, "usage: %s [--sequences N ≥ 1] [--seed S ≥ 0]\n", argv[0]);
    return 2;
  }
  std::printf("jump_sim_rate_bench: outcomes at lower simulation rates against 600 Hz (thesis §3.6.2)\n");
  const auto seed_u = static_cast<std::uint64_t>(seed);
  compare(jump::JumpKind::high_jump, 0.5, sequences_n, seed_u);
  compare(jump::JumpKind::high_jump, 0.75, sequences_n, seed_u);
  compare(jump::JumpKind::obstacle, 0.05, sequences_n, seed_u);
  return 0;
}
