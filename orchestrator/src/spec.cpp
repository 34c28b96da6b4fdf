#include "podium/orchestrator/spec.h"

#include <algorithm>

#include "podium/base/config.h"
#include "podium/base/suggest.h"

namespace podium::orchestrator {

using base::ConfigReader;
using base::required;

namespace {

// The ranges of the spec's numbers (README "The campaign spec" and campaign.schema.json list
// them): wide enough for any real campaign, narrow enough that nothing downstream overflows
// (a timeout becomes steady_clock nanoseconds, which overflow past 9.2e9 s) or allocates per unit.
constexpr double kMaxSeconds = 365.0 * 24 * 3600;  // trial_timeout_s, budget.wall_time_s: a year
constexpr std::int64_t kMaxRetries = 100;
constexpr std::int64_t kMaxPerInput = 1'000'000;  // budget.trials.per_input, inputs.k
constexpr std::int64_t kMaxCpusPerTask = 1024;
constexpr std::int64_t kMaxJobsInQueue = 100'000;

// Every key each object of the spec accepts (README "The campaign spec"). Checked before anything
// is read, so a misspelt key is named as unknown with the whole list (the reader's own check runs
// last and lists only the keys it read: not the optional objects absent, and after a "missing"
// error for the required key the misspelling hides).
const std::vector<std::string> kCampaignKeys = {"name",    "seed",    "description",     "run_dir", "executor",
                                                "workers", "retries", "trial_timeout_s", "stages"};
const std::vector<std::string> kStageKeys = {"name",   "task",  "preset", "config", "search", "strategy_threshold",
                                             "inputs", "budget"};
const std::vector<std::string> kSearchKeys = {"algorithm", "config"};
const std::vector<std::string> kBudgetKeys = {"trials", "wall_time_s"};
const std::vector<std::string> kPerInputKeys = {"per_input"};
const std::vector<std::string> kInputsKeys = {"stage", "select", "k", "per_trial"};
const std::vector<std::string> kExecutorKeys = {"kind",          "partition", "account",      "time",
                                                "cpus_per_task", "mem",       "extra_sbatch", "max_jobs_in_queue"};

void check_keys(const Json& object, const std::vector<std::string>& known, const std::string& path, const std::string& source) {
  if (!object.is_object()) return;  // a wrong type is the reader's to report
  for (const auto& [key, value] : object.items())
    if (std::find(known.begin(), known.end(), key) == known.end())
      throw base::ConfigError(source, base::json_path_join(path, key),
                              "unknown key (known: " + base::name_list(known) + ")" + base::did_you_mean(key, known));
}

void check_spec_keys(const Json& j, const std::string& source) {
  check_keys(j, kCampaignKeys, "", source);
  if (!j.is_object()) return;
  if (j.contains("executor")) check_keys(j["executor"], kExecutorKeys, "executor", source);
  if (!j.contains("stages") || !j["stages"].is_array()) return;
  for (std::size_t i = 0; i < j["stages"].size(); ++i) {
    const Json& stage = j["stages"][i];
    const std::string path = "stages[" + std::to_string(i) + "]";
    check_keys(stage, kStageKeys, path, source);
    if (!stage.is_object()) continue;
    if (stage.contains("search")) check_keys(stage["search"], kSearchKeys, path + ".search", source);
    if (stage.contains("inputs")) check_keys(stage["inputs"], kInputsKeys, path + ".inputs", source);
    if (!stage.contains("budget")) continue;
    check_keys(stage["budget"], kBudgetKeys, path + ".budget", source);
    if (stage["budget"].is_object() && stage["budget"].contains("trials"))
      check_keys(stage["budget"]["trials"], kPerInputKeys, path + ".budget.trials", source);
  }
}

// A campaign or stage name: printed by status, looked up by `podium status NAME`, so no control
// characters (C0, DEL, C1): they would reach terminals raw, and a NUL cannot be typed.
std::string read_name(ConfigReader& f) {
  std::string name = f.string("name", required);  // not const: returned by move
  for (std::size_t i = 0; i < name.size(); ++i) {
    const auto c = static_cast<unsigned char>(name[i]);
    const bool c1 = c == 0xC2 && i + 1 < name.size() && static_cast<unsigned char>(name[i + 1]) <= 0x9F;
    if (c < 0x20 || c == 0x7F || c1) f.fail("name", "has a control character (names are printed and typed)");
  }
  return name;
}

// stages[i].inputs. `names` are all stages' names (a later stage is named as such in errors).
InputsSpec parse_inputs(ConfigReader& f, std::size_t index, const std::vector<std::string>& names) {
  InputsSpec in;
  const Json stage = f.raw("stage", required);
  const bool single = stage.is_string();
  if (!single && !(stage.is_array() && !stage.empty())) f.fail("stage", "is not a stage name or a non-empty array of them");
  const std::vector<std::string> list = single ? std::vector<std::string>{f.string("stage", required)} : f.strings("stage", {});
  for (std::size_t i = 0; i < list.size(); ++i) {
    const auto fail = [&](const std::string& rule) { single ? f.fail("stage", rule) : f.fail("stage", i, rule); };
    const auto found = std::find(names.begin(), names.end(), list[i]);
    const auto position = static_cast<std::size_t>(found - names.begin());
    if (found == names.end()) fail("is not the name of an earlier stage");
    if (position == index) fail("is this stage itself; inputs come from earlier stages");
    if (position > index) fail("is a later stage (stages[" + std::to_string(position) + "]); inputs come from earlier stages");
    if (std::find(in.stages.begin(), in.stages.end(), list[i]) != in.stages.end()) fail("is named twice");
    in.stages.push_back(list[i]);
  }
  in.select = f.choice("select", "all", {"all", "best", "best_per_strategy", "top"});
  if (in.select == "top") in.top_k = f.integer<int>("k", required, {.min = 1, .max = kMaxPerInput});
  else if (f.has("k")) f.fail("k", "applies only to \"select\": \"top\"");
  in.per_trial = f.choice("per_trial", "all", {"all", "each"});
  return in;
}

StageSpec parse_stage(ConfigReader& f, const std::vector<StageSpec>& earlier, const std::vector<std::string>& names) {
  StageSpec s;
  s.name = read_name(f);
  for (const auto& e : earlier)
    if (e.name == s.name) f.fail("name", "is already the name of an earlier stage");
  s.task = f.string("task", required);
  s.preset = f.string("preset", "");
  s.config = f.raw_object("config");
  f.object("search", required, [&](ConfigReader& search) {
    s.algorithm = search.string("algorithm", required);
    s.search_config = search.raw_object("config");
  });
  s.strategy_threshold = f.number("strategy_threshold", 0.0, {.min = 0.0, .exclusive_min = true});
  if (f.has("inputs"))
    s.inputs = f.object("inputs", required, [&](ConfigReader& in) { return parse_inputs(in, earlier.size(), names); });
  f.object("budget", required, [&](ConfigReader& budget) {
    if (budget.has("trials") && budget.raw("trials", required).is_object()) {
      s.budget_per_input = budget.object("trials", required, [](ConfigReader& per) {
        return per.integer<std::int64_t>("per_input", required, {.min = 1, .max = kMaxPerInput});
      });
      if (!s.inputs) budget.fail("trials", "needs the stage's \"inputs\"");
    } else {
      s.budget_trials = budget.integer<std::int64_t>("trials", required, {.min = 1, .max = kMaxTrials});
    }
    s.budget_seconds = budget.number("wall_time_s", 0.0, {.min = 0.0, .max = kMaxSeconds, .exclusive_min = true});
  });
  return s;
}

ExecutorSpec parse_executor(ConfigReader& e) {
  ExecutorSpec x;
  x.kind = e.choice("kind", required, {"local", "slurm"});
  if (x.kind == "slurm") {
    x.partition = e.string("partition", required);
    x.account = e.string("account", "");
    x.time = e.string("time", "");
    if (x.time.find_first_not_of("0123456789:-") != std::string::npos)
      e.fail("time", "is not a Slurm time limit (minutes, or [days-]hours:minutes:seconds)");
    x.cpus_per_task = e.integer("cpus_per_task", 1, {.min = 1, .max = kMaxCpusPerTask});
    x.mem = e.string("mem", "");
    x.extra_sbatch = e.strings("extra_sbatch", {});
    x.max_jobs_in_queue = e.integer("max_jobs_in_queue", 100, {.min = 1, .max = kMaxJobsInQueue});
  }
  return x;
}

}  // namespace

Json to_json(const InputsSpec& inputs) {
  Json j = {{"stages", inputs.stages}, {"select", inputs.select}, {"per_trial", inputs.per_trial}};
  if (inputs.select == "top") j["k"] = inputs.top_k;
  return j;
}

CampaignSpec parse_spec(const Json& j, const std::string& source) {
  check_spec_keys(j, source);
  ConfigReader f(j, "", source);
  CampaignSpec spec;
  spec.name = read_name(f);
  spec.seed = f.integer<std::uint64_t>("seed", required);
  spec.description = f.string("description", "");
  spec.run_dir = f.string("run_dir", "");
  if (f.has("executor")) spec.executor = f.object("executor", required, parse_executor);
  spec.workers = f.integer("workers", 2, {.min = 1, .max = kMaxWorkers});
  spec.retries = f.integer("retries", 2, {.min = 0, .max = kMaxRetries});
  spec.trial_timeout_s = f.number("trial_timeout_s", 3600.0, {.min = 0.0, .max = kMaxSeconds, .exclusive_min = true});
  const Json stages = f.raw("stages", required);
  if (!stages.is_array() || stages.empty()) f.fail("stages", "is not a non-empty array");
  // Every stage's name first, so inputs naming a later stage can say so.
  std::vector<std::string> names;
  for (const auto& stage : stages)
    names.push_back(stage.is_object() && stage.contains("name") && stage["name"].is_string() ? stage["name"].get<std::string>()
                                                                                             : "");
  f.objects("stages", [&](ConfigReader& stage) { spec.stages.push_back(parse_stage(stage, spec.stages, names)); });
  f.finish();
  return spec;
}

}  // namespace podium::orchestrator
