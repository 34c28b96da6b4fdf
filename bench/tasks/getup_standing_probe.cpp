// Can the get-up's body stand at all under the task's control (torques chosen at 40 Hz and held
// for a control step's simulation steps)? The `quick` Weaker policies rise but never stand; this
// separates "the physics cannot hold a stand at that control rate and strength" from "the policy
// has not learned to". A joint-space PD towards the standing pose (App. D's kp = torque limit,
// kd = kp/10, scaled) stands in for the policy: it is computed once per control step and held
// (as a policy's torque is), and, for comparison, evaluated at every simulation step.
//
// The same PD runs, in the same program, on the peer: MuJoCo 2.2.2 with a MuJoCo body (the peer's
// ../shared/peers/mujoco/humanoid.xml, or the file given, e.g. the seed repository's
// data/humanoid_static.xml, set down onto the floor), at the same rate with its passive joints as
// the file has them, and once more bare (armature, damping and stiffness 0). Podium runs
// humanoid21_seed (armature, frictionless self-contact) with passive_joints, and humanoid21
// without them (the body `quick` trained on before the get-up took the seed's).
//
// Prints, for each engine, strength β, gain scale and hold, how long the head top stayed above
// 1.2 m from the standing pose (10 s at most) and the head top's range, then per Podium body the
// median over the rows held a whole control step of its time up over MuJoCo's as the file has it
// (the tipping-time ratio; 1: tips as fast as the seed's body). No row stands: both bodies need
// active balance, which a PD to a fixed pose does not give. Run (HZ: the simulation rate, 200 the
// seed's π_weak, 800 its π_slow; default 200):
//   build/bin/getup_standing_probe [seconds [mujoco.xml [HZ]]]
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "bench_args.h"
#include "getup_rewards.h"
#include "podium/sim/world.h"

namespace {

using podium::sim::Control;

constexpr double kControlHz = 40.0, kUpM = 1.2;  // the get-up task's control rate; §7's height
double sim_hz = 200.0;                           // the simulation rate of both engines (argument)

// How long the head top stayed above kUpM from the start, and its range.
struct Outcome {
  double stood_s = 0.0, lowest_m = 1e9, highest_m = -1e9;
  bool blew_up = false, standing = true;

  // The head top after control step `k` (from 0).
  void observe(int k, double head_top_m) {
    lowest_m = std::min(lowest_m, head_top_m);
    highest_m = std::max(highest_m, head_top_m);
    standing = standing && head_top_m > kUpM;
    if (standing) stood_s = (k + 1) / kControlHz;
  }
};

Outcome hold(const char* body, double strength, double gain_scale, double kd_ratio, int hold_steps, bool passive,
             double seconds) {
  const podium::sim::ModelPtr model = podium::sim::load_shipped_model(body);
  podium::sim::WorldConfig config;
  config.sim_hz = sim_hz;
  config.control_hz = kControlHz;
  config.strength = strength;
  config.passive_joints = passive;
  podium::sim::World world(model, config);
  const Eigen::VectorXd target = model->standing_pose();
  const Eigen::VectorXd kp = gain_scale * model->torque_limits();
  const Eigen::VectorXd kd = kd_ratio * kp;
  const auto pd_torque = [&] {
    const auto& d = world.data();
    Eigen::VectorXd tau = Eigen::VectorXd::Zero(model->nv());
    for (const podium::sim::Link& l : model->links())
      if (l.joint == podium::sim::JointType::revolute)
        tau(l.v_index) = kp(l.v_index) * (target(l.q_index) - d.q(l.q_index)) - kd(l.v_index) * d.qd(l.v_index);
    return tau;
  };
  const double head_top_m = podium::tasks::getup::BodyReadings::of(*model).head_top_m;
  Outcome out;
  for (int k = 0; k < static_cast<int>(seconds * kControlHz); ++k) {
    podium::sim::StepReport report;
    Eigen::VectorXd tau;
    for (int s = 0; s < world.substeps() && report.ok; ++s) {
      if (s % hold_steps == 0) tau = pd_torque();
      report = world.sim_step(Control::torque, tau);
    }
    if (!report.ok) {
      out.blew_up = true;
      break;
    }
    out.observe(k, world.observe().head_height_m + head_top_m);
  }
  return out;
}

// MuJoCo: the motors' PD toward qpos0 (standing), kp = scale × gear, clamped to β of the motor
// range; the head top is the head body's z plus its sphere's radius.
Outcome hold_mujoco(mjModel* m, double strength, double gain_scale, double kd_ratio, int hold_steps, double seconds) {
  m->opt.timestep = 1.0 / sim_hz;
  mjData* d = mj_makeData(m);
  // Set down onto the floor: the lowest root height without a contact (the seed repository's
  // file puts the torso at 1.5 m, its feet 0.2 m in the air).
  double free_m = d->qpos[2] + 1.0, touching_m = 0.0;
  for (int i = 0; i < 40; ++i) {
    d->qpos[2] = 0.5 * (free_m + touching_m);
    mj_forward(m, d);
    (d->ncon > 0 ? touching_m : free_m) = d->qpos[2];
  }
  d->qpos[2] = free_m;
  mj_forward(m, d);
  const int head = mj_name2id(m, mjOBJ_BODY, "head");
  const double radius = m->geom_size[3 * mj_name2id(m, mjOBJ_GEOM, "head")];
  Outcome out;
  for (int k = 0; k < static_cast<int>(seconds * kControlHz) && !out.blew_up; ++k) {
    for (int s = 0; s < static_cast<int>(std::lround(sim_hz / kControlHz)); ++s) {
      if (s % hold_steps == 0)
        for (int a = 0; a < m->nu; ++a) {
          const int j = m->actuator_trnid[2 * a];
          const double kp = gain_scale * m->actuator_gear[6 * a];
          const double tau =
              kp * (m->qpos0[m->jnt_qposadr[j]] - d->qpos[m->jnt_qposadr[j]]) - kd_ratio * kp * d->qvel[m->jnt_dofadr[j]];
          d->ctrl[a] = std::clamp(tau / m->actuator_gear[6 * a], -strength, strength);
        }
      mj_step(m, d);
    }
    out.blew_up = d->warning[mjWARN_BADQACC].number > 0 || !std::isfinite(d->qvel[0]);
    out.observe(k, d->xpos[3 * head + 2] + radius);
  }
  mj_deleteData(d);
  return out;
}

void print(const char* engine, double strength, double scale, double kd_ratio, int hold_steps, const Outcome& o) {
  std::printf("%-26s %-8.2f %-6.1f %-6.2f %-14d %-10.3f %.3f to %.3f%s\n", engine, strength, scale, kd_ratio, hold_steps,
              o.stood_s, o.lowest_m, o.highest_m, o.blew_up ? " (blew up)" : "");
}

// Sets every joint's armature, damping and stiffness of `m` to 0 (`bare`) or back to `saved`.
struct PassiveTerms {
  std::vector<mjtNum> armature, damping, stiffness;
  explicit PassiveTerms(const mjModel* m)
      : armature(m->dof_armature, m->dof_armature + m->nv),
        damping(m->dof_damping, m->dof_damping + m->nv),
        stiffness(m->jnt_stiffness, m->jnt_stiffness + m->njnt) {}
  void bare(mjModel* m) const {
    std::fill(m->dof_armature, m->dof_armature + m->nv, 0.0);
    std::fill(m->dof_damping, m->dof_damping + m->nv, 0.0);
    std::fill(m->jnt_stiffness, m->jnt_stiffness + m->njnt, 0.0);
  }
  void restore(mjModel* m) const {
    std::copy(armature.begin(), armature.end(), m->dof_armature);
    std::copy(damping.begin(), damping.end(), m->dof_damping);
    std::copy(stiffness.begin(), stiffness.end(), m->jnt_stiffness);
  }
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  double seconds = 10.0;
  if (argc > 4 || (argc >= 2 && (!podium::bench::real_number(argv[1], seconds) || !(seconds > 0.0))) ||
      (argc == 4 && (!podium::bench::real_number(argv[3], sim_hz) || !(sim_hz >= kControlHz)))) {
    std::fprintf(stderr, "usage: %s [SECONDS>0 [MUJOCO_XML [HZ>=40]]]\n", argv[0]);
    return 2;
  }
  const int substeps = static_cast<int>(std::lround(sim_hz / kControlHz));
  if (std::abs(substeps * kControlHz - sim_hz) > 1e-9) {
    std::fprintf(stderr, "%s: HZ %g is not a multiple of the control rate %g\n", argv[0], sim_hz, kControlHz);
    return 2;
  }
  mju_user_warning = [](const char*) {};  // counted per run (mjWARN_BADQACC) instead of printed
  // Another MuJoCo body (e.g. the seed repository's humanoid_static.xml) in place of the peer's.
  const std::string xml = argc >= 3 ? argv[2] : std::string(PODIUM_SHARED_DIR) + "/peers/mujoco/humanoid.xml";
  char error[1000] = "";
  mjModel* m = mj_loadXML(xml.c_str(), nullptr, error, sizeof error);
  if (!m) std::printf("mujoco: skipped, cannot load %s: %s\n", xml.c_str(), error);
  std::printf(
      "From the standing pose, joint PD to it (kp = scale × torque limit) chosen every `hold` simulation steps at %.0f Hz (%d: "
      "the task's 40 Hz), %.0f s at most; stood = head top above 1.2 m\n",
      sim_hz, substeps, seconds);
  std::printf("%-26s %-8s %-6s %-6s %-14s %-10s %s\n", "engine", "strength", "scale", "kd/kp", "hold (steps)", "stood (s)",
              "head top range (m)");
  std::vector<double> seed_ratio, plain_ratio;  // per row held a control step: Podium's time up over MuJoCo's
  for (const double strength : {1.0, 0.6})
    for (const double scale : {1.0, 2.0})
      for (const int hold_steps : {1, substeps}) {
        const double kd_ratio = 0.1;
        const Outcome plain = hold("humanoid21", strength, scale, kd_ratio, hold_steps, false, seconds);
        const Outcome seed = hold("humanoid21_seed", strength, scale, kd_ratio, hold_steps, true, seconds);
        print("podium humanoid21", strength, scale, kd_ratio, hold_steps, plain);
        print("podium humanoid21_seed", strength, scale, kd_ratio, hold_steps, seed);
        if (!m) continue;
        const Outcome file = hold_mujoco(m, strength, scale, kd_ratio, hold_steps, seconds);
        print("mujoco as the file", strength, scale, kd_ratio, hold_steps, file);
        const PassiveTerms terms(m);
        terms.bare(m);
        print("mujoco bare", strength, scale, kd_ratio, hold_steps,
              hold_mujoco(m, strength, scale, kd_ratio, hold_steps, seconds));
        terms.restore(m);
        if (hold_steps == substeps && file.stood_s > 0) {
          seed_ratio.push_back(seed.stood_s / file.stood_s);
          plain_ratio.push_back(plain.stood_s / file.stood_s);
        }
      }
  if (!seed_ratio.empty())
    std::printf(
        "median tipping-time ratio to MuJoCo as the file, held %d steps (%zu rows): humanoid21_seed with passive joints "
        "%.2f, humanoid21 bare %.2f\n",
        substeps, seed_ratio.size(), median(seed_ratio), median(plain_ratio));
  if (m) mj_deleteModel(m);
  return 0;
}
