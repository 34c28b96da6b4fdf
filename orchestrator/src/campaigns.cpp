#include "podium/orchestrator/campaigns.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "podium/base/config.h"
#include "podium/base/error.h"
#include "podium/base/rng.h"
#include "podium/base/suggest.h"
#include "podium/orchestrator/spec.h"
#include "podium/search/search.h"
#include "podium/search/strategies.h"
#include "podium/store/store.h"
#include "podium/store/summary.h"
#include "slurm_executor.h"
#include "worker_process.h"

namespace podium::orchestrator {

using base::Json;
using base::UserError;

namespace {

// What a stage's inputs need of the earlier stages they select from (described just before).
void check_inputs(const InputsSpec& inputs, const std::vector<store::NewStage>& earlier, const std::string& path) {
  for (const auto& name : inputs.stages) {
    const auto& from = *std::find_if(earlier.begin(), earlier.end(), [&](const auto& e) { return e.name == name; });
    const std::string which = "stage \"" + name + "\" (task " + from.task + ")";
    if (inputs.select == "best_per_strategy" && from.description.value("features", Json::array()).empty())
      throw UserError(path + ".select: \"best_per_strategy\" needs strategy features, but " + which + " declares none");
    if (inputs.select != "all" && from.description.value("objectives", Json::array()).empty())
      throw UserError(path + ".select: \"" + inputs.select + "\" ranks trials by their primary objective, but " + which +
                      " declares no objectives");
  }
}

namespace fs = std::filesystem;

// One file path of the spec ("format": "file"; "path": a file or a folder): relative to the spec's
// folder, checked, made absolute (the scheduler, its workers and a Slurm job all read the same
// file, whatever folder they start in).
std::string resolved_file(const std::string& written, const fs::path& spec_dir, const std::string& json_path,
                          bool or_folder = false) {
  const fs::path as_written(written);
  const fs::path resolved = as_written.is_absolute() ? as_written : (spec_dir / as_written).lexically_normal();
  std::error_code ec;
  if (!fs::is_regular_file(resolved, ec) && !(or_folder && fs::is_directory(resolved, ec)))
    throw UserError(json_path + ": \"" + written + "\" is not a file" + (or_folder ? " or folder" : "") + " (looked for " +
                    resolved.string() + (as_written.is_absolute() ? ")" : "; a relative path is relative to the spec's folder)"));
  return resolved.string();
}

// "file" or "path" (a file or a folder), or "" for any other format.
std::string path_format(const Json& key) {
  const std::string f = key.value("format", std::string());
  return f == "file" || f == "path" ? f : "";
}

// The values of `config` (the spec's own stage config) that the task's config description
// (`keys`, ConfigReader::describe's form) declares as files ("format": "file" or "path"), in nested objects
// and arrays too, resolved by resolved_file. `path` is config's JSON path, for errors.
void resolve_files(Json& config, const Json& keys, const fs::path& spec_dir, const std::string& path) {
  if (!config.is_object() || !keys.is_array()) return;
  for (const auto& key : keys) {
    const std::string name = key.value("key", std::string());
    if (!config.contains(name)) continue;
    Json& value = config[name];
    const std::string at = base::json_path_join(path, name);
    const Json items = key.value("items", Json::object());
    if (!path_format(key).empty() && value.is_string() && !value.get<std::string>().empty()) {
      value = resolved_file(value.get<std::string>(), spec_dir, at, path_format(key) == "path");
    } else if (key.contains("keys") && value.is_object()) {
      resolve_files(value, key["keys"], spec_dir, at);
    } else if (value.is_array()) {
      for (std::size_t i = 0; i < value.size(); ++i) {
        const std::string element = at + "[" + std::to_string(i) + "]";
        if (items.contains("keys")) resolve_files(value[i], items["keys"], spec_dir, element);
        else if (!path_format(items).empty() && value[i].is_string() && !value[i].get<std::string>().empty())
          value[i] = resolved_file(value[i].get<std::string>(), spec_dir, element, path_format(items) == "path");
      }
    }
  }
}

}  // namespace

std::int64_t submit_campaign(const std::filesystem::path& database, const Json& spec_json, const std::string& source,
                             const std::filesystem::path& spec_dir, const std::filesystem::path& worker_binary) {
  const CampaignSpec spec = parse_spec(spec_json, source);
  if (spec.executor.kind == "slurm") SlurmExecutor::check_cluster(spec.executor, source + ": executor");
  std::vector<store::NewStage> stages;
  for (std::size_t i = 0; i < spec.stages.size(); ++i) {
    const StageSpec& s = spec.stages[i];
    const std::string path = source + ": stages[" + std::to_string(i) + "]";
    // Ask the plugin (in its own process) for defaults and presets, then for the full description.
    Json defaults;
    try {
      defaults = describe_task_isolated(worker_binary, s.task, Json::object());
    } catch (const UserError& e) {
      throw UserError(path + ".task: " + e.what());
    }
    // The spec's file paths, relative to its folder, checked and made absolute before the task sees them.
    Json own_config = s.config;
    resolve_files(own_config, defaults.value("config", Json::array()), spec_dir, path + ".config");
    Json config = defaults.value("config_defaults", Json::object());
    if (!s.preset.empty()) {
      const Json presets = defaults.value("presets", Json::object());
      if (!presets.contains(s.preset)) {
        std::string known;
        for (const auto& [name, value] : presets.items()) known += (known.empty() ? "" : ", ") + name;
        throw UserError(path + ".preset: \"" + s.preset + "\" is not a preset of task " + s.task + " (presets: " + known + ")");
      }
      config.update(presets[s.preset], /*merge_objects=*/true);
    }
    // Merged key by key at every depth, so `config.ppo.policy_lr_start` alone keeps the preset's other PPO keys.
    config.update(own_config, /*merge_objects=*/true);
    // The task validates its resolved config: a value it rejects is named by its JSON path.
    Json description;
    try {
      description = describe_task_isolated(worker_binary, s.task, config);
    } catch (const base::ConfigError& e) {
      throw UserError(base::json_path_join(path + ".config", e.path()) + ": " + e.problem());
    } catch (const UserError& e) {
      throw UserError(path + ".config: " + e.what());
    }
    // The one definition of "distinct" for this stage: the spec's threshold, else the task's, else
    // 5% of the feature box's diagonal.
    double threshold = s.strategy_threshold;
    if (threshold <= 0) threshold = description.value("strategy_threshold", 0.0);
    if (threshold <= 0) {
      double diagonal = 0;
      for (const auto& f : description.at("features")) {
        const double range = f.at("high").get<double>() - f.at("low").get<double>();
        diagonal += range * range;
      }
      threshold = 0.05 * std::sqrt(diagonal);
    }
    description["strategy_threshold"] = threshold;
    try {  // the task's success rule, checked once here rather than at its first trial
      search::trial_success(description.value("success", Json()), Json::object());
    } catch (const UserError& e) {
      throw UserError(path + " (task " + s.task + "): " + e.what());
    }
    // Build the search once so its config errors are reported now, not when the stage starts.
    search::SearchSetup setup;
    setup.space = search::Space::from_json(description.at("params"), path + " (task params)");
    setup.features = search::Feature::list_from_json(description.at("features"), path + " (task features)");
    setup.config = s.search_config;
    setup.strategy_threshold = threshold;
    search::check_search(s.algorithm, setup, s.inputs.has_value(), path + ".search");
    if (s.inputs) check_inputs(*s.inputs, stages, path + ".inputs");
    stages.push_back({s.name, s.task, s.algorithm, s.search_config, config, description,
                      s.inputs ? to_json(*s.inputs) : Json(nullptr), s.budget_trials, s.budget_seconds});
  }
  // A relative run_dir is relative to the spec file, resolved once: every command finds it.
  std::string run_dir = spec.run_dir;
  if (!run_dir.empty() && std::filesystem::path(run_dir).is_relative())
    run_dir = (std::filesystem::absolute(spec_dir) / run_dir).lexically_normal().string();
  auto store = store::Store::open(database, store::Store::Access::read_write);
  return store->add_campaign(spec.name, spec_json, spec.seed, run_dir, stages);
}

void control_campaign(store::Store& store, const std::string& id_or_name, const std::string& action) {
  const auto campaign = store.campaign(store::find_campaign_id(store, id_or_name));
  const std::string& state = campaign->state;
  const bool active = state == "queued" || state == "running";
  std::string next;
  if (action == "pause" && active) next = "paused";
  else if (action == "resume" && state == "paused") next = "queued";
  else if (action == "cancel" && (active || state == "paused")) next = "cancelled";
  if (next.empty()) throw UserError("campaign " + std::to_string(campaign->id) + " is " + state + "; cannot " + action + " it");
  store.transaction([&] {
    store.set_campaign_state(campaign->id, next);
    store.add_event(campaign->id, action + "_requested", Json::object());
  });
}

Extension extend_campaign(store::Store& store, const std::string& id_or_name, const std::string& stage, std::int64_t add_trials) {
  Extension out;
  store.transaction([&] {  // read and written under the write lock: no scheduler moves in between
    const auto campaign = store.campaign(store::find_campaign_id(store, id_or_name));
    const std::string which = "campaign " + std::to_string(campaign->id) + " (" + campaign->name + ")";
    if (campaign->state != "done") {
      const bool ended = campaign->state == "failed" || campaign->state == "cancelled";
      throw UserError(which + " is " + campaign->state + ": extend continues a done campaign (" +
                      (ended ? "submit its spec again with a larger budget" : "let it finish, then extend it") + ")");
    }
    const auto stages = store.stages(campaign->id);
    const store::StageRecord& last = stages.back();
    if (!stage.empty() && stage != last.name) {
      std::string names;
      for (const auto& st : stages) names += (names.empty() ? "" : ", ") + st.name;
      if (std::none_of(stages.begin(), stages.end(), [&](const auto& st) { return st.name == stage; }))
        throw UserError(which + " has no stage \"" + stage + "\" (stages: " + names + ")");
      // Its later stages ran from what it had then; continuing it would leave them behind.
      throw UserError("stage \"" + stage + "\" of " + which + " is followed by stages that have run (" + names +
                      "): only the last stage, \"" + last.name + "\", can be extended");
    }
    if (last.budget_seconds > 0 && last.elapsed_s >= last.budget_seconds)
      throw UserError("stage \"" + last.name + "\" of " + which + " spent its wall-time budget (" +
                      Json(last.budget_seconds).dump() + " s): no new trial would start");
    const std::int64_t room = kMaxTrials - last.budget_trials;
    if (add_trials < 1 || add_trials > room)
      throw UserError("--add-trials: " + std::to_string(add_trials) + " is not in [1, " + std::to_string(room) + "] (stage \"" +
                      last.name + "\" has " + std::to_string(last.budget_trials) + " of at most " + std::to_string(kMaxTrials) +
                      " trials)");
    out = {campaign->id, campaign->name, last.name, last.budget_trials, last.budget_trials + add_trials};
    store.set_stage_budget(last.id, out.budget_after);
    store.set_stage_state(last.id, "running");
    store.set_campaign_state(campaign->id, "queued");
    store.add_event(campaign->id, "extended",
                    {{"stage", last.name}, {"budget_trials_before", out.budget_before}, {"budget_trials", out.budget_after}});
  });
  return out;
}

namespace {
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

using Ordered = nlohmann::ordered_json;

std::string number(const Ordered& v) { return v.is_number() ? store::format_number(v.get<double>()) : ""; }

void add_unique(std::vector<std::string>& list, const std::string& name) {
  if (std::find(list.begin(), list.end(), name) == list.end()) list.push_back(name);
}

// {name: value} in the task's order: `names` first, then any other key of `values` (a JSON object,
// or an array named by position).
Ordered in_order(const std::vector<std::string>& names, const Json& values) {
  Ordered out = Ordered::object();
  if (values.is_array()) {
    for (std::size_t i = 0; i < values.size(); ++i)
      out[i < names.size() ? names[i] : "value" + std::to_string(i)] = Ordered::parse(values[i].dump());
    return out;
  }
  if (!values.is_object()) return out;
  for (const auto& n : names)
    if (values.contains(n)) out[n] = Ordered::parse(values[n].dump());
  for (const auto& [k, v] : values.items())
    if (!out.contains(k)) out[k] = Ordered::parse(v.dump());
  return out;
}

std::vector<std::string> names_of(const Json& entries) {
  std::vector<std::string> out;
  for (const auto& e : entries) out.push_back(e.is_object() ? e.value("name", std::string()) : e.get<std::string>());
  return out;
}

struct StageColumns {
  std::vector<std::string> params, objectives, features;
};

// Every trial of a campaign as rows, and the column names in the tasks' order (stage by stage).
std::vector<Ordered> export_rows(const store::Store& store, std::int64_t campaign_id, bool json, bool metrics,
                                 StageColumns& columns) {
  std::vector<Ordered> rows;
  for (const auto& st : store.stages(campaign_id)) {
    const auto params = names_of(st.description.value("params", Json::array()));
    const auto objectives = names_of(store::objective_entries(st.description));
    const auto features = names_of(store::feature_entries(st.description));
    for (const auto& n : params) add_unique(columns.params, n);
    for (const auto& n : objectives) add_unique(columns.objectives, n);
    for (const auto& n : features) add_unique(columns.features, n);
    const store::StrategyLabels labels = store.strategy_labels(st.id);
    for (const auto& t : store.trials(st.id)) {
      Ordered row = {{"campaign", campaign_id},
                     {"name", store::trial_name(st.name, t.index)},
                     {"id", t.id},
                     {"stage", st.name},
                     {"trial", t.index},
                     {"state", t.state},
                     {"attempts", t.attempts},
                     {"seed", t.seed}};
      row["params"] = in_order(params, t.params);
      row["objectives"] = in_order(objectives, t.objectives);
      for (const auto& [k, v] : row["objectives"].items()) add_unique(columns.objectives, k);
      row["features"] = in_order(features, Json(t.features));
      for (const auto& [k, v] : row["features"].items()) add_unique(columns.features, k);
      for (const auto& [k, v] : row["params"].items()) add_unique(columns.params, k);
      row["strategy"] = t.strategy ? Ordered(*t.strategy) : Ordered(nullptr);
      const auto label = t.strategy ? labels.find(*t.strategy) : labels.end();
      row["strategy_label"] = label != labels.end() ? Ordered(label->second) : Ordered(nullptr);
      row["error"] = t.error;
      row["started_at"] = t.started_at;
      row["finished_at"] = t.finished_at;
      if (json) {
        row["result"] = Ordered::parse(t.result_info.dump());  // the task's free-form results (RunResult::info)
        Ordered artifacts = Ordered::array();                  // the files it left, as the dashboard lists them
        for (const auto& a : store.artifacts(t.id))
          artifacts.push_back({{"name", a.name}, {"path", a.path}, {"sha256", a.sha256}, {"size_bytes", a.size_bytes}});
        row["artifacts"] = artifacts;
      }
      if (metrics) {
        Ordered series = Ordered::object();
        for (const auto& m : store.metrics(t.id)) series[m.name].push_back({m.step, m.value});
        row["metrics"] = series;
      }
      rows.push_back(std::move(row));
    }
  }
  return rows;
}
}  // namespace

std::string export_campaign(const store::Store& store, std::int64_t campaign_id, const std::string& format, bool metrics) {
  if (format != "csv" && format != "json") throw UserError("--format: \"" + format + "\" is not one of csv, json");
  if (metrics && format != "json") throw UserError("--metrics: only with --format json");
  StageColumns columns;
  const auto rows = export_rows(store, campaign_id, format == "json", metrics, columns);
  if (format == "json") {
    Ordered array = Ordered::array();
    for (const auto& r : rows) array.push_back(r);
    return array.dump(2) + "\n";
  }
  // CSV: one column per parameter, objective and feature name, in the tasks' order over the stages.
  std::ostringstream out;
  out << "campaign,stage,trial,state,attempts,seed";
  for (const auto& p : columns.params) out << "," << csv_field("param." + p);
  for (const auto& o : columns.objectives) out << "," << csv_field("objective." + o);
  for (const auto& f : columns.features) out << "," << csv_field("feature." + f);
  out << ",strategy,strategy_label,error\n";
  for (const auto& r : rows) {
    out << campaign_id << "," << csv_field(r["stage"]) << "," << r["trial"] << "," << r["state"].get<std::string>() << ","
        << r["attempts"] << "," << r["seed"];
    for (const auto& p : columns.params) out << "," << (r["params"].contains(p) ? number(r["params"][p]) : "");
    for (const auto& o : columns.objectives) out << "," << (r["objectives"].contains(o) ? number(r["objectives"][o]) : "");
    for (const auto& f : columns.features) out << "," << (r["features"].contains(f) ? number(r["features"][f]) : "");
    out << "," << (r["strategy"].is_null() ? "" : r["strategy"].dump()) << ","
        << (r["strategy_label"].is_null() ? "" : r["strategy_label"].dump()) << "," << csv_field(r["error"]) << "\n";
  }
  return out.str();
}

}  // namespace podium::orchestrator
