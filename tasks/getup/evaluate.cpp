#include "evaluate.h"

#include <cmath>
#include <optional>
#include <stdexcept>

#include "head_watch.h"
#include "podium/base/rng.h"
#include "podium/character/evaluator.h"

namespace podium::tasks::getup {

using base::Json;
namespace fs = std::filesystem;

EvaluateConfig read_evaluate(base::ConfigReader& r) {
  EvaluateConfig c;
  c.falls = r.integer<int>("eval_falls", c.falls, {1, 10000}, "Evaluate: falls per speed");
  c.falls_seed = r.integer<std::uint64_t>("eval_falls_seed", c.falls_seed, {},
                                          "Evaluate: picks the falls (not eval_seed: unseen in training)");
  c.kappas =
      r.numbers("eval_kappas", c.kappas, {.min = 0.0, .max = 10.0, .exclusive_min = true}, "Evaluate: the speeds κ besides fast");
  c.pause_at = r.number("pause_at", c.pause_at, {.min = 0.0, .max = 1.0}, "Evaluate: §8.3's held frame, as a fraction of τ_fast");
  c.pause_steps =
      r.integer<int>("pause_steps", c.pause_steps, {0, 100000}, "Evaluate: control steps of τ_fast the frame is held");
  c.pause_kappa = r.number("pause_kappa", c.pause_kappa, {.min = 0.0, .max = 10.0, .exclusive_min = true},
                           "Evaluate: κ of the paused motion");
  c.strengths = r.numbers("eval_strengths", c.strengths, {.min = 0.0, .max = 1.0, .exclusive_min = true},
                          "Evaluate: further strengths β for π_weak's fast runs (its own is always run)");
  return c;
}

Json SpeedResult::to_json() const {
  return {{"name", name},
          {"kappa", kappa},
          {"strength", strength},
          {"success_rate", success_rate},
          {"rise_time_s", rise_time_s},
          {"risen", risen},
          {"stood", stood},
          {"on_back", on_back},
          {"risen_on_back", risen_on_back},
          {"stood_on_back", stood_on_back},
          {"drops", drops},
          {"peak_head_m", peak_head_m},
          {"com_error_m", com_error_m},
          {"tracked_fraction", tracked_fraction},
          {"end_com_gap_m", end_com_gap_m},
          {"fast_rise_time_s", fast_rise_time_s}};
}

Json EvaluateOutcome::to_json() const {
  Json j = {{"speeds", Json::array()}, {"features", features.as_vector()}, {"shown_fall", shown_fall}};
  for (const auto& s : speeds) j["speeds"].push_back(s.to_json());
  return j;
}

const SpeedResult& EvaluateOutcome::at(const std::string& name) const {
  for (const auto& s : speeds)
    if (s.name == name) return s;
  throw std::out_of_range("getup evaluate: no speed " + name);
}

FastRollout paused(FastRollout fast, double fraction, int steps) {
  const auto j = static_cast<std::size_t>(std::floor(fraction * fast.steps()));
  const auto at = static_cast<std::ptrdiff_t>(j + 1);
  fast.q.insert(fast.q.begin() + at, static_cast<std::size_t>(steps), fast.q[j]);
  fast.qd[j].setZero();
  fast.qd.insert(fast.qd.begin() + at, static_cast<std::size_t>(steps), fast.qd[j]);
  fast.com_height_m.insert(fast.com_height_m.begin() + at, static_cast<std::size_t>(steps), fast.com_height_m[j]);
  fast.torso_up.insert(fast.torso_up.begin() + at, static_cast<std::size_t>(steps), fast.torso_up[j]);
  return fast;
}

namespace {

// Each fall's head top against rise_height_m (head_watch.h), observed from the fall's end, and
// whether the fall ended on the back.
struct FallWatch {
  std::vector<HeadWatch> heads;
  std::vector<char> on_back;
  FallWatch(std::size_t falls, double height_m) : heads(falls, HeadWatch{.height_m = height_m}), on_back(falls, 0) {}
  void observe(std::size_t fall, const character::CharacterEnv& env, double head_m) {
    heads[fall].observe(env.step_index(), head_m);
    if (env.step_index() == 0) on_back[fall] = static_cast<char>(lies_on_back(env));
  }
};

// The recorded falls: every one on π_weak's run at its own strength, which picks the fall the
// replays show (shown_episode: its best get-up); that fall alone at every other speed, so fast
// and slowed replay side by side from the same fall.
void record_falls(character::EvaluationConfig& e, std::optional<std::size_t> shown, const fs::path& dir) {
  e.record.clear();
  for (std::size_t i = 0; i < e.start_seeds.size(); ++i)
    if (!shown || i == *shown) e.record.push_back(i);
  e.record_dir = dir;
}

void summarise(SpeedResult& r, const character::EvaluationReport& report, const FallWatch& watch, int stand_steps, double dt_s) {
  r.success_rate = report.success_rate;
  const BackSummary back = summarise_back(watch.heads, watch.on_back, stand_steps);
  r.on_back = back.falls, r.risen_on_back = back.risen, r.stood_on_back = back.stood;
  const HeadSummary h = summarise_heads(watch.heads, stand_steps);
  r.risen = h.risen;
  r.stood = h.stood;
  r.rise_time_s = h.first_step * dt_s;
  r.drops = h.drops;
  r.peak_head_m = h.peak_m;
  if (!report.trajectories.empty()) r.trajectory = report.trajectories.front();
}

}  // namespace

namespace {

// What every run of one Evaluate trial shares.
struct EvaluateInputs {
  const Settings& s;
  const SlowerConfig& slower;
  const WeakPolicy& weak;
  std::shared_ptr<const learn::FrozenPolicy> teacher;
  std::vector<std::uint64_t> falls;
  fs::path work_dir;
};

// One fast run: π_weak from the same falls SlowerEnv's teacher gets first (its generator's first
// draw) at `strength`. Without `shown` (π_weak's own strength, whose strategy features are the
// trial's) it picks the fall every speed's replay shows and keeps only that recording; with it,
// it records that fall alone.
struct FastRun {
  SpeedResult result;
  std::size_t shown = 0;
  StrategyFeatures features;
};

FastRun run_fast(const EvaluateInputs& in, double strength, std::optional<std::size_t> shown) {
  auto beta = std::make_shared<double>(strength);
  GetupEnv env(in.s.env, beta, false);
  check_policy_fits(*in.teacher, env, "getup evaluate: π_weak");
  character::EvaluationConfig e;
  for (std::uint64_t f : in.falls) e.start_seeds.push_back(base::Rng(f).next());
  const double rise_m = in.slower.env.rise_height_m;
  e.success = [rise_m](const character::CharacterEnv& env) {
    return static_cast<const GetupEnv&>(env).weak().head_height_m > rise_m;
  };
  FallWatch watch(in.falls.size(), rise_m);
  std::vector<StrategyRecorder> strategies(in.falls.size(), StrategyRecorder(env.model(), env.readings().head_top_m, rise_m));
  e.each_step = [&](std::size_t fall, const character::CharacterEnv& ce) {
    watch.observe(fall, ce, static_cast<const GetupEnv&>(ce).weak().head_height_m);
    if (ce.step_index() > 0) strategies[fall].observe(ce);
  };
  FastRun run;
  char name[32];
  std::snprintf(name, sizeof name, "fast_b%g", strength);
  run.result.name = shown ? name : "fast";
  run.result.strength = strength;
  record_falls(e, shown, in.work_dir / "rollouts" / run.result.name);
  auto report = character::evaluate(
      env, [&](std::span<const double> o, std::span<double> a) { in.teacher->act(o, a, env.action_scale()); }, e);
  if (!shown) {
    run.shown = shown_episode(watch.heads, in.s.stand_steps);
    for (std::size_t i = 0; i < report.trajectories.size(); ++i)
      if (i != run.shown) fs::remove(report.trajectories[i]);
    report.trajectories = {report.trajectories.at(run.shown)};
    std::vector<StrategyFeatures> per_fall;
    for (const auto& rec : strategies) per_fall.push_back(rec.features());
    run.features = mean_features(per_fall);
  }
  summarise(run.result, report, watch, in.s.stand_steps, env.control_dt_s());
  return run;
}

// One slowed run: π_slow at κ, or the paused motion; the shown fall recorded.
struct SlowRun {
  std::string name;
  double kappa;
  bool pause;
};

SpeedResult run_slow(const EvaluateInputs& in, const EvaluateConfig& c, const learn::FrozenPolicy& pi_slow, const SlowRun& run,
                     std::size_t shown) {
  SlowerEnv env(in.s.env, in.slower.env, in.teacher, in.weak.strength, run.kappa);
  check_policy_fits(pi_slow, env, "getup evaluate: π_slow");
  if (run.pause) env.set_rollout_edit([&c](FastRollout f) { return paused(std::move(f), c.pause_at, c.pause_steps); });
  character::EvaluationConfig e = slower_test(in.slower.env, in.falls);
  e.measures.push_back({"fast_rise_time_s", [](const character::CharacterEnv& ce) {
                          return static_cast<const SlowerEnv&>(ce).reference_motion().fast().steps() * ce.control_dt_s();
                        }});
  FallWatch watch(in.falls.size(), in.slower.env.rise_height_m);
  e.each_step = [&](std::size_t fall, const character::CharacterEnv& ce) {
    watch.observe(fall, ce, static_cast<const SlowerEnv&>(ce).weak().head_height_m);
  };
  record_falls(e, shown, in.work_dir / "rollouts" / run.name);
  const auto report = character::evaluate(
      env, [&](std::span<const double> o, std::span<double> a) { pi_slow.act(o, a); }, e);
  SpeedResult r;
  r.name = run.name;
  r.kappa = run.kappa;
  summarise(r, report, watch, in.s.stand_steps, env.control_dt_s());
  r.com_error_m = report.mean("com_error_m");
  r.tracked_fraction = report.mean("tracked_fraction");
  r.end_com_gap_m = report.mean("end_com_gap_m");
  r.fast_rise_time_s = report.mean("fast_rise_time_s");
  return r;
}

}  // namespace

EvaluateOutcome run_evaluate(const Settings& s, const SlowerConfig& slower, const EvaluateConfig& c, const fs::path& slow_policy,
                             const WeakPolicy& weak, const fs::path& work_dir, const std::atomic<bool>* cancel) {
  EvaluateInputs in{s, slower, weak, std::make_shared<const learn::FrozenPolicy>(weak.policy), {}, work_dir};
  for (int k = 0; k < c.falls; ++k) in.falls.push_back(base::derive_seed(c.falls_seed, static_cast<std::uint64_t>(k)));
  const auto check_cancel = [&] {
    if (cancel && cancel->load()) throw std::runtime_error("getup evaluate: cancelled");
  };
  EvaluateOutcome out;

  // Fast: π_weak at its own strength (which picks the shown fall), then the further strengths.
  check_cancel();
  const FastRun own = run_fast(in, weak.strength, std::nullopt);
  out.speeds.push_back(own.result);
  out.features = own.features;
  for (double strength : c.strengths) {
    check_cancel();
    out.speeds.push_back(run_fast(in, strength, own.shown).result);
  }
  out.shown_fall = static_cast<int>(own.shown);
  if (slow_policy.empty()) return out;

  // Slow: π_slow at each κ, and the paused motion.
  std::vector<SlowRun> runs;
  for (double k : c.kappas) {
    char name[32];
    std::snprintf(name, sizeof name, "k%g", k);
    runs.push_back({name, k, false});
  }
  if (c.pause_steps > 0) runs.push_back({"pause", c.pause_kappa, true});
  const learn::FrozenPolicy pi_slow(slow_policy);
  for (const SlowRun& run : runs) {
    check_cancel();
    out.speeds.push_back(run_slow(in, c, pi_slow, run, own.shown));
  }
  return out;
}

}  // namespace podium::tasks::getup
