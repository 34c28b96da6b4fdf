// Benchmark B: simulated seconds per wall second on one core for humanoid21 under random PD
// targets (ragdoll drops, lying, rolling), next to MuJoCo 2.2.2 simulating the same body layout
// (../shared/peers/mujoco/humanoid.xml) under the same protocol, in the same run.
#include <mujoco/mujoco.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "bench_args.h"
#include "podium/base/rng.h"
#include "podium/sim/dynamics.h"
#include "podium/sim/starts.h"
#include "podium/sim/world.h"

using namespace podium::sim;
using Clock = std::chrono::steady_clock;

namespace {

constexpr double kSimSeconds = 30.0;     // per measurement
constexpr double kEpisodeSeconds = 5.0;  // a new ragdoll drop every 5 s
constexpr double kControlHz = 10.0;
// Sane physics, checked the same way for both engines: kinetic energy (after every control step)
// stays below a blow-up bound, and no body geom sinks deeper than this into the floor at any
// simulation step (sampled every step: sampling per control step would look at a smaller share
// of the steps the smaller Δt is).
constexpr double kMaxEnergyJ = 2000.0;
constexpr double kMaxPenetrationM = 0.05;

// The standing check of the SPD stability test (root servo, model gains) at sim rate hz.
bool standing_holds(const ModelPtr& model, double hz, Control mode) {
  WorldConfig config;
  config.sim_hz = hz;
  config.control_hz = hz;
  World world(model, config);
  Gains gains = Gains::from_model(*model);
  gains.kp.head<6>().setConstant(20000.0);
  gains.kd.head<6>().setConstant(2000.0);
  world.set_gains(gains);
  const double h0 = world.observe().head_height_m;
  for (int k = 0; k < static_cast<int>(10 * hz); ++k) {
    if (!world.control_step(mode, model->standing_pose()).ok || world.observe().head_height_m < 0.9 * h0) return false;
  }
  return true;
}

struct Result {
  double rtf = 0, steps_per_s = 0, max_energy = 0, lowest_m = 0;
  bool ok = true;  // finite throughout
  bool sane() const { return ok && max_energy < kMaxEnergyJ && lowest_m > -kMaxPenetrationM; }
};

Result run_bullet(const ModelPtr& model, double hz, std::uint64_t seed, Control mode) {
  WorldConfig config;
  config.sim_hz = hz;
  config.control_hz = kControlHz;
  World world(model, config);
  podium::base::Rng rng(seed);
  Result r;
  const int controls = static_cast<int>(kSimSeconds * kControlHz), per_episode = static_cast<int>(kEpisodeSeconds * kControlHz);
  const auto t0 = Clock::now();
  for (int k = 0; k < controls && r.ok; ++k) {
    if (k % per_episode == 0) {
      Eigen::VectorXd q = random_pose(*model, rng, 1.5);
      world.reset(q, Eigen::VectorXd::Zero(model->nv()));
    }
    const Eigen::VectorXd target = random_pose(*model, rng, 0.0);
    for (int s = 0; s < world.substeps() && r.ok; ++s) {
      r.ok = world.sim_step(mode, target).ok;
      r.lowest_m = std::min(r.lowest_m, lowest_geom_point(*model, world.data()));
    }
    r.max_energy = std::max(r.max_energy, world.kinetic_energy());
  }
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  r.rtf = kSimSeconds / wall;
  r.steps_per_s = kSimSeconds * hz / wall;
  return r;
}

// MuJoCo's counterparts of Podium's checks: kinetic energy ½ q̇ᵀM q̇ and the lowest point of any
// body geom (sphere or capsule, as lowest_geom_point) from the positions of the last mj_step's
// forward pass (the state at the start of that step).
double kinetic_energy(const mjModel* m, mjData* d) {
  std::vector<double> Mv(m->nv);
  mj_mulM(m, d, Mv.data(), d->qvel);
  return 0.5 * mju_dot(d->qvel, Mv.data(), m->nv);
}

double lowest_geom_point(const mjModel* m, const mjData* d) {
  double z = 1e9;
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->geom_bodyid[g] == 0) continue;  // the floor
    const double* size = m->geom_size + 3 * g;
    const double half_length = m->geom_type[g] == mjGEOM_CAPSULE ? size[1] : 0.0;
    z = std::min(z, d->geom_xpos[3 * g + 2] - std::abs(d->geom_xmat[9 * g + 8]) * half_length - size[0]);
  }
  return z;
}

// PD through the motors toward joint targets: kp = gear (the seed's torque limit), kd = kp/10, as
// in Podium's model, clamped to the motor range.
void motor_pd(const mjModel* m, mjData* d, const std::vector<double>& target) {
  for (int a = 0; a < m->nu; ++a) {
    const int j = m->actuator_trnid[2 * a];
    const double gear = m->actuator_gear[6 * a];
    const double tau = gear * (target[a] - d->qpos[m->jnt_qposadr[j]]) - 0.1 * gear * d->qvel[m->jnt_dofadr[j]];
    d->ctrl[a] = std::clamp(tau / gear, -1.0, 1.0);
  }
}

// The standing check of Podium's row, in MuJoCo: from humanoid.xml's standing qpos0 the motors
// hold the joints at 0 with the workload's PD (kp = gear, kd = kp/10, clamped to the motor range);
// the root assist is MuJoCo's own implicit form of Podium's root servo, a weld of the torso to the
// world (an explicit 20000/2000 servo through xfrc_applied diverges at 5 ms, as plain PD does).
// The head must stay above 90% of its height for 10 s. `welded` has the weld added.
bool mujoco_standing_holds(mjModel* welded, double dt) {
  welded->opt.timestep = dt;
  mjData* d = mj_makeData(welded);
  mj_forward(welded, d);
  const int head = mj_name2id(welded, mjOBJ_BODY, "head");
  const double h0 = d->xpos[3 * head + 2];
  const std::vector<double> standing(welded->nu, 0.0);
  bool holds = true;
  for (int s = 0; s < static_cast<int>(10.0 / dt) && holds; ++s) {
    motor_pd(welded, d, standing);
    mj_step(welded, d);
    holds = std::isfinite(d->qvel[0]) && d->warning[mjWARN_BADQACC].number == 0 && d->xpos[3 * head + 2] > 0.9 * h0;
  }
  mj_deleteData(d);
  return holds;
}

// humanoid.xml with `<weld body1="torso"/>` (satisfied at qpos0), loaded from a temporary copy.
mjModel* load_welded(const std::string& xml_path) {
  std::ifstream in(xml_path);
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const auto end = text.rfind("</mujoco>");
  if (end == std::string::npos) return nullptr;
  text.insert(end, "  <equality><weld body1=\"torso\"/></equality>\n");
  const auto path = std::filesystem::temp_directory_path() / ("podium-welded-humanoid-" + std::to_string(::getpid()) + ".xml");
  std::ofstream(path) << text;
  char error[1000] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
  std::filesystem::remove(path);
  return m;
}

Result run_mujoco(const mjModel* m, std::uint64_t seed) {
  mjData* d = mj_makeData(m);
  podium::base::Rng rng(seed);
  Result r;
  const double dt = m->opt.timestep;
  const int steps = static_cast<int>(kSimSeconds / dt), per_control = static_cast<int>(std::lround(1.0 / (kControlHz * dt)));
  const int per_episode = static_cast<int>(kEpisodeSeconds / dt);
  std::vector<double> target(m->nu);
  const auto t0 = Clock::now();
  for (int s = 0; s < steps; ++s) {
    if (s % per_episode == 0) {
      mj_resetData(m, d);
      d->qpos[2] = 1.5;
      const double u1 = rng.uniform(), u2 = rng.uniform(0, 2 * M_PI), u3 = rng.uniform(0, 2 * M_PI);
      d->qpos[3] = std::sqrt(1 - u1) * std::sin(u2);
      d->qpos[4] = std::sqrt(1 - u1) * std::cos(u2);
      d->qpos[5] = std::sqrt(u1) * std::sin(u3);
      d->qpos[6] = std::sqrt(u1) * std::cos(u3);
      for (int j = 1; j < m->njnt; ++j) d->qpos[m->jnt_qposadr[j]] = rng.uniform(m->jnt_range[2 * j], m->jnt_range[2 * j + 1]);
    }
    if (s % per_control == 0) {
      for (int a = 0; a < m->nu; ++a) {
        const int j = m->actuator_trnid[2 * a];
        target[a] = rng.uniform(m->jnt_range[2 * j], m->jnt_range[2 * j + 1]);
      }
    }
    motor_pd(m, d, target);
    mj_step(m, d);
    r.lowest_m = std::min(r.lowest_m, lowest_geom_point(m, d));
    if ((s + 1) % per_control == 0) r.max_energy = std::max(r.max_energy, kinetic_energy(m, d));
  }
  const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
  // MuJoCo resets the state itself when accelerations go bad; count that as a blow-up.
  r.ok = std::isfinite(d->qvel[0]) && d->warning[mjWARN_BADQACC].number == 0;
  r.rtf = kSimSeconds / wall;
  r.steps_per_s = steps / wall;
  mj_deleteData(d);
  return r;
}

// One seed's workload repeated kRepetitions times (deterministic, so the checks repeat exactly):
// the fastest repetition is the timing. 30 simulated s take well under 0.1 s of wall time at
// these rates, too short for one run to time reliably on a shared machine.
constexpr int kRepetitions = 5;
template <class Run>
Result fastest_of_repetitions(Run&& run, std::uint64_t seed) {
  Result best = run(seed);
  for (int k = 1; k < kRepetitions; ++k) {
    const Result r = run(seed);
    if (r.rtf > best.rtf) best.rtf = r.rtf, best.steps_per_s = r.steps_per_s;
  }
  return best;
}

// Median real-time factor over seeds 1..3 (the worst workload check counts).
template <class Run>
Result median_of_3(Run&& run) {
  Result rs[3] = {fastest_of_repetitions(run, 1), fastest_of_repetitions(run, 2), fastest_of_repetitions(run, 3)};
  std::sort(std::begin(rs), std::end(rs), [](const Result& a, const Result& b) { return a.rtf < b.rtf; });
  Result r = rs[1];
  for (const Result& x : rs) {
    r.ok = r.ok && x.ok;
    r.max_energy = std::max(r.max_energy, x.max_energy);
    r.lowest_m = std::min(r.lowest_m, x.lowest_m);
  }
  return r;
}

}  // namespace

// Usage: sim_engine_bench [HZ ...] — Podium rows to run (default: all rates below).
int main(int argc, char** argv) {
  std::vector<double> rates = {30.0, 60.0, 120.0, 240.0, 480.0, 800.0};
  if (argc > 1) rates.assign(argc - 1, 0.0);
  for (int i = 1; i < argc; ++i) {
    // The workload's 10 Hz control must divide the rate (World refuses it otherwise).
    if (!podium::bench::real_number(argv[i], rates[i - 1]) || rates[i - 1] < kControlHz ||
        std::fmod(rates[i - 1], kControlHz) != 0) {
      std::fprintf(stderr, "%s: bad value '%s' for HZ\nusage: %s [HZ ...]  (each a multiple of %g)\n", argv[0], argv[i], argv[0],
                   kControlHz);
      return 2;
    }
  }
  const ModelPtr model = load_shipped_model("humanoid21");
  std::printf(
      "Benchmark B: humanoid21, random SPD targets every 1/%g s, ragdoll drop every %g s, %g simulated s per row (median of "
      "seeds 1-3, fastest of %d repetitions each), one core\n",
      kControlHz, kEpisodeSeconds, kSimSeconds, kRepetitions);
  std::printf("%-8s %8s %10s %12s %10s %9s %10s %10s\n", "engine", "dt (ms)", "standing", "workload ok", "steps/s", "x real",
              "max KE J", "lowest m");
  double best_rtf = 0, best_dt = 0;
  for (double hz : rates) {
    const bool stands = standing_holds(model, hz, Control::spd_maba);
    const Result r = median_of_3([&](std::uint64_t seed) { return run_bullet(model, hz, seed, Control::spd_maba); });
    std::printf("%-8s %8.2f %10s %12s %10.0f %9.1f %10.1f %10.3f\n", "podium", 1000.0 / hz, stands ? "holds" : "falls",
                r.sane() ? "yes" : "NO", r.steps_per_s, r.rtf, r.max_energy, r.lowest_m);
    if (stands && r.sane() && best_dt == 0) {
      best_rtf = r.rtf;
      best_dt = 1.0 / hz;
    }
  }
  // The same checks with the PD inside the velocity solve (Control::spd_implicit), for its cost
  // and its rates; the verdict below stays the SPD row's.
  for (double hz : rates) {
    const bool stands = standing_holds(model, hz, Control::spd_implicit);
    const Result r = median_of_3([&](std::uint64_t seed) { return run_bullet(model, hz, seed, Control::spd_implicit); });
    std::printf("%-8s %8.2f %10s %12s %10.0f %9.1f %10.1f %10.3f\n", "podium-i", 1000.0 / hz, stands ? "holds" : "falls",
                r.sane() ? "yes" : "NO", r.steps_per_s, r.rtf, r.max_energy, r.lowest_m);
  }
  // Bad accelerations are counted per run (mjWARN_BADQACC) instead of printed into the table.
  mju_user_warning = [](const char*) {};
  const std::string xml = std::string(PODIUM_SHARED_DIR) + "/peers/mujoco/humanoid.xml";
  char error[1000] = "";
  mjModel* m = mj_loadXML(xml.c_str(), nullptr, error, sizeof error);
  mjModel* welded = m ? load_welded(xml) : nullptr;
  if (!m || !welded) {
    std::printf("mujoco: cannot load %s: %s\n", xml.c_str(), error);
    return 1;
  }
  // Each engine at the largest Δt at which its standing check holds and its workload is sane
  // (sim/README.md); MuJoCo's default Δt is shown too, as it is the rate MuJoCo users know.
  const double default_dt = m->opt.timestep;
  std::vector<double> dts = {default_dt};
  for (double hz : rates) dts.push_back(1.0 / hz);
  std::sort(dts.begin(), dts.end(), std::greater<>());
  Result mj_default, mj_best;
  double mj_best_dt = 0;
  for (double dt : dts) {
    m->opt.timestep = dt;
    const bool stands = mujoco_standing_holds(welded, dt);
    const Result mj = median_of_3([&](std::uint64_t seed) { return run_mujoco(m, seed); });
    const bool is_default = dt == default_dt;
    std::printf("%-8s %8.2f %10s %12s %10.0f %9.1f %10.1f %10.3f%s\n", "mujoco", 1000.0 * dt, stands ? "holds" : "falls",
                mj.sane() ? "yes" : "NO", mj.steps_per_s, mj.rtf, mj.max_energy, mj.lowest_m, is_default ? "  (default dt)" : "");
    if (is_default) mj_default = mj;
    if (stands && mj.sane() && mj_best_dt == 0) {
      mj_best = mj;
      mj_best_dt = dt;
    }
  }
  if (best_dt == 0 || mj_best_dt == 0) {
    std::printf("largest admissible dt: %s has none among the rates run; no verdict\n", best_dt == 0 ? "podium" : "MuJoCo");
  } else {
    std::printf(
        "largest admissible dt: podium %.2f ms, %.1fx real time; MuJoCo %.2f ms, %.1fx; ratio %.2f; bar (>= MuJoCo): %s\n",
        best_dt * 1000, best_rtf, mj_best_dt * 1000, mj_best.rtf, best_rtf / mj_best.rtf,
        best_rtf >= mj_best.rtf ? "met" : "NOT met");
  }
  std::printf("MuJoCo at its default %.1f ms: %.1fx; podium / that: %.2f\n", default_dt * 1000, mj_default.rtf,
              best_rtf / mj_default.rtf);
  mj_deleteModel(welded);
  mj_deleteModel(m);
  return 0;
}
