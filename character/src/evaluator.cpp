#include "podium/character/evaluator.h"

#include <algorithm>
#include <numeric>
#include <optional>

#include "podium/base/error.h"
#include "podium/sim/recorder.h"
#include "podium/sim/world.h"

namespace podium::character {

base::Json EvaluationReport::to_json() const {
  base::Json j = {{"returns", returns}, {"mean_return", mean_return}, {"success_rate", success_rate}};
  if (!successes.empty()) j["successes"] = std::vector<int>(successes.begin(), successes.end());
  for (const auto& [name, values] : measures) j["measures"][name] = values;
  std::vector<std::string> paths;
  for (const auto& p : trajectories) paths.push_back(p.string());
  j["trajectories"] = paths;
  return j;
}

double EvaluationReport::mean(const std::string& measure) const {
  const auto& values = measures.at(measure);
  return std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
}

namespace {

// Simulation steps between recorded frames (EvaluationConfig::record_min_hz).
int record_stride(const sim::World& world, double min_hz) {
  const int period = world.substeps();
  if (min_hz <= 0.0) return period;
  for (int k = period; k > 1; --k)
    if (period % k == 0 && world.config().sim_hz / k >= min_hz) return k;
  return 1;
}

// While alive, records the World's states between control steps every `stride` simulation steps
// (the state at the end of a control step is the caller's to record, as without sub-steps).
// Records the states between control steps, every `stride`-th simulation step (none when stride
// is a whole control step), after whatever observer the env's world has, which it keeps.
std::optional<sim::ScopedSubstepObserver> record_substeps(sim::World& world, sim::Recorder& recorder, int stride) {
  if (stride >= world.substeps()) return std::nullopt;
  return std::optional<sim::ScopedSubstepObserver>(
      std::in_place, world, [&recorder, stride, period = world.substeps(), step = 0](sim::World& w) mutable {
        step = step % period + 1;  // 1 … period within each control step
        if (step % stride == 0 && step < period) recorder.record(w);
      });
}

}  // namespace

EvaluationReport evaluate(CharacterEnv& env, const PolicyFn& policy, const EvaluationConfig& config) {
  if (config.start_seeds.empty()) throw base::UserError("evaluator: no start seeds");
  for (std::size_t r : config.record)
    if (r >= config.start_seeds.size())
      throw base::UserError("evaluator: record index " + std::to_string(r) + " is not below the " +
                            std::to_string(config.start_seeds.size()) + " starts");
  if (!config.record.empty()) std::filesystem::create_directories(config.record_dir);
  EvaluationReport report;
  std::vector<double> observation;
  std::vector<double> action(env.action_space().size());
  learn::StepResult step;
  sim::Recorder recorder(env.world().model_ptr());
  for (std::size_t i = 0; i < config.start_seeds.size(); ++i) {
    const bool recording = std::find(config.record.begin(), config.record.end(), i) != config.record.end();
    recorder.clear();
    env.seed(config.start_seeds[i]);
    env.reset(observation);
    if (recording) recorder.record(env.world());
    if (config.each_step) config.each_step(i, env);
    const auto substeps = record_substeps(env.world(), recorder,
                                          recording ? record_stride(env.world(), config.record_min_hz) : env.world().substeps());
    double ret = 0.0;
    for (;;) {
      policy(observation, action);
      env.step(action, step);
      ret += step.reward;
      if (recording) recorder.record(env.world());
      if (config.each_step) config.each_step(i, env);
      if (step.terminated || step.truncated) break;
      observation.swap(step.observation);
    }
    report.returns.push_back(ret);
    if (config.success) report.successes.push_back(config.success(env) ? 1 : 0);
    for (const auto& m : config.measures) report.measures[m.name].push_back(m.at_end(env));
    if (recording) {
      const auto path = config.record_dir / ("trajectory_" + std::to_string(i) + ".jsonl");
      sim::write_trajectory(recorder, path);
      report.trajectories.push_back(path);
    }
  }
  const double n = static_cast<double>(report.returns.size());
  report.mean_return = std::accumulate(report.returns.begin(), report.returns.end(), 0.0) / n;
  if (!report.successes.empty()) report.success_rate = std::accumulate(report.successes.begin(), report.successes.end(), 0.0) / n;
  return report;
}

}  // namespace podium::character
