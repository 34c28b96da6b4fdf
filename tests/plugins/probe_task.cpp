// The probe task plugin, for the orchestrator's end-to-end tests: it reports in its result info
// what reached it (the hand-over inputs, the attempt, the previous attempt, what its work folder
// held) and "trains" in steps with a checkpoint in the work folder, so a later attempt resumes
// where the last checkpoint was taken. Its objective depends on its inputs, so a trial given
// other inputs gives another result.
//
// Config: steps (metric points, one per step), checkpoint_every (steps), sleep_s (per step,
// cancellable), fail_step / fail_attempts (throw after sending step fail_step's metric, on
// attempts <= fail_attempts; -1: never), features (2, or 0 to declare none), reject (throw
// base::UserError at once, on every attempt: a task's verdict on its input), data_file and
// shipped[].policy (files, declared "format": "file") and data_path (a file or a folder, "format":
// "path"): the spec's paths, resolved at submit; the result info says what reached the task and
// whether it exists.
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <thread>

#include "podium/base/error.h"
#include "podium/base/json.h"
#include "podium/base/log.h"
#include "podium/plugins/export.h"

namespace podium::tests {

using base::Json;
namespace fs = std::filesystem;

namespace {

const Json kDefaults = {
    {"steps", 6},    {"checkpoint_every", 2}, {"sleep_s", 0.0},  {"fail_step", -1},          {"fail_attempts", 1},
    {"features", 2}, {"reject", false},       {"data_file", ""}, {"shipped", Json::array()}, {"data_path", ""}};

// The config description (ConfigReader::describe's form) for the keys whose declaration matters
// to the orchestrator: the files.
const Json kFileKeys = {
    {{"key", "data_file"}, {"type", "string"}, {"format", "file"}, {"default", ""}},
    {{"key", "data_path"}, {"type", "string"}, {"format", "path"}, {"default", ""}},
    {{"key", "shipped"},
     {"type", "array"},
     {"default", Json::array()},
     {"items", {{"type", "object"}, {"keys", {{{"key", "policy"}, {"type", "string"}, {"format", "file"}}}}}}}};

Json file_json(const std::string& path) {
  return {{"path", path}, {"absolute", fs::path(path).is_absolute()}, {"exists", fs::is_regular_file(path)}};
}

Json merged(const Json& config) {
  for (const auto& [key, value] : config.items())
    if (!kDefaults.contains(key)) throw std::runtime_error("probe config: unknown key \"" + key + "\"");
  Json c = kDefaults;
  c.update(config);
  return c;
}

Json input_json(const plugins::InputTrial& in) {
  Json artifacts = Json::object();
  for (const auto& [name, path] : in.artifacts)
    artifacts[name] = {{"path", path.string()}, {"absolute", path.is_absolute()}, {"exists", fs::exists(path)}};
  return {{"stage", in.stage},
          {"stage_index", in.stage_index},
          {"trial_index", in.trial_index},
          {"params", in.params},
          {"objectives", in.objectives},
          {"features", in.features},
          {"strategy", in.strategy ? Json(*in.strategy) : Json(nullptr)},
          {"artifacts", artifacts},
          {"info", in.info}};
}

double loss(double x0, int step) { return (1.0 + x0) / (step + 1.0); }

}  // namespace

class ProbeTask final : public plugins::Task {
 public:
  Json describe(const Json& config) const override {
    const Json c = merged(config);
    Json features = Json::array();
    for (int f = 0; f < c["features"].get<int>(); ++f)
      features.push_back({{"name", "f" + std::to_string(f)}, {"low", 0.0}, {"high", 1.0}});
    return {{"params", {{{"name", "x0"}, {"low", 0.0}, {"high", 1.0}}, {{"name", "x1"}, {"low", 0.0}, {"high", 1.0}}}},
            {"features", features},
            {"metrics", {{{"name", "loss"}}}},
            {"objectives", {"objective"}},
            {"strategy_threshold", 0.25},
            {"presets", {{"smoke", Json::object()}}},
            {"config", kFileKeys},
            {"config_defaults", kDefaults}};
  }

  plugins::RunResult run(const plugins::RunRequest& request, plugins::Sink& sink) override {
    const Json c = merged(request.config);
    const double x0 = request.params.at("x0").get<double>(), x1 = request.params.at("x1").get<double>();
    if (c["reject"].get<bool>()) throw base::UserError("probe: rejects its input");
    const fs::path checkpoint = request.work_dir / "checkpoint.json";
    Json info = {{"attempt", request.attempt},
                 {"work_dir_absolute", request.work_dir.is_absolute()},
                 {"previous_attempt", nullptr},
                 {"inputs", Json::array()}};
    if (!c["data_file"].get<std::string>().empty()) info["data_file"] = file_json(c["data_file"]);
    if (!c["data_path"].get<std::string>().empty()) info["data_path"] = file_json(c["data_path"]);
    for (const auto& entry : c["shipped"]) info["shipped"].push_back(file_json(entry.value("policy", std::string())));
    if (request.previous_attempt)
      info["previous_attempt"] = {{"number", request.previous_attempt->number},
                                  {"state", request.previous_attempt->state},
                                  {"error", request.previous_attempt->error}};
    double input_sum = 0;
    for (const auto& in : request.inputs) {
      info["inputs"].push_back(input_json(in));
      if (!in.objectives.empty()) input_sum += in.objectives[0];
    }

    int step = 0;
    if (fs::exists(checkpoint)) step = Json::parse(std::ifstream(checkpoint)).at("step").get<int>();
    info["resumed_from_step"] = step;
    base::log_info("probe: attempt " + std::to_string(request.attempt) + " starts at step " + std::to_string(step));
    // The checkpoint covers the points before it (here they follow from the step): re-sent, since
    // a killed scheduler may not have stored them (task.h).
    for (int k = 0; k < step; ++k) sink.metric("loss", k, loss(x0, k));
    const int steps = c["steps"].get<int>(), every = c["checkpoint_every"].get<int>();
    for (; step < steps; ++step) {
      const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(c["sleep_s"].get<double>());
      while (std::chrono::steady_clock::now() < until) {
        if (request.cancel && request.cancel->load()) throw std::runtime_error("cancelled");
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
      }
      sink.metric("loss", step, loss(x0, step));
      // Renamed into place whole, as task.h asks: a kill mid-write leaves the previous checkpoint.
      if ((step + 1) % every == 0) base::write_json_file_atomic(checkpoint, {{"step", step + 1}});
      if (step == c["fail_step"].get<int>() && request.attempt <= c["fail_attempts"].get<int>())
        throw std::runtime_error("probe: injected failure at step " + std::to_string(step));
    }

    plugins::RunResult result;
    result.objectives = {-((x0 - 0.3) * (x0 - 0.3) + (x1 - 0.7) * (x1 - 0.7)) + 0.1 * input_sum};
    if (c["features"].get<int>() == 2) result.features = {x0, x1};
    const fs::path policy = request.work_dir / "policy.json";
    std::ofstream(policy) << Json{{"x", {x0, x1}}}.dump();
    result.artifacts.push_back({"policy", policy});
    result.info = info;
    return result;
  }

  // A tool for `podium tool`'s plumbing: "echo" prints its arguments, "reject" throws a user error,
  // "fail" returns 1 after a line on err.
  std::vector<plugins::ToolCommand> tools() const override {
    return {{"echo", "[ARGS...]", "prints its arguments, one a line"},
            {"reject", "", "refuses its input (a base::UserError)"},
            {"fail", "", "fails (exit 1)"}};
  }
  int tool(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) override {
    if (args.at(0) == "reject") throw base::UserError("probe reject: refused as asked");
    if (args.at(0) == "fail") {
      err << "probe fail: failed as asked\n";
      return 1;
    }
    for (std::size_t k = 1; k < args.size(); ++k) out << args[k] << "\n";
    return 0;
  }
};

}  // namespace podium::tests

PODIUM_EXPORT_TASK(podium::tests::ProbeTask, "probe")
