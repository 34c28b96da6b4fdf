// The simulation-rate probe (README.md "Simulation rate"): the same action sequences at 600 Hz and
// at lower rates (30 Hz control), their outcomes compared with 600 Hz's, as the jump measured its
// rate. Cases: the Start mode from each crouch start, its reference's next pose plus seeded noise
// as SPD targets (a start that tracks its reference for a while); and the plain environment from
// standing with seeded random targets for 2 s (falls). Prints a table; no training.
//
//   build/bin/sprint_sim_rate_probe [episodes per case, default 25]
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "crouch_start.h"
#include "podium/base/rng.h"
#include "podium/character/pose_bridge.h"
#include "sprint_env.h"

namespace sprint = podium::tasks::sprint;
using podium::base::Rng;

namespace {

struct Episode {
  sprint::SprintEnv::Outcome outcome = sprint::SprintEnv::Outcome::running;
  int steps = 0;
  double com_x = 0.0;
};

// One episode: the env's generator seeded, reset, then `steps` actions (or until it ends).
template <class Action>
Episode run(sprint::SprintEnv& env, std::uint64_t seed, int steps, const Action& action) {
  env.seed(seed);
  std::vector<double> observation, a(env.action_space().size());
  env.reset(observation);
  podium::learn::StepResult out;
  Episode e;
  Rng noise(seed + 17);
  for (int k = 0; k < steps; ++k) {
    action(env, k, noise, a);
    env.step(a, out);
    ++e.steps;
    if (out.terminated || out.truncated) break;
  }
  e.outcome = env.outcome();
  e.com_x = env.features().com.x();
  return e;
}

struct Case {
  std::string name;
  bool start_mode = false;
};

std::vector<Episode> run_case(const Case& c, double sim_hz, int episodes) {
  sprint::SprintEnvSettings s;
  s.preset = sprint::load_sprint_preset("quick");
  s.sim_hz = sim_hz;
  s.fixed_draw = sprint::EpisodeDraw{};
  if (c.start_mode)
    s.start_references = sprint::crouch_start_references(podium::sim::load_shipped_model(s.model), s.control_hz, s.preset.start);
  sprint::SprintEnv env(s);
  const podium::character::PoseBridge bridge(env.world().model_ptr());
  std::vector<Episode> out;
  for (int i = 0; i < episodes; ++i) {
    if (c.start_mode) {
      out.push_back(run(env, 1000 + i, 40, [&](sprint::SprintEnv& e, int k, Rng& noise, std::vector<double>& a) {
        const auto& clip = e.imitation().clip();
        const std::vector<double> target = bridge.pose(clip.poses[std::min<std::size_t>(k + 1, clip.size() - 1)]);
        for (std::size_t j = 0; j < a.size(); ++j) a[j] = target[j] + 0.1 * noise.normal();
      }));
    } else {
      out.push_back(run(env, 2000 + i, 60, [&](sprint::SprintEnv&, int, Rng& noise, std::vector<double>& a) {
        for (double& v : a) v = noise.uniform(-0.5, 0.5);
      }));
    }
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  const int episodes = argc > 1 ? std::atoi(argv[1]) : 25;
  const std::vector<Case> cases = {{"start: reference + noise", true}, {"standing: random targets", false}};
  const std::vector<double> rates = {600, 300, 210, 150, 120, 90, 60};
  std::printf(
      "| case | rate Hz | same outcome | same outcome and step | max |Δ COM x| m | ms/episode |\n|---|---|---|---|---|---|\n");
  for (const Case& c : cases) {
    std::vector<Episode> reference;
    for (const double hz : rates) {
      const auto t0 = std::chrono::steady_clock::now();
      const std::vector<Episode> e = run_case(c, hz, c.start_mode ? 4 * episodes : episodes);
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() /
                        static_cast<double>(e.size());
      if (reference.empty()) reference = e;
      int same = 0, same_step = 0;
      double dx = 0.0;
      for (std::size_t i = 0; i < e.size(); ++i) {
        same += e[i].outcome == reference[i].outcome ? 1 : 0;
        same_step += e[i].outcome == reference[i].outcome && e[i].steps == reference[i].steps ? 1 : 0;
        if (e[i].outcome == reference[i].outcome) dx = std::max(dx, std::abs(e[i].com_x - reference[i].com_x));
      }
      int landed = 0, fell = 0;
      for (const Episode& x : e)
        landed += x.outcome == sprint::SprintEnv::Outcome::landed, fell += x.outcome == sprint::SprintEnv::Outcome::fell;
      std::printf("| %s | %.0f | %d/%zu | %d | %.3f | %.1f | (landed %d, fell %d)\n", c.name.c_str(), hz, same, e.size(),
                  same_step, dx, ms, landed, fell);
      std::fflush(stdout);
    }
  }
  return 0;
}
