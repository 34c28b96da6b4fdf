#include "train_runup.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>

#include "podium/base/error.h"
#include "podium/base/log.h"
#include "podium/base/rng.h"
#include "podium/character/frames.h"
#include "podium/learn/frozen_policy.h"
#include "podium/sim/recorder.h"

namespace podium::tasks::jump {

using base::Json;
namespace fs = std::filesystem;

namespace {

const RunupEnv& as_runup(const character::CharacterEnv& env) { return static_cast<const RunupEnv&>(env); }

// The policy with EvaluationJumps' noise on every episode but the first (restarted per episode).
struct NoisyPolicy {
  const character::PolicyFn& policy;
  learn::BoxSpace box;
  double sigma;
  bool noisy = false;
  base::Rng noise{0};
  void begin(int episode, std::uint64_t seed) { noisy = episode > 0, noise = base::Rng(seed); }
  void operator()(std::span<const double> observation, std::span<double> action) {
    policy(observation, action);
    if (!noisy) return;
    for (std::size_t j = 0; j < action.size(); ++j) {
      const double half = 0.5 * (box.high[j] - box.low[j]);
      action[j] = std::clamp(action[j] + sigma * half * noise.normal(), box.low[j], box.high[j]);
    }
  }
};

}  // namespace

RunupEvaluation evaluate_runups(RunupEnv& env, const character::PolicyFn& policy, const EvaluationJumps& config) {
  if (config.jumps < 1) throw base::UserError("jump runup evaluation: run-ups " + std::to_string(config.jumps) + " is not ≥ 1");
  character::EvaluationConfig c;
  for (int k = 0; k < config.jumps; ++k) c.start_seeds.push_back(base::derive_seed(config.seed, static_cast<std::uint64_t>(k)));
  NoisyPolicy noisy{policy, env.action_space(), config.sigma};
  c.each_step = [&](std::size_t start, const character::CharacterEnv& e) {
    if (e.step_index() == 0) noisy.begin(static_cast<int>(start), c.start_seeds[start]);
  };
  c.success = [](const character::CharacterEnv& e) { return as_runup(e).handed_over(); };
  c.measures = {{"task_reward", [](const character::CharacterEnv& e) { return as_runup(e).task_reward(); }},
                {"lateral", [](const character::CharacterEnv& e) {
                   const RunupEnv& r = as_runup(e);
                   return std::abs(r.end().velocity.y() - r.target().lateral_speed);
                 }}};
  for (int axis = 0; axis < 3; ++axis)
    c.measures.push_back({"omega_" + std::to_string(axis), [axis](const character::CharacterEnv& e) {
                            const RunupEnv& r = as_runup(e);
                            return std::abs(r.end().omega(axis) - r.target().root_omega(axis));
                          }});
  const character::EvaluationReport report = character::evaluate(
      env, [&](auto o, auto a) { noisy(o, a); }, c);
  RunupEvaluation out;
  out.handover_rate = report.success_rate;
  out.return_mean = report.mean_return;
  int n = 0;
  for (std::size_t k = 0; k < report.successes.size(); ++k) {
    if (!report.successes[k]) continue;
    ++n;
    out.task_reward += report.measures.at("task_reward")[k];
    out.lateral_speed_error += report.measures.at("lateral")[k];
    for (int axis = 0; axis < 3; ++axis) out.omega_error(axis) += report.measures.at("omega_" + std::to_string(axis))[k];
  }
  if (n > 0) {
    out.task_reward /= n, out.lateral_speed_error /= n;
    out.omega_error /= n;
  }
  if (env.settings().kind != JumpKind::high_jump) out.lateral_speed_error = 0.0;  // not a target of eq. 3.14
  return out;
}

Placement place_for_jump(const Eigen::VectorXd& q) {
  Placement p;
  const Eigen::Quaterniond root = character::quat_at(q, 3).normalized();
  p.rotation = character::heading_rotation(character::heading_yaw(root.toRotationMatrix())).transpose();
  p.offset = Eigen::Vector3d(q(0), q(1), 0.0);
  p.q = q;
  p.q.head<3>() = p.rotation * (q.head<3>() - p.offset);
  character::set_quat(p.q, 3, Eigen::Quaterniond(p.rotation) * root);
  return p;
}

namespace {

// Moves a recorded frame (a trajectory file's line) by the placement's rigid motion and its time by dt.
void move_frame(Json& frame, const Placement& p, double dt) {
  const Eigen::Quaterniond turn(p.rotation);
  const auto point = [&](Json& a, std::size_t at) {
    const Eigen::Vector3d x =
        p.rotation * (Eigen::Vector3d(a[at].get<double>(), a[at + 1].get<double>(), a[at + 2].get<double>()) - p.offset);
    for (int i = 0; i < 3; ++i) a[at + i] = x(i);
  };
  const auto rotation = [&](Json& a, std::size_t at) {
    const Eigen::Quaterniond r =
        turn * Eigen::Quaterniond(a[at].get<double>(), a[at + 1].get<double>(), a[at + 2].get<double>(), a[at + 3].get<double>());
    a[at] = r.w(), a[at + 1] = r.x(), a[at + 2] = r.y(), a[at + 3] = r.z();
  };
  for (const char* key : {"root", "q"}) point(frame[key], 0), rotation(frame[key], 3);
  for (Json& link : frame["links"]) point(link, 0), rotation(link, 3);
  point(frame["com"], 0);
  frame["t"] = frame["t"].get<double>() + dt;
}

// One motion from the run-up's recording (moved into the jump's frame) and the jump's (after it,
// its first frame being the run-up's last): the jump file's header (its props), then both's frames.
void merge_recordings(const fs::path& runup, const fs::path& jump, const Placement& p, const fs::path& out) {
  std::ifstream a(runup), b(jump);
  std::string header, line, jump_header;
  std::getline(a, header);
  std::getline(b, jump_header);
  std::vector<Json> frames;
  while (std::getline(a, line))
    if (!line.empty()) frames.push_back(Json::parse(line));
  if (frames.empty()) throw base::RuntimeError("jump runup: the run-up recording " + runup.string() + " has no frames");
  const double t0 = frames.front()["t"].get<double>(), t_end = frames.back()["t"].get<double>();
  std::ofstream o(out);
  o << jump_header << '\n';
  for (Json& f : frames) move_frame(f, p, -t0), o << f.dump() << '\n';
  bool first = true;
  while (std::getline(b, line)) {
    if (line.empty()) continue;
    if (first) {  // the hand-over state, already the run-up's last frame
      first = false;
      continue;
    }
    Json f = Json::parse(line);
    f["t"] = f["t"].get<double>() + t_end - t0;
    o << f.dump() << '\n';
  }
  if (!o) throw base::RuntimeError("jump runup: writing " + out.string() + " failed");
}

// Steps `env` with `policy` to the episode's end (reset done), recording every simulation step
// into `recorder` when given.
void roll_out(character::CharacterEnv& env, const character::PolicyFn& policy, std::vector<double>& obs,
              sim::Recorder* recorder) {
  std::optional<sim::ScopedSubstepObserver> recording;
  if (recorder) {
    recorder->record(env.world());
    recording.emplace(env.world(), [recorder](sim::World& w) { recorder->record(w); });
  }
  std::vector<double> action(env.action_space().size());
  learn::StepResult out;
  do {
    policy(obs, action);
    env.step(action, out);
    obs = out.observation;
  } while (!out.terminated && !out.truncated);
}

}  // namespace

FullJumps full_jumps(RunupEnv& runup, const character::PolicyFn& runup_policy, const JumpPolicy& jump,
                     const EvaluationJumps& config, const fs::path& record_dir) {
  const learn::FrozenPolicy jump_policy(jump.policy);
  JumpEnv jump_env(jump.settings, jump.prior);
  NoisyPolicy noisy{runup_policy, runup.action_space(), config.sigma};
  FullJumps out;
  int successes = 0;
  for (int k = 0; k < config.jumps; ++k) {
    const bool record = k == 0 && !record_dir.empty();
    sim::Recorder run_rec(runup.world().model_ptr()), jump_rec(jump_env.world().model_ptr());
    const std::uint64_t seed = base::derive_seed(config.seed, static_cast<std::uint64_t>(k));
    runup.seed(seed);
    noisy.begin(k, seed);
    std::vector<double> obs;
    runup.reset(obs);
    roll_out(
        runup, [&](auto o, auto a) { noisy(o, a); }, obs, record ? &run_rec : nullptr);
    if (!runup.handed_over()) {
      ++out.endings["no hand-over"];
      continue;
    }
    const Placement p = place_for_jump(runup.world().data().q);
    jump_env.seed(seed);
    jump_env.reset(obs);
    jump_env.world().reset(p.q, runup.world().data().qd);  // sim's root velocities are in the root frame: unchanged
    jump_env.observe(obs);
    roll_out(
        jump_env, [&](auto o, auto a) { jump_policy.act(o, a); }, obs, record ? &jump_rec : nullptr);
    successes += jump_env.outcome() == Outcome::success ? 1 : 0;
    ++out.endings[jump_env.outcome() == Outcome::success ? "success" : jump_env.outcome_reason()];
    if (record) {
      fs::create_directories(record_dir);
      sim::write_trajectory(run_rec, record_dir / "runup.jsonl");
      sim::write_trajectory(jump_rec, record_dir / "jump.jsonl");
      out.trajectory = record_dir / "full_jump.jsonl";
      merge_recordings(record_dir / "runup.jsonl", record_dir / "jump.jsonl", p, out.trajectory);
    }
  }
  out.success_rate = static_cast<double>(successes) / config.jumps;
  return out;
}

RunupStage::RunupStage(const TrainSettings& train, const RunupSettings& runup, std::uint64_t seed, std::optional<JumpPolicy> jump)
    : train_(train), runup_(runup), seed_(seed), jump_(std::move(jump)), reference_(load_reference_run(runup)) {}

void RunupStage::build(const Json&) {
  std::vector<std::unique_ptr<learn::Env>> copies;
  for (int i = 0; i < train_.copies; ++i) copies.push_back(std::make_unique<RunupEnv>(runup_, reference_, false));
  envs_ = std::make_unique<learn::VecEnv>(std::move(copies), train_.threads, base::derive_seed(seed_, 1));
}

// The jump's PPO settings, with DeepMimic's discount (γ = 0.95) for the dense imitation reward
// and a smaller action noise (σ 0.2 → 0.05 of the offset bound: the jump's 0.5 of ±1 rad
// throws a running athlete over in a step) unless the config sets them.
Json RunupStage::learner_spec() const {
  Json spec = jump::learner_spec(train_);
  if (!spec["config"].contains("gamma")) spec["config"]["gamma"] = 0.95;
  if (!spec["config"].contains("sigma_start")) spec["config"]["sigma_start"] = 0.2;
  if (!spec["config"].contains("sigma_end")) spec["config"]["sigma_end"] = 0.05;
  return spec;
}

character::Figures RunupStage::test(const character::TestRound& round, learn::Learner& learner, const character::MetricFn& send) {
  const auto samples = static_cast<double>(round.env_steps);
  RunupEnv env(runup_, reference_, true);
  const RunupEvaluation e = evaluate_runups(
      env, [&](std::span<const double> o, std::span<double> a) { learner.act(o, a, true); }, train_.eval);
  send("runup/return", samples, e.return_mean);
  send("runup/handover_rate", samples, e.handover_rate);
  send("runup/task_reward", samples, e.task_reward);
  for (int axis = 0; axis < 3; ++axis) send(std::string("runup/omega_error_") + "xyz"[axis], samples, e.omega_error(axis));
  send("runup/lateral_speed_error", samples, e.lateral_speed_error);
  char line[200];
  std::snprintf(line, sizeof line, "runup: sample %.0f: return %.2f, hand-over %.2f, r_G %.3f, |Δω| (%.2f, %.2f, %.2f) rad/s",
                samples, e.return_mean, e.handover_rate, e.task_reward, e.omega_error.x(), e.omega_error.y(), e.omega_error.z());
  base::log_info(line);
  return {{"return", e.return_mean}, {"handover_rate", e.handover_rate}, {"task_reward", e.task_reward}};
}

std::optional<character::ExportReason> RunupStage::export_rule(const character::ExportRecord& tested,
                                                               const character::ExportRecord* exported) {
  return character::best_by(tested, exported, {{"return"}});
}

void RunupStage::record(const character::Recording& r) {
  const auto policy = [&](std::span<const double> o, std::span<double> a) { r.policy.act(o, a); };
  EvaluationJumps final_runs = train_.eval;
  final_runs.jumps = train_.final_jumps;
  RunupEnv env(runup_, reference_, true);
  final_ = evaluate_runups(env, policy, final_runs);
  const auto samples = static_cast<double>(r.exported.env_steps);
  r.send("runup/final_task_reward", samples, final_.task_reward);
  r.send("runup/final_handover_rate", samples, final_.handover_rate);
  if (jump_) {
    full_ = full_jumps(env, policy, *jump_, final_runs, r.rollouts / "full_jump");
    r.send("full_jump/success_rate", samples, full_.success_rate);
  } else {  // no jump to hand over to: the run-up alone is the motion
    character::EvaluationConfig c;
    c.start_seeds = {final_runs.seed};
    c.record = {0}, c.record_dir = r.rollouts / "runup", c.record_min_hz = 60.0;
    const character::EvaluationReport report = character::evaluate(env, policy, c);
    if (!report.trajectories.empty()) full_.trajectory = report.trajectories.front();
  }
}

Json RunupOutcome::to_json() const {
  return {{"samples", samples},
          {"handover_rate", runups.handover_rate},
          {"task_reward", runups.task_reward},
          {"omega_error", {runups.omega_error.x(), runups.omega_error.y(), runups.omega_error.z()}},
          {"lateral_speed_error", runups.lateral_speed_error},
          {"return", runups.return_mean},
          {"full_jump_success_rate", full.success_rate},
          {"full_jump_endings", full.endings}};
}

RunupOutcome run_runup_trial(const TrainSettings& train, const RunupSettings& runup, const std::optional<JumpPolicy>& jump,
                             const character::StageRun& run) {
  RunupStage stage(train, runup, run.seed, jump);
  const character::StageOutcome done = character::run_training_stage(stage,
                                                                     {.name = "runup",
                                                                      .total_steps = train.total_samples,
                                                                      .steps_per_iteration = 1,
                                                                      .test_every = train.eval_every,
                                                                      .checkpoint_every = train.checkpoint_every,
                                                                      .warm_start = runup.warm_start},
                                                                     run);
  RunupOutcome out;
  out.runups = stage.final_runups();
  out.full = stage.full();
  out.policy = done.policy;
  out.samples = done.env_steps;
  return out;
}

}  // namespace podium::tasks::jump
