#include "podium/orchestrator/spec.h"

#include <set>

#include "podium/base/error.h"

namespace podium::orchestrator {

using base::UserError;

namespace {

// Reads fields of one JSON object, remembering which keys were consumed so that unknown keys
// can be reported with their path.
class Fields {
 public:
  Fields(const Json& j, std::string path, std::string source) : j_(j), path_(std::move(path)), source_(std::move(source)) {
    if (!j.is_object()) fail(path_.empty() ? "(top level)" : path_, j, "is not an object");
  }

  [[noreturn]] void fail(const std::string& path, const Json& value, const std::string& rule) const {
    throw UserError(source_ + ": " + path + ": " + value.dump() + " " + rule);
  }
  std::string at(const std::string& key) const { return base::json_path_join(path_, key); }
  bool has(const std::string& key) {
    seen_.insert(key);
    return j_.contains(key);
  }
  const Json& get(const std::string& key) {
    if (!has(key)) throw UserError(source_ + ": " + at(key) + ": missing (required)");
    return j_[key];
  }
  std::string string(const std::string& key, bool required, const std::string& fallback = "") {
    if (!required && !has(key)) return fallback;
    const Json& v = get(key);
    if (!v.is_string()) fail(at(key), v, "is not a string");
    if (v.get<std::string>().empty()) fail(at(key), v, "must not be empty");
    return v.get<std::string>();
  }
  std::int64_t integer(const std::string& key, bool required, std::int64_t fallback, std::int64_t min) {
    if (!required && !has(key)) return fallback;
    const Json& v = get(key);
    if (!v.is_number_integer()) fail(at(key), v, "is not an integer");
    if (v.get<std::int64_t>() < min) fail(at(key), v, "is not >= " + std::to_string(min));
    return v.get<std::int64_t>();
  }
  double positive(const std::string& key, double fallback) {
    if (!has(key)) return fallback;
    const Json& v = get(key);
    if (!v.is_number()) fail(at(key), v, "is not a number");
    if (!(v.get<double>() > 0.0)) fail(at(key), v, "is not > 0");
    return v.get<double>();
  }
  Json object(const std::string& key) {
    if (!has(key)) return Json::object();
    const Json& v = get(key);
    if (!v.is_object()) fail(at(key), v, "is not an object");
    return v;
  }
  void reject_unknown() const {
    for (const auto& [key, value] : j_.items())
      if (!seen_.count(key)) throw UserError(source_ + ": " + at(key) + ": unknown key");
  }
  const std::string& path() const { return path_; }

 private:
  const Json& j_;
  std::string path_, source_;
  std::set<std::string> seen_;
};

StageSpec parse_stage(const Json& j, const std::string& path, const std::string& source,
                      const std::vector<StageSpec>& earlier) {
  Fields f(j, path, source);
  StageSpec s;
  s.name = f.string("name", true);
  for (const auto& e : earlier)
    if (e.name == s.name) f.fail(f.at("name"), j["name"], "is already the name of an earlier stage");
  s.task = f.string("task", true);
  s.preset = f.string("preset", false);
  s.config = f.object("config");

  Fields search(f.get("search"), f.at("search"), source);
  s.algorithm = search.string("algorithm", true);
  s.search_config = search.object("config");
  search.reject_unknown();

  s.strategy_threshold = f.positive("strategy_threshold", 0.0);
  Fields budget(f.get("budget"), f.at("budget"), source);
  s.budget_trials = budget.integer("trials", true, 0, 1);
  s.budget_seconds = budget.positive("wall_time_s", 0.0);
  budget.reject_unknown();

  if (f.has("inputs")) {
    Fields inputs(j["inputs"], f.at("inputs"), source);
    const std::string from = inputs.string("stage", true);
    bool found = false;
    for (const auto& e : earlier) found = found || e.name == from;
    if (!found) inputs.fail(inputs.at("stage"), j["inputs"]["stage"], "is not the name of an earlier stage");
    const std::string select = inputs.string("select", false, "all");
    if (select != "all" && select != "best")
      inputs.fail(inputs.at("select"), j["inputs"]["select"], "is not one of \"all\", \"best\"");
    inputs.reject_unknown();
    s.inputs = {{"stage", from}, {"select", select}};
  }
  f.reject_unknown();
  return s;
}

ExecutorSpec parse_executor(const Json& j, const std::string& source) {
  Fields e(j, "executor", source);
  ExecutorSpec x;
  x.kind = e.string("kind", true);
  if (x.kind == "slurm") {
    x.partition = e.string("partition", true);
    x.account = e.string("account", false);
    x.time = e.string("time", false);
    if (x.time.find_first_not_of("0123456789:-") != std::string::npos)
      e.fail(e.at("time"), j["time"], "is not a Slurm time limit (minutes, or [days-]hours:minutes:seconds)");
    x.cpus_per_task = static_cast<int>(e.integer("cpus_per_task", false, 1, 1));
    x.mem = e.string("mem", false);
    if (e.has("extra_sbatch")) {
      const Json& extra = j["extra_sbatch"];
      if (!extra.is_array()) e.fail(e.at("extra_sbatch"), extra, "is not an array of strings");
      for (const auto& item : extra) {
        if (!item.is_string()) e.fail(e.at("extra_sbatch"), extra, "is not an array of strings");
        x.extra_sbatch.push_back(item.get<std::string>());
      }
    }
    x.max_jobs_in_queue = static_cast<int>(e.integer("max_jobs_in_queue", false, 100, 1));
  } else if (x.kind != "local") {
    e.fail(e.at("kind"), j["kind"], "is not a supported executor (supported: \"local\", \"slurm\")");
  }
  e.reject_unknown();
  return x;
}

}  // namespace

CampaignSpec parse_spec(const Json& j, const std::string& source) {
  Fields f(j, "", source);
  CampaignSpec spec;
  spec.name = f.string("name", true);
  spec.seed = static_cast<std::uint64_t>(f.integer("seed", true, 0, 0));
  if (f.has("description")) spec.description = f.string("description", false);
  spec.run_dir = f.string("run_dir", false);
  if (f.has("executor")) spec.executor = parse_executor(j["executor"], source);
  spec.workers = static_cast<int>(f.integer("workers", false, 2, 1));
  spec.retries = static_cast<int>(f.integer("retries", false, 2, 0));
  spec.trial_timeout_s = f.positive("trial_timeout_s", 3600.0);
  const Json& stages = f.get("stages");
  if (!stages.is_array() || stages.empty()) f.fail("stages", stages, "is not a non-empty array");
  for (std::size_t i = 0; i < stages.size(); ++i)
    spec.stages.push_back(parse_stage(stages[i], base::json_path_index("stages", i), source, spec.stages));
  f.reject_unknown();
  return spec;
}

}  // namespace podium::orchestrator
