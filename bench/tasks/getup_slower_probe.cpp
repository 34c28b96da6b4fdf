// Where π_slow loses its reference (bar (d) of tasks/getup/RESULTS.md): for fresh falls, π_weak's τ_fast (how
// long it stays low and how fast it climbs the upper half of its COM rise) and how a π_slow, or
// the bare PD tracking of the reference (zero residual), follows τ_slow at one κ: the steps
// tracked, how the episode ended, the COM against the reference where τ_slow ends, the highest
// head top. At the frame where τ_fast's upper climb starts it also shows what a slowed copy must
// do without momentum: the bodies on the ground and how far the COM's ground projection lies
// from the nearer foot (a static rise needs it over a foot; standing: half the stance width); and
// the climb's peak knee and hip speed, against which π_slow's PD (k_d = k_p/10, residuals within
// ±1 rad) keeps k_p·(1 + e − |q̇|/10) of torque (e: its tracking lag, rad).
//
//   getup_slower_probe WEAK_POLICY STRENGTH KAPPA [FALLS] [SLOW_POLICY|-] [REFERENCE_END_M]
//
// WEAK_POLICY: a Weaker TorchScript export and the strength β it passed at; SLOW_POLICY: a Slower
// export trained on that π_weak (omitted or -: zero residual). Falls use seeds 1000, 1001, … with
// the task's default settings (the seed repository's body; π_weak at 200 Hz, π_slow at 800 Hz,
// 40 Hz control; τ_fast until one step after the head origin passes REFERENCE_END_M, 1.4 m unless
// given).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "bench_args.h"
#include "podium/learn/frozen_policy.h"
#include "slower_env.h"

using namespace podium;
using podium::tasks::getup::FastRollout;

namespace {

// The fast seconds τ_fast takes for the upper half of its COM climb (from its last frame below
// halfway between the fall's end and the head-up frame).
double final_climb_s(const FastRollout& fast, double dt) {
  const double low = fast.com_height_m.front(), high = fast.com_height_m.back();
  int from = fast.steps();
  while (from > 0 && fast.com_height_m[static_cast<std::size_t>(from - 1)] > low + 0.5 * (high - low)) --from;
  return (fast.steps() - from) * dt;
}

// The first frame of the upper half of τ_fast's COM climb.
int climb_start(const FastRollout& fast, double dt) {
  return fast.steps() - static_cast<int>(std::lround(final_climb_s(fast, dt) / dt));
}

// At pose q: the bodies touching the ground ("+"-joined) and the horizontal distance (m) from the
// COM to the nearer foot's centroid.
std::pair<std::string, double> support(sim::World& world, const Eigen::VectorXd& q) {
  world.reset(q, Eigen::VectorXd::Zero(world.model().nv()));
  const sim::Observation o = world.observe();
  const sim::CharacterModel& model = world.model();
  std::string on_ground;
  for (std::size_t b = 0; b < model.bodies().size(); ++b)
    if (o.touches(static_cast<int>(b), sim::Contact::Partner::ground))
      on_ground += (on_ground.empty() ? "" : "+") + model.bodies()[b].name;
  double nearer = INFINITY;
  for (const char* foot : {"foot_right", "foot_left"})
    nearer = std::min(nearer, (o.com - world.body_centroid(model.find_body(foot))).head<2>().norm());
  return {on_ground.empty() ? "-" : on_ground, nearer};
}

// The largest |q̇| of the knees' and hips' y joints from frame `from` of τ_fast on, rad/s.
double peak_leg_speed(const sim::CharacterModel& model, const FastRollout& fast, int from) {
  double peak = 0.0;
  for (const char* joint : {"knee_right", "knee_left", "hip_y_right", "hip_y_left"}) {
    const int v = model.link(joint).v_index;
    for (std::size_t i = static_cast<std::size_t>(from); i < fast.qd.size(); ++i) peak = std::max(peak, std::abs(fast.qd[i](v)));
  }
  return peak;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  long long falls = 10;
  double strength = 0.0, kappa = 0.0;
  tasks::getup::SlowerSettings settings;
  if (argc < 4 || argc > 7 || !bench::real_number(argv[2], strength) || !(strength > 0.0 && strength <= 1.0) ||
      !bench::real_number(argv[3], kappa) || !(kappa > 0.0) || (argc > 4 && !bench::whole_number(argv[4], 1, falls)) ||
      (argc > 6 && (!bench::real_number(argv[6], settings.reference_end_m) || !(settings.reference_end_m > 0.0)))) {
    std::fprintf(stderr,
                 "usage: getup_slower_probe WEAK_POLICY STRENGTH(0,1] KAPPA>0 [FALLS>0] [SLOW_POLICY|-] [REFERENCE_END_M>0]\n");
    return 2;
  }
  try {
    const auto weak = std::make_shared<const learn::FrozenPolicy>(argv[1]);
    const std::unique_ptr<learn::FrozenPolicy> slow =
        argc > 5 && std::string(argv[5]) != "-" ? std::make_unique<learn::FrozenPolicy>(argv[5]) : nullptr;
    tasks::getup::SlowerEnv env({}, settings, weak, strength, kappa);
    sim::World still(env.world().model_ptr(), sim::WorldConfig{});
    std::vector<double> observation, action(env.action_space().size(), 0.0), low_s, climb_s, offset_m, speed;
    int reached = 0, stood = 0;
    std::printf("standing: COM %.2f m from the nearer foot\n", support(still, env.world().model().standing_pose()).second);
    std::printf(
        "κ %.2f, τ_fast to a head origin of %.2f m (and a step), %s\nfall  T(steps)  low s  upper climb s  steps  ended          "
        "  COM/ref at "
        "T/κ (m)  head top max (m)  climb: peak leg rad/s; at its start: COM–foot (m), on the ground\n",
        kappa, settings.reference_end_m, slow ? "π_slow" : "zero residual (PD on the reference)");
    for (long long k = 0; k < falls; ++k) {
      env.seed(1000 + static_cast<std::uint64_t>(k));
      env.reset(observation);
      const FastRollout& fast = env.reference_motion().fast();
      const double dt = env.control_dt_s();
      learn::StepResult step;
      int steps = 0;
      double head_max = 0.0, com_at_end = 0.0, ref_at_end = 0.0;
      for (;;) {
        if (slow) slow->act(observation, action);
        env.step(action, step);
        ++steps;
        head_max = std::max(head_max, env.weak().head_height_m);
        if (!env.standing_phase()) {
          com_at_end = env.features().com.z();
          ref_at_end = env.reference_motion().com_height_m(env.reference_time_s());
        }
        if (step.terminated || step.truncated) break;
        observation.swap(step.observation);
      }
      const bool standing = env.standing_phase();
      const char* ended = !standing ? "lost the COM" : step.terminated ? "fell after T/κ" : "stood to the end";
      reached += standing;
      stood += standing && !step.terminated;
      climb_s.push_back(final_climb_s(fast, dt));
      low_s.push_back(fast.steps() * dt - climb_s.back());
      const int climb = climb_start(fast, dt);
      const auto [on_ground, offset] = support(still, fast.q[static_cast<std::size_t>(climb)]);
      offset_m.push_back(offset);
      speed.push_back(peak_leg_speed(env.world().model(), fast, climb));
      std::printf("%4lld  %8d  %5.2f  %13.2f  %5d  %-16s  %.2f / %.2f           %.2f  %6.1f  %.2f  %s\n", k, fast.steps(),
                  low_s.back(), climb_s.back(), steps, ended, com_at_end, ref_at_end, head_max, speed.back(), offset,
                  on_ground.c_str());
    }
    std::printf(
        "medians: low %.2f s, upper climb %.2f s (fast time), its peak leg speed %.1f rad/s, COM to the nearer foot at its start "
        "%.2f m; "
        "reached T/κ in %d/%lld, stood to the end in %d/%lld\n",
        median(low_s), median(climb_s), median(speed), median(offset_m), reached, falls, stood, falls);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "getup_slower_probe: %s\n", error.what());
    return 1;
  }
  return 0;
}
