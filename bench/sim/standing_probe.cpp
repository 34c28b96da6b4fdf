// Can humanoid21 stand at all under the get-up task's control (torques chosen at 40 Hz and held
// for the 20 simulation steps at 800 Hz)? Issue 18's Weaker policies rise but never stand; this
// separates "the physics cannot hold a stand at that control rate and strength" from "the policy
// has not learned to". A joint-space PD towards the standing pose (App. D's kp = torque limit,
// kd = kp/10, scaled) stands in for the policy: it is computed once per control step and held
// (as a policy's torque is), and, for comparison, evaluated at every simulation step.
//
// The same PD runs, in the same program, on the peer: MuJoCo 2.2.2 with the seed's body
// (../shared/peers/mujoco/humanoid.xml: motor gear = Table 2's torque limits, armature 0.01,
// soft contacts, implicit joint damping), at the same 800 Hz with its passive joints as the file
// has them, and once more bare: armature, damping and stiffness 0, as humanoid21 without
// `passive_joints`.
//
// Prints, for each engine, strength β, gain scale and hold, how long the head top stayed above
// 1.2 m from the standing pose (10 s at most) and the head top's range. No row stands: both bodies
// need active balance, which a PD to a fixed pose does not give; the rows compare how fast each
// tips over. Run:
//   build/bin/standing_probe [seconds]
#include <mujoco/mujoco.h>

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "podium/sim/world.h"

namespace {

using podium::sim::Control;

struct Outcome {
  double stood_s = 0.0, lowest_m = 1e9, highest_m = -1e9;
  bool blew_up = false;
};

Outcome hold(double strength, double gain_scale, double kd_ratio, int hold_steps, bool passive, double seconds) {
  const podium::sim::ModelPtr model = podium::sim::load_shipped_model("humanoid21");
  podium::sim::WorldConfig config;
  config.strength = strength;
  config.passive_joints = passive;
  podium::sim::World world(model, config);
  const Eigen::VectorXd target = model->standing_pose();
  const int nv = static_cast<int>(model->torque_limits().size());
  const Eigen::VectorXd kp = gain_scale * model->torque_limits();
  const Eigen::VectorXd kd = kd_ratio * kp;
  // humanoid21's joints are all revolute: joint DoF v ≥ 6 is coordinate v + 1 of q (the root
  // has 7 coordinates and 6 velocities).
  const auto pd_torque = [&] {
    const auto& d = world.data();
    Eigen::VectorXd tau = Eigen::VectorXd::Zero(nv);
    for (int v = 6; v < nv; ++v) tau(v) = kp(v) * (target(v + 1) - d.q(v + 1)) - kd(v) * d.qd(v);
    return tau;
  };
  Outcome out;
  const double head_top = 0.1;  // humanoid21's head sphere radius (tasks/getup measures the top)
  const int control_steps = static_cast<int>(seconds * config.control_hz);
  bool standing = true;
  for (int k = 0; k < control_steps; ++k) {
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
    const double head = world.observe().head_height_m + head_top;
    out.lowest_m = std::min(out.lowest_m, head);
    out.highest_m = std::max(out.highest_m, head);
    if (standing && head > 1.2) out.stood_s = (k + 1) / config.control_hz;
    standing = standing && head > 1.2;
  }
  return out;
}

// MuJoCo: the motors' PD toward qpos0 (standing), kp = scale × gear, clamped to β of the motor
// range; the head top is the head body's z plus its sphere's radius.
Outcome hold_mujoco(mjModel* m, double strength, double gain_scale, double kd_ratio, int hold_steps, double seconds) {
  m->opt.timestep = 1.0 / 800.0;
  mjData* d = mj_makeData(m);
  mj_forward(m, d);
  const int head = mj_name2id(m, mjOBJ_BODY, "head");
  const double radius = m->geom_size[3 * mj_name2id(m, mjOBJ_GEOM, "head")];
  Outcome out;
  bool standing = true;
  const int substeps = 20, control_steps = static_cast<int>(seconds * 40.0);
  for (int k = 0; k < control_steps && !out.blew_up; ++k) {
    for (int s = 0; s < substeps; ++s) {
      if (s % hold_steps == 0)
        for (int a = 0; a < m->nu; ++a) {
          const int j = m->actuator_trnid[2 * a];
          const double kp = gain_scale * m->actuator_gear[6 * a];
          const double tau = kp * (m->qpos0[m->jnt_qposadr[j]] - d->qpos[m->jnt_qposadr[j]]) - kd_ratio * kp * d->qvel[m->jnt_dofadr[j]];
          d->ctrl[a] = std::clamp(tau / m->actuator_gear[6 * a], -strength, strength);
        }
      mj_step(m, d);
    }
    out.blew_up = d->warning[mjWARN_BADQACC].number > 0 || !std::isfinite(d->qvel[0]);
    const double top = d->xpos[3 * head + 2] + radius;
    out.lowest_m = std::min(out.lowest_m, top);
    out.highest_m = std::max(out.highest_m, top);
    if (standing && top > 1.2) out.stood_s = (k + 1) / 40.0;
    standing = standing && top > 1.2;
  }
  mj_deleteData(d);
  return out;
}

void print(const char* engine, double strength, double scale, double kd_ratio, int hold_steps, const Outcome& o) {
  std::printf("%-26s %-8.2f %-6.1f %-6.2f %-14d %-10.3f %.3f to %.3f%s\n", engine, strength, scale, kd_ratio, hold_steps, o.stood_s,
              o.lowest_m, o.highest_m, o.blew_up ? " (blew up)" : "");
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

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 10.0;
  mju_user_warning = [](const char*) {};  // counted per run (mjWARN_BADQACC) instead of printed
  const std::string xml = std::string(PODIUM_SHARED_DIR) + "/peers/mujoco/humanoid.xml";
  char error[1000] = "";
  mjModel* m = mj_loadXML(xml.c_str(), nullptr, error, sizeof error);
  if (!m) std::printf("mujoco: skipped, cannot load %s: %s\n", xml.c_str(), error);
  std::printf("From the standing pose, joint PD to it (kp = scale × torque limit) chosen every `hold` simulation steps at 800 Hz (20: the task's 40 Hz), "
              "%.0f s at most; stood = head top above 1.2 m\n", seconds);
  std::printf("%-26s %-8s %-6s %-6s %-14s %-10s %s\n", "engine", "strength", "scale", "kd/kp", "hold (steps)", "stood (s)", "head top range (m)");
  for (const double strength : {1.0, 0.6})
    for (const double scale : {1.0, 2.0})
      for (const int hold_steps : {1, 8, 20}) {
        const double kd_ratio = 0.1;
        print("podium", strength, scale, kd_ratio, hold_steps, hold(strength, scale, kd_ratio, hold_steps, false, seconds));
        print("podium passive_joints", strength, scale, kd_ratio, hold_steps, hold(strength, scale, kd_ratio, hold_steps, true, seconds));
        if (!m) continue;
        print("mujoco as the file", strength, scale, kd_ratio, hold_steps, hold_mujoco(m, strength, scale, kd_ratio, hold_steps, seconds));
        const PassiveTerms terms(m);
        terms.bare(m);
        print("mujoco bare", strength, scale, kd_ratio, hold_steps, hold_mujoco(m, strength, scale, kd_ratio, hold_steps, seconds));
        terms.restore(m);
      }
  if (m) mj_deleteModel(m);
  return 0;
}
