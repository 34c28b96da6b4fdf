// jump_runup_probe: where a run-up can and cannot reach, without training. For a reference run
// and the shipped strategies (policies/MANIFEST.json) it prints
//   - the reference's own root motion (heading frame) around its take-off, against each target;
//   - how far the reference pose alone carries the athlete (a zero residual action) from the run's
//     start and from starts at later frames;
//   - each strategy's jump policy handed the reference's own state at its take-off (an ideal
//     run-up) and that state with the strategy's ω and lateral speed put in: the full jump's ceiling.
//
//   jump_runup_probe RUN.txt [JUMPS [KIND]]   (RUN: VC5_sprint__curves_03.txt or, with KIND
//                                              obstacle, VC5_Run_jumpToBox_01.txt of arpspoof/Jump's
//                                              data/motions/beyond; JUMPS per case, default 20;
//                                              KIND high_jump (default) or obstacle: whose strategies)
//
// With a trained run-up policy it evaluates it instead, on noise seeds of one's choosing (held
// out from training's tests): JUMPS run-ups and full jumps (the first deterministic, the others
// with σ 0.1 action noise), the hand-over's mean |error| per feature and the full jump's success.
//
//   jump_runup_probe RUN.txt JUMPS RUNUP.pt STRATEGY SEED LEAD_S [WINDOW_S]
//       STRATEGY: the MANIFEST's index among the jump policies (0 flop-like, 1 scissor-like,
//       2 straddle-like, 3–6 the obstacle jumps; an obstacle strategy's run-up uses eq. 3.14); LEAD_S: the run-up's runup_lead_s
//       (quick: 0.5); WINDOW_S: runup_window_s (default 0.2; 0 hands over at the reference's take-off time exactly)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "podium/base/json.h"
#include "podium/character/frames.h"
#include "podium/learn/frozen_policy.h"
#include "pose_prior.h"
#include "runup_env.h"
#include "train_runup.h"

using namespace podium;
using namespace podium::tasks::jump;

namespace {

struct Strategy {
  std::string name, policy;
  std::vector<double> takeoff;
  double z_m = 0.5;
  JumpKind kind = JumpKind::high_jump;
};

// The P-VAE a kind's shipped jump policies act through (MANIFEST.json).
PosePrior prior_for(JumpKind kind) {
  return load_pose_prior(std::string(PODIUM_JUMP_POLICY_DIR) +
                         (kind == JumpKind::obstacle ? "/obstacle_pose_vae.pt" : "/athlete_pose_vae.pt"));
}

std::vector<Strategy> shipped(const std::string& dir) {
  std::ifstream in(dir + "/MANIFEST.json");
  const base::Json m = base::Json::parse(in);
  std::vector<Strategy> out;
  for (const base::Json& p : m.at("policies")) {
    if (!p.contains("takeoff")) continue;
    const bool obstacle = p.contains("box_width_reached_m");
    out.push_back({p.at("file").get<std::string>(), dir + "/" + p.at("file").get<std::string>(),
                   p.at("takeoff").get<std::vector<double>>(),
                   p.at(obstacle ? "box_width_reached_m" : "bar_reached_m").get<double>(),
                   obstacle ? JumpKind::obstacle : JumpKind::high_jump});
  }
  return out;
}

// Zero residual from `start_s` on the reference clock: control steps survived and how it ended.
void zero_residual(const RunupSettings& s, const std::shared_ptr<const character::Clip>& clip, double start_s) {
  RunupEnv env(s, clip, true);
  std::vector<double> obs;
  env.reset(obs);
  env.world().reset(clip->sample(start_s), character::ImitationReference(clip).velocity(start_s));
  env.set_reference_time(start_s);
  env.observe(obs);
  const std::vector<double> zero(env.action_space().size(), 0.0);
  learn::StepResult out;
  int steps = 0;
  double ri = 0.0;
  do {
    env.step(zero, out);
    ++steps, ri += out.info[0];
  } while (!out.terminated && !out.truncated);
  std::printf("  zero residual from %.2f s: %3d steps to %.2f s, %s, mean r_I %.3f%s\n", start_s, steps, env.reference_time_s(),
              env.handed_over() ? "handed over" : to_string(env.termination()), ri / steps,
              env.handed_over() ? (", r_G " + std::to_string(env.task_reward())).c_str() : "");
}

// The jump policy from the state (q, qd) of a run-up's end: successes of `n` (the first
// deterministic run, all deterministic: the spread is the state noise added).
int jumps_from(const Strategy& st, const PosePrior& prior, const Eigen::VectorXd& q, const Eigen::VectorXd& qd, int n,
               double noise) {
  JumpSettings js;
  js.kind = st.kind;
  js.sim_hz = 150.0;
  js.takeoff_features = st.takeoff;
  js.difficulty_m = st.z_m;
  JumpEnv env(js, prior);
  const learn::FrozenPolicy policy(st.policy);
  base::Rng rng(7);
  int ok = 0;
  for (int k = 0; k < n; ++k) {
    std::vector<double> obs;
    env.seed(static_cast<std::uint64_t>(k));
    env.reset(obs);
    const Placement p = place_for_jump(q);
    Eigen::VectorXd v = qd;
    if (k > 0)
      for (int i = 6; i < v.size(); ++i) v(i) += noise * rng.normal();
    env.world().reset(p.q, v);
    env.observe(obs);
    std::vector<double> a(env.action_space().size());
    learn::StepResult out;
    do {
      policy.act(obs, a);
      env.step(a, out);
      obs = out.observation;
    } while (!out.terminated && !out.truncated);
    ok += env.outcome() == Outcome::success ? 1 : 0;
  }
  return ok;
}

int held_out(const RunupSettings& base, const std::vector<Strategy>& strategies, int n, char** argv) {
  const Strategy& st = strategies.at(static_cast<std::size_t>(std::stoi(argv[4])));
  RunupSettings s = base;
  s.kind = st.kind;
  s.takeoff_features = st.takeoff;
  s.lead_s = std::stod(argv[6]);
  if (argv[7] != nullptr) s.handover_window_s = std::stod(argv[7]);
  RunupEnv env(s, load_reference_run(s), true);
  const learn::FrozenPolicy runup(argv[3]);
  const character::PolicyFn policy = [&](std::span<const double> o, std::span<double> a) { runup.act(o, a); };
  const EvaluationJumps config{.jumps = n, .sigma = 0.1, .seed = std::stoull(argv[5])};
  const RunupEvaluation e = evaluate_runups(env, policy, config);
  JumpSettings js;
  js.kind = st.kind;
  js.sim_hz = s.sim_hz;
  js.takeoff_features = st.takeoff;
  js.difficulty_m = st.z_m;
  const JumpPolicy jump{st.policy, prior_for(st.kind), js};
  const FullJumps full = full_jumps(env, policy, jump, config, {});
  std::printf(
      "%s run-up %s, seed %s, %d run-ups: hand-over %.2f, r_G %.3f, |Δω| (%.3f, %.3f, %.3f) rad/s, |Δv_y| %.3f m/s; "
      "full jumps over %.2f m (%s): %.2f\n",
      st.name.c_str(), argv[3], argv[5], n, e.handover_rate, e.task_reward, e.omega_error.x(), e.omega_error.y(),
      e.omega_error.z(), e.lateral_speed_error, st.z_m, st.kind == JumpKind::obstacle ? "box width" : "bar", full.success_rate);
  for (const auto& [ending, count] : full.endings) std::printf("  full jumps ending %s: %d\n", ending.c_str(), count);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr,
                 "usage: jump_runup_probe RUN.txt [JUMPS [KIND]] | RUN.txt JUMPS RUNUP.pt STRATEGY SEED LEAD_S [WINDOW_S]\n");
    return 2;
  }
  const int n = argc > 2 ? std::stoi(argv[2]) : 20;
  RunupSettings s;
  s.motion = argv[1];
  s.sim_hz = 150.0;
  std::vector<Strategy> strategies = shipped(PODIUM_JUMP_POLICY_DIR);
  if (argc >= 7) return held_out(s, strategies, n, argv);
  s.kind = argc > 3 && std::string(argv[3]) == "obstacle" ? JumpKind::obstacle : JumpKind::high_jump;
  std::erase_if(strategies, [&](const Strategy& st) { return st.kind != s.kind; });
  s.takeoff_features = strategies.front().takeoff;
  const auto clip = load_reference_run(s);
  const character::ImitationReference reference(clip);
  RunupEnv probe(s, clip, true);
  const double t_off = probe.condition().takeoff_time_s;
  std::printf("reference %s: %.2f s, take-off at %.3f s\n", argv[1], clip->duration_s(), t_off);
  std::printf("  t s    ω_x    ω_y    ω_z    v_x    v_y    v_z   (heading frame)\n");
  for (double t = t_off - 0.5; t <= t_off + 0.2 + 1e-9; t += 1.0 / 30.0) {
    const RootMotion m = root_motion(clip->sample(t), reference.velocity(t));
    std::printf("  %.3f %6.2f %6.2f %6.2f %6.2f %6.2f %6.2f%s\n", t, m.omega.x(), m.omega.y(), m.omega.z(), m.velocity.x(),
                m.velocity.y(), m.velocity.z(), std::abs(t - t_off) < 1e-6 ? "   <- take-off" : "");
  }
  const auto yaw = [&](double t) {
    return character::heading_yaw(character::quat_at(clip->sample(t), 3).normalized().toRotationMatrix());
  };
  const auto travel = [&](double t) {  // the direction of the root's path over the next frame
    const Eigen::VectorXd a = clip->sample(t), b = clip->sample(t + 1.0 / 30.0);
    return std::atan2(b(1) - a(1), b(0) - a(0));
  };
  for (double lead : {2.0, 1.0, 0.5})
    std::printf("  over the last %.1f s: heading turns %+.2f rad, the path %+.2f rad (+: left)\n", lead,
                std::remainder(yaw(t_off) - yaw(t_off - lead), 2 * M_PI),
                std::remainder(travel(t_off) - travel(t_off - lead), 2 * M_PI));
  for (const Strategy& st : strategies) {
    const RunupTarget target = runup_target(s.kind, st.takeoff);
    std::printf("target %s: ω (%.2f, %.2f, %.2f), v_y %.2f; reference's r_G %.3f\n", st.name.c_str(), target.root_omega.x(),
                target.root_omega.y(), target.root_omega.z(), target.lateral_speed,
                runup_task_reward(target, root_motion(clip->sample(t_off), reference.velocity(t_off))));
  }
  for (double start : {0.0, t_off - 2.0, t_off - 1.5, t_off - 1.0, t_off - 0.5})
    if (start >= 0.0) zero_residual(s, clip, start);
  const PosePrior prior = prior_for(s.kind);
  for (const Strategy& st : strategies)
    for (double t = t_off - 0.2; t <= t_off + 1e-9; t += 1.0 / 30.0) {
      const Eigen::VectorXd q = clip->sample(t);
      const Eigen::VectorXd& qd = reference.velocity(t);  // the stored frame's
      const RunupTarget target = runup_target(s.kind, st.takeoff);
      // The reference's take-off with the strategy's ω and lateral speed put in (heading frame → root frame).
      Eigen::VectorXd ideal = qd;
      const Eigen::Matrix3d R = character::quat_at(q, 3).normalized().toRotationMatrix();
      const Eigen::Matrix3d H = character::heading_rotation(character::heading_yaw(R));
      const RootMotion m = root_motion(q, qd);
      ideal.head<3>() = R.transpose() * H * target.root_omega;
      ideal.segment<3>(3) = R.transpose() * H * Eigen::Vector3d(m.velocity.x(), target.lateral_speed, m.velocity.z());
      std::printf(
          "jump %s at %.2f m from the reference's state at %.3f s: %d/%d; with its ω, v_y: %d/%d (joint-rate noise 0.5 rad/s)\n",
          st.name.c_str(), st.z_m, t, jumps_from(st, prior, q, qd, n, 0.5), n, jumps_from(st, prior, q, ideal, n, 0.5), n);
    }
  return 0;
}
