// Benchmark A: stable-PD cost per simulation step, MABA vs dense factorisation, on humanoid21,
// humanoid34 and chains of 36, 72 and 195 DoF, beside the thesis's Tables 2.2/2.3. Also counts
// heap allocations inside SPD and inside a full step (docs/style.md: none expected inside SPD).
// "dense" and "MABA" are the public calls, each with its forward kinematics, so they compare like
// with like. "SPD %" is SPD's share of the step as the step runs it: World::sim_step ends with
// forward kinematics (collision detection and observations need the pose), and the next step's
// MABA reuses that pose, so SPD adds MABA minus FK to a step.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <vector>

#include "podium/base/rng.h"
#include "podium/sim/dynamics.h"
#include "podium/sim/starts.h"
#include "podium/sim/world.h"

namespace {
std::atomic<long long> g_allocations{0};
}  // namespace

void* operator new(std::size_t n) {
  ++g_allocations;
  if (void* p = std::malloc(n)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

using namespace podium::sim;
using Clock = std::chrono::steady_clock;

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

template <class F>
double median_ns(F&& f, int reps, int runs = 7) {
  std::vector<double> t;
  for (int r = 0; r < runs; ++r) {
    const auto a = Clock::now();
    for (int i = 0; i < reps; ++i) f();
    t.push_back(std::chrono::duration<double, std::nano>(Clock::now() - a).count() / reps);
  }
  return median(t);
}

struct Row {
  const char* label;
  ModelPtr model;
  const char* thesis;  // Table 2.2 FPS (DF / MABA) and Table 2.3 SPD share (DF / MABA)
};

}  // namespace

int main() {
  std::vector<Row> rows = {
      {"humanoid21", load_shipped_model("humanoid21"), "  —"},
      {"humanoid34", load_shipped_model("humanoid34"), "humanoid (34): 13,752 / 20,224 fps; 31.1% / 2.1%"},
      {"chain36", make_chain(11), "snake1 (36): 11,897 / 16,444 fps; 28.0% / 1.7%"},
      {"chain72", make_chain(23), "snake2 (72): 5,099 / 8,334 fps; 39.9% / 2.5%"},
      {"chain195", make_chain(64), "snake3 (195): 1,036 / 3,036 fps; 64.4% / 3.7%"},
  };
  std::printf(
      "Benchmark A: SPD per call and full simulation step with MABA SPD at 600 Hz, lying on flat ground (medians of 7 runs, seed "
      "1)\n");
  std::printf("%-11s %4s %11s %11s %7s %8s %12s %9s %10s   thesis (PhysX, DF / MABA)\n", "model", "nv", "dense ns", "MABA ns",
              "ratio", "FK ns", "step ns", "SPD %", "allocs");
  for (const Row& row : rows) {
    const CharacterModel& m = *row.model;
    podium::base::Rng rng(1);
    WorldConfig config;
    config.sim_hz = 600;
    config.control_hz = 30;
    // SPD is implicit only unclamped: the chains' 50 N·m limits saturate at kp = 200, and clamped
    // SPD in contact blew chain72 up (kinetic energy 1e14 J within 80 steps), which left the step
    // figure timing a broken state.
    config.torque_limits = false;
    World world(row.model, config);
    // Humanoids drop from a random pose; chains start straight on the ground (a random pose curls
    // a long chain into itself, and pushing 64 links apart blew chain195 up with either step).
    Eigen::VectorXd q = random_pose(m, rng, 0.5, 0.3);
    if (row.model->name().rfind("chain", 0) == 0) q = m.standing_pose();
    q.segment<4>(3) << 1, 0, 0, 0;
    world.set_state(q, Eigen::VectorXd::Zero(m.nv()));
    for (int k = 0; k < 30; ++k) world.control_step(Control::torque, Eigen::VectorXd::Zero(m.nv()));  // settle
    const Eigen::VectorXd target = random_pose(m, rng, 0.5, 0.3);
    CharacterData data = world.data();
    const Gains gains = Gains::from_model(m);
    const int reps = std::max(200, 200000 / m.nv());
    const double dense = median_ns([&] { stable_pd_dense(m, data, gains, target, 1.0 / 600); }, reps / 4);
    const long long before = g_allocations.load();
    stable_pd_maba(m, data, gains, target, 1.0 / 600);
    const long long spd_allocs = g_allocations.load() - before;
    const long long before_step = g_allocations.load();
    world.sim_step(Control::spd_maba, target);
    const long long step_allocs = g_allocations.load() - before_step;
    // MABA, FK and 600 steps (1 s) from the same state, interleaved in each of 7 runs, so each run's
    // share divides figures taken under the same machine load; medians over the runs.
    const Eigen::VectorXd q0 = world.data().q, qd0 = world.data().qd;
    std::vector<double> mabas, fks, steps, shares;
    for (int r = 0; r < 7; ++r) {
      mabas.push_back(median_ns([&] { stable_pd_maba(m, data, gains, target, 1.0 / 600); }, reps, 1));
      fks.push_back(median_ns([&] { forward_kinematics(m, data); }, reps, 1));
      world.set_state(q0, qd0);
      steps.push_back(median_ns([&] { world.sim_step(Control::spd_maba, target); }, 600, 1));
      shares.push_back((mabas.back() - fks.back()) / steps.back());
    }
    const double maba = median(mabas), fk = median(fks), step = median(steps), share = median(shares);
    std::printf("%-11s %4d %11.0f %11.0f %6.1fx %8.0f %12.0f %8.1f%% %4lld/%-5lld   %s%s\n", row.label, m.nv(), dense, maba,
                dense / maba, fk, step, 100.0 * share, spd_allocs, step_allocs, row.thesis,
                world.data().qd.allFinite() ? "" : "  (STATE NOT FINITE: step time invalid)");
  }
  std::printf(
      "SPD %%: (MABA - FK) / step, SPD's share of a step that already has its pose (median over the 7 runs of each run's "
      "share)\n");
  std::printf(
      "allocs: C++ heap allocations (operator new) in one MABA SPD call / in one full step; Bullet allocates through malloc and "
      "is not counted\n");
  return 0;
}
