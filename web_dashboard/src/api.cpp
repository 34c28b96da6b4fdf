#include "api.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <string_view>
#include <type_traits>

#include "podium/base/json.h"
#include "podium/store/run_folders.h"
#include "podium/store/summary.h"
#include "podium/store/writer_lock.h"

namespace podium::web_dashboard {

namespace fs = std::filesystem;
using store::Queries;

namespace {

Json counts_json(const store::TrialCounts& c) {
  return {{"total", c.total},     {"pending", c.pending + c.interrupted},
          {"running", c.running}, {"done", c.done},
          {"failed", c.failed},   {"cancelled", c.cancelled}};
}

Json optional_number(const std::optional<double>& v) { return v && std::isfinite(*v) ? Json(*v) : Json(nullptr); }

// The one name of a trial on every page and in `podium trials`: "<stage name>/<index in the
// stage>" (database ids appear in URLs only).
using store::trial_name;

// A strategy's label (store::StrategyLabels) or null: what pages show for a strategy id.
Json label_of(const store::StrategyLabels& labels, const std::optional<std::int64_t>& strategy) {
  const auto it = strategy ? labels.find(*strategy) : labels.end();
  return it != labels.end() ? Json(it->second) : Json(nullptr);
}

// States as `podium status` shows them: a stage of a paused or cancelled campaign says so
// (store::shown_stage_state), and a running campaign or stage with no scheduler alive (none holds
// the database's writer lock) is "stopped".
std::string shown_state(const std::string& state, bool scheduler_alive) {
  return state == "running" && !scheduler_alive ? "stopped" : state;
}
bool scheduler_alive(const Queries& q) { return store::WriterLock::held(q.store().path()); }

// A stage's best done trial by its primary objective (an index probe: trials_by_objective), with
// the objective's name, so no page compares objectives across stages; null before one is done.
Json stage_best(const Queries& q, std::int64_t campaign_id, const store::StageRecord& st) {
  store::TrialFilter f;
  f.stage_index = static_cast<int>(st.index);
  f.state = "done";
  f.order = store::TrialFilter::Order::objective;
  f.descending = true;
  f.limit = 1;
  const auto page = q.trial_page(campaign_id, f);
  const Json names = st.description.value("objectives", Json::array());
  const std::string objective = !names.empty() && names[0].is_string() ? names[0].get<std::string>() : "objective";
  if (page.trials.empty()) return nullptr;
  const auto& t = page.trials.front();
  const Json values = Json::parse(t.objectives, nullptr, false);
  const bool has_value = values.is_array() && !values.empty() && values[0].is_number();
  return {{"id", t.id},
          {"name", trial_name(st.name, t.index)},
          {"objective", objective},
          {"value", has_value ? values[0] : Json(nullptr)}};
}

Json campaign_summary(const Queries& q, const store::CampaignRecord& c, const store::CampaignSummary& s,
                      const std::vector<store::StageRecord>& stage_list, bool alive, double now) {
  std::map<std::int64_t, std::int64_t> strategies;  // by stage index: ids restart per stage
  for (const auto& row : s.strategy_table) ++strategies[row.stage_index];
  Json stages = Json::array();
  std::int64_t budget = 0;
  for (const auto& st : stage_list) {
    budget += st.budget_trials;
    stages.push_back({{"index", st.index},
                      {"name", st.name},
                      {"task", st.task},
                      {"algorithm", st.algorithm},
                      {"state", shown_state(store::shown_stage_state(c.state, st.state), alive)},
                      {"error", st.error},
                      {"budget_trials", st.budget_trials},
                      {"strategies", strategies[st.index]},
                      {"best", stage_best(q, c.id, st)}});
  }
  // Rate over the span the campaign has been producing results (to now while it runs).
  const double end = c.state == "running" ? now : s.last_finished_at;
  const double span_s = c.started_at > 0 ? end - c.started_at : 0.0;
  const double per_minute = span_s > 0 ? 60.0 * static_cast<double>(s.counts.done) / span_s : 0.0;
  return {{"id", c.id},
          {"name", c.name},
          {"state", shown_state(c.state, alive)},
          {"scheduler", alive ? "alive" : "none"},
          {"error", c.error},
          {"seed", std::to_string(c.seed)},
          {"created_at", c.created_at},
          {"started_at", c.started_at},
          {"finished_at", c.finished_at},
          {"stages", stages},
          {"budget_trials", budget},
          {"counts", counts_json(s.counts)},
          {"progress", budget > 0 ? static_cast<double>(s.counts.done + s.counts.failed) / static_cast<double>(budget) : 0.0},
          {"trials_per_minute", per_minute},
          {"done_last_minute", s.done_last_minute},
          {"best_objective", optional_number(s.best_objective)}};
}

Json trial_json(const store::TrialRecord& t, const store::StageRecord& stage) {
  return {{"id", t.id},
          {"name", trial_name(stage.name, t.index)},
          {"stage_id", t.stage_id},
          {"stage", stage.index},
          {"index", t.index},
          {"params", t.params},
          {"context", t.context},
          {"info", t.info},
          {"seed", std::to_string(t.seed)},  // 64-bit: a JSON number would lose digits in JavaScript
          {"state", t.state},
          {"error", t.error},
          {"attempts", t.attempts},
          {"objectives", t.objectives},
          {"features", t.features},
          {"result_info", t.result_info},
          {"strategy", t.strategy ? Json(*t.strategy) : Json(nullptr)},
          {"created_at", t.created_at},
          {"started_at", t.started_at},
          {"finished_at", t.finished_at}};
}

// Writes one JSON object into a string: members given as JSON text are copied as they are.
class ObjectText {
 public:
  explicit ObjectText(std::string& out) : out_(out) { out_ += '{'; }
  ~ObjectText() { out_ += '}'; }
  ObjectText(const ObjectText&) = delete;
  ObjectText& operator=(const ObjectText&) = delete;
  ObjectText& raw(const char* key, std::string_view json) {
    out_ += first_ ? "\"" : ",\"";
    first_ = false;
    out_ += key;
    out_ += "\":";
    out_ += json;
    return *this;
  }
  ObjectText& value(const char* key, const Json& j) { return raw(key, j.dump()); }

 private:
  std::string& out_;
  bool first_ = true;
};

// Writes one JSON array into a string; numbers are written shortest-exact (std::to_chars, as
// nlohmann::json does), non-finite ones as null.
class ArrayText {
 public:
  ArrayText() : out_("[") {}
  ArrayText& raw(std::string_view json) {
    if (out_.size() > 1) out_ += ',';
    out_ += json;
    return *this;
  }
  template <class Number>
  ArrayText& number(Number v) {
    if constexpr (std::is_floating_point_v<Number>)
      if (!std::isfinite(v)) return raw("null");
    char text[32];
    const auto end = std::to_chars(text, text + sizeof text, v).ptr;
    return raw(std::string_view(text, static_cast<std::size_t>(end - text)));
  }
  /// The array's text (call once).
  std::string close() { return std::move(out_ += ']'); }

 private:
  std::string out_;
};

// The same document as trial_json(), written from the stored JSON text (see store::TrialText).
void append_trial(std::string& out, const store::TrialText& t, const store::StageRecord& stage) {
  ObjectText o(out);
  o.value("id", t.id).value("name", trial_name(stage.name, t.index));
  o.value("stage_id", t.stage_id).value("stage", stage.index).value("index", t.index);
  o.raw("params", t.params).raw("context", t.context).raw("info", t.info);
  o.value("seed", std::to_string(t.seed)).value("state", t.state).value("error", t.error).value("attempts", t.attempts);
  o.raw("objectives", t.objectives).value("features", t.features).raw("result_info", t.result_info);
  o.value("strategy", t.strategy ? Json(*t.strategy) : Json(nullptr));
  o.value("created_at", t.created_at).value("started_at", t.started_at).value("finished_at", t.finished_at);
}

std::map<std::int64_t, store::StageRecord> stages_by_id(const Queries& q, std::int64_t campaign_id) {
  std::map<std::int64_t, store::StageRecord> out;
  for (auto& st : q.store().stages(campaign_id)) out.emplace(st.id, std::move(st));
  return out;
}

bool inside(const fs::path& child, const fs::path& parent) {
  const auto [p, c] = std::mismatch(parent.begin(), parent.end(), child.begin(), child.end());
  return p == parent.end() && c != child.end();
}

// A path read from the store or built from its names is data, not trust: it is served only if it
// resolves (symlinks and ".." included) into the campaign's run folder, and is a file with no
// other name (a hard link cannot be told from the file it shares).
fs::path file_in_run_folder(const Queries& q, const fs::path& database, std::int64_t campaign_id, const fs::path& path,
                            const std::string& what) {
  std::error_code ec;
  const fs::path root = fs::weakly_canonical(store::campaign_run_dir(database, *q.store().campaign(campaign_id)), ec);
  fs::path file = fs::weakly_canonical(path, ec);  // not const: returned by move
  if (ec || !inside(file, root)) throw HttpError(403, what + " outside the campaign's run folder");
  if (!fs::is_regular_file(file)) throw HttpError(404, what + " file " + file.string() + " is missing");
  if (fs::hard_link_count(file, ec) != 1) throw HttpError(403, what + " has other hard links (maybe outside the run folder)");
  return file;
}

bool has_motion(const std::vector<store::ArtifactRecord>& artifacts) {
  return std::any_of(artifacts.begin(), artifacts.end(), [](const auto& a) { return a.name == "trajectory"; });
}

// The nearest captured technique a task named in a trial's result info ({"nearest_technique":
// {"name"}}, as the jump's explore trials carry it), or null.
Json nearest_technique(const Json& result_info) {
  const Json* t =
      result_info.is_object() && result_info.contains("nearest_technique") ? &result_info["nearest_technique"] : nullptr;
  return t && t->is_object() && t->contains("name") && (*t)["name"].is_string() ? (*t)["name"] : Json(nullptr);
}

Json strategy_json(const Queries& q, const std::vector<store::StrategySummary>& list,
                   const std::vector<store::StageRecord>& stages) {
  Json out = Json::array();
  for (const auto& s : list) {
    // Per representative: whether it recorded a motion (no replay link otherwise) and its technique.
    const auto representative = q.trial(s.representative_trial);
    out.push_back(
        {{"stage", s.stage_index},
         {"strategy", s.strategy},
         {"label", s.label},
         {"trials", s.trials},
         {"representative_trial", s.representative_trial},
         {"representative_name", trial_name(stages.at(static_cast<std::size_t>(s.stage_index)).name, s.representative_index)},
         {"best_objective", optional_number(s.best_objective)},
         {"features", s.representative_features},
         {"motion", has_motion(q.store().artifacts(s.representative_trial))},
         {"technique", representative ? nearest_technique(representative->result_info) : Json(nullptr)}});
  }
  return out;
}

// The trials a trial of `stage` was handed (docs/architecture.md "Stage hand-over"; the orchestrator's
// inputs_of_trial, repeated because this layer depends on the store only): per_trial "each" gives
// trial the input its info names, "all" every input the stage selected.
Json trial_inputs(const Queries& q, const store::StageRecord& stage, const store::TrialRecord& t,
                  const std::vector<store::StageRecord>& stages) {
  Json out = Json::array();
  if (!stage.input_trials || !stage.input_trials->is_array()) return out;
  const Json& all = *stage.input_trials;
  std::vector<const Json*> given;
  if (stage.inputs.is_object() && stage.inputs.value("per_trial", "all") == "each") {
    if (t.info.contains("input") && t.info["input"].get<std::size_t>() < all.size())
      given.push_back(&all[t.info["input"].get<std::size_t>()]);
  } else {
    for (const auto& input : all) given.push_back(&input);
  }
  for (const Json* input : given) {
    const auto stage_index = input->at("stage_index").get<std::size_t>();
    const auto index = input->at("trial_index").get<std::int64_t>();
    const auto id = stage_index < stages.size() ? q.trial_id(stages[stage_index].id, index) : std::nullopt;
    const Json strategy = input->value("strategy", Json(nullptr));
    const auto labels = stage_index < stages.size() ? q.store().strategy_labels(stages[stage_index].id) : store::StrategyLabels{};
    out.push_back({{"name", trial_name(input->at("stage").get<std::string>(), index)},
                   {"id", id ? Json(*id) : Json(nullptr)},
                   {"stage", stage_index},
                   {"index", index},
                   {"objectives", input->value("objectives", Json::array())},
                   {"strategy", strategy},
                   {"strategy_label",
                    label_of(labels, strategy.is_number_integer() ? std::optional<std::int64_t>(strategy.get<std::int64_t>())
                                                                  : std::nullopt)}});
  }
  return out;
}

// A description's metrics as the pages draw them (plugins::metric_entry's fields): an entry
// written without "x" or "kind" (an older task or database) is a learning curve over "step".
Json metric_shapes(const Json& description) {
  Json out = Json::array();
  for (Json m : description.value("metrics", Json::array())) {
    if (!m.is_object() || !m.contains("name")) continue;
    if (!m.contains("x") || !m["x"].is_object() || !m["x"].contains("name")) m["x"] = {{"name", "step"}};
    if (!m.contains("kind") || (m["kind"] != "learning_curve" && m["kind"] != "evaluation")) m["kind"] = "learning_curve";
    out.push_back(std::move(m));
  }
  return out;
}

// The file name an artifact downloads as: campaign, stage, trial index and artifact name with the
// file's extension ("getup-demo_evaluate-0_trajectory_fast.jsonl"), so a trial's artifacts, and
// those of different trials, never share a name. send_file() keeps it to [A-Za-z0-9._-].
std::string download_name(const std::string& campaign, const std::string& stage, std::int64_t index,
                          const store::ArtifactRecord& a) {
  return campaign + "_" + stage + "-" + std::to_string(index) + "_" + a.name + fs::path(a.path).extension().string();
}

}  // namespace

Json campaign_list(const Queries& q, double now) {
  Json out = Json::array();
  const bool alive = scheduler_alive(q);
  for (const auto& c : q.store().campaigns())
    out.push_back(campaign_summary(q, c, q.summary(c.id, now), q.store().stages(c.id), alive, now));
  return out;
}

std::int64_t resolve_campaign(const Queries& q, const std::string& campaign) {
  const auto c = q.store().find_campaign(campaign);
  if (!c) throw HttpError(404, "no campaign \"" + campaign + "\"");
  return c->id;
}

Json campaign_detail(const Queries& q, std::int64_t campaign_id, double now) {
  const auto c = q.store().campaign(campaign_id);
  if (!c) throw HttpError(404, "no campaign " + std::to_string(campaign_id));
  const auto summary = q.summary(campaign_id, now);
  const auto stage_list = q.store().stages(campaign_id);
  Json out = campaign_summary(q, *c, summary, stage_list, scheduler_alive(q), now);
  out["spec"] = c->spec;
  out["podium_version"] = c->podium_version;
  // The summary's stage entries, with what the campaign page shows beside them.
  for (std::size_t i = 0; i < stage_list.size(); ++i) {
    const auto& st = stage_list[i];
    const auto counts = summary.stage_counts.find(st.id);
    Json description = st.description;
    description.erase("presets");  // every preset of the task: noise on this page
    Json& entry = out["stages"][i];
    entry["id"] = st.id;
    entry["search_config"] = st.search_config;
    entry["task_config"] = st.task_config;
    description["metrics"] = metric_shapes(st.description);
    entry["description"] = description;  // with "config": the keys the task accepts
    entry["inputs"] = st.inputs;
    // How many trials the stage was handed when it started (null before, or without inputs).
    entry["input_trials"] = st.input_trials && st.input_trials->is_array() ? Json(st.input_trials->size()) : Json(nullptr);
    entry["budget_seconds"] = st.budget_seconds;
    entry["elapsed_s"] = st.elapsed_s;
    entry["counts"] = counts_json(counts == summary.stage_counts.end() ? store::TrialCounts{} : counts->second);
  }
  out["strategy_table"] = strategy_json(q, summary.strategy_table, stage_list);
  return out;
}

std::string trial_page(const Queries& q, std::int64_t campaign_id, const store::TrialFilter& filter) {
  const auto page = q.trial_page(campaign_id, filter);
  const auto stages = stages_by_id(q, campaign_id);
  std::string trials = "[";
  for (const auto& t : page.trials) {
    if (trials.size() > 1) trials += ',';
    append_trial(trials, t, stages.at(t.stage_id));
  }
  trials += ']';
  std::string out;
  ObjectText(out).value("total", page.total).value("offset", filter.offset).value("limit", filter.limit).raw("trials", trials);
  return out;
}

std::string scatter_points(const Queries& q, std::int64_t campaign_id, std::int64_t max_points) {
  std::int64_t total = 0;
  const auto points = q.points(campaign_id, max_points, &total);
  // Columns rather than objects: a 5,000-point scatter stays a small document.
  ArrayText id, stage, index, objective, features, strategy, step, finished;
  std::map<std::string, std::string> step_json;  // a handful of distinct values
  for (const auto& p : points) {
    id.number(p.id);
    stage.number(p.stage_index);
    index.number(p.index);
    objective.number(p.objective);
    ArrayText f;
    for (double v : p.features) f.number(v);
    features.raw(f.close());
    p.strategy ? strategy.number(*p.strategy) : strategy.raw("null");
    auto [it, added] = step_json.try_emplace(p.step);
    if (added) it->second = Json(p.step).dump();
    step.raw(it->second);
    finished.number(p.finished_at);
  }
  std::string columns, out;
  ObjectText(columns)
      .raw("id", id.close())
      .raw("stage", stage.close())
      .raw("index", index.close())
      .raw("objective", objective.close())
      .raw("features", features.close())
      .raw("strategy", strategy.close())
      .raw("step", step.close())
      .raw("finished_at", finished.close());
  ObjectText(out).value("total", total).value("returned", points.size()).raw("columns", columns);
  return out;
}

Json strategy_table(const Queries& q, std::int64_t campaign_id) {
  return strategy_json(q, q.strategies(campaign_id), q.store().stages(campaign_id));
}

std::shared_ptr<const Json> SummaryCache::get(const Queries& q, std::int64_t campaign_id) {
  if (!enabled_) return std::make_shared<const Json>(store::campaign_summary(q.store(), campaign_id));
  std::string token = q.store().summary_token(campaign_id);
  {
    std::lock_guard lock(mutex_);
    const auto it = entries_.find(campaign_id);
    if (it != entries_.end() && it->second.first == token) return it->second.second;
  }
  auto summary = std::make_shared<const Json>(store::campaign_summary(q.store(), campaign_id));
  std::lock_guard lock(mutex_);
  if (entries_.size() >= kMaxCampaigns) entries_.clear();
  entries_[campaign_id] = {std::move(token), summary};
  return summary;
}

Json summary_document(const Queries& q, SummaryCache& cache, std::int64_t campaign_id) { return *cache.get(q, campaign_id); }

Json comparison_document(const Queries& q, SummaryCache& cache, const std::string& campaigns) {
  constexpr std::size_t kMaxCampaigns = 8;  // each summary reads its campaign's done trials
  std::vector<std::int64_t> ids;
  std::size_t start = 0;
  while (start <= campaigns.size()) {
    const std::size_t comma = std::min(campaigns.find(',', start), campaigns.size());
    const std::string name = campaigns.substr(start, comma - start);
    if (name.empty()) throw HttpError(400, "campaigns: \"" + campaigns + "\" has an empty entry (ids or names, comma-separated)");
    ids.push_back(resolve_campaign(q, name));
    start = comma + 1;
  }
  if (ids.size() > kMaxCampaigns)
    throw HttpError(400, "campaigns: " + std::to_string(ids.size()) + " given, at most " + std::to_string(kMaxCampaigns) +
                             " compare at once");
  std::vector<Json> summaries;
  for (const auto id : ids) summaries.push_back(*cache.get(q, id));
  return store::compare_summaries(summaries);
}

Json campaign_events(const Queries& q, std::int64_t campaign_id, std::size_t last_n) {
  return Json(q.last_events(campaign_id, static_cast<std::int64_t>(std::min<std::size_t>(last_n, INT64_MAX))));
}

Json trial_detail(const Queries& q, std::int64_t trial_id) {
  const auto t = q.trial(trial_id);
  const auto campaign_id = q.trial_campaign(trial_id);
  if (!t || !campaign_id) throw HttpError(404, "no trial " + std::to_string(trial_id));
  const auto stages = q.store().stages(*campaign_id);
  const auto stage = std::find_if(stages.begin(), stages.end(), [&](const auto& s) { return s.id == t->stage_id; });
  Json out = trial_json(*t, *stage);
  out["strategy_label"] = label_of(q.store().strategy_labels(stage->id), t->strategy);
  out["campaign_id"] = *campaign_id;
  out["inputs"] = trial_inputs(q, *stage, *t, stages);  // the earlier trials it was handed
  out["stage_name"] = stage->name;
  out["task"] = stage->task;
  out["feature_names"] = Json::array();
  for (const auto& f : stage->description.value("features", Json::array())) out["feature_names"].push_back(f.value("name", ""));
  out["objective_names"] = stage->description.value("objectives", Json::array());
  out["metrics"] = metric_shapes(stage->description);  // each metric's axis, unit and kind
  out["task_config"] = stage->task_config;             // resolved (e.g. a slowed get-up's κ)
  const auto campaign = q.store().campaign(*campaign_id);
  const std::string campaign_name = campaign ? campaign->name : "";
  out["campaign_name"] = campaign_name;
  Json attempts = Json::array();
  for (const auto& a : q.store().attempts(trial_id))
    attempts.push_back({{"number", a.number},
                        {"state", a.state},
                        {"worker", a.worker},
                        {"host", a.host},
                        {"job_id", a.job_id},
                        {"exit_code", a.exit_code ? Json(*a.exit_code) : Json(nullptr)},
                        {"signal", a.signal ? Json(*a.signal) : Json(nullptr)},
                        {"error", a.error},
                        {"started_at", a.started_at},
                        {"finished_at", a.finished_at}});
  out["attempt_list"] = attempts;
  Json artifacts = Json::array();
  const auto list = q.store().artifacts(trial_id);
  for (std::size_t i = 0; i < list.size(); ++i)
    artifacts.push_back({{"name", list[i].name},
                         {"path", list[i].path},
                         {"sha256", list[i].sha256},
                         {"size_bytes", list[i].size_bytes},
                         {"download_name", download_name(campaign_name, stage->name, t->index, list[i])},
                         {"url", "/api/trials/" + std::to_string(trial_id) + "/artifacts/" + std::to_string(i)}});
  out["artifacts"] = artifacts;
  out["log_url"] = "/api/trials/" + std::to_string(trial_id) + "/log";
  return out;
}

Json metric_series(const Queries& q, std::int64_t trial_id, std::int64_t max_points, const std::optional<std::string>& name) {
  if (!q.trial_campaign(trial_id)) throw HttpError(404, "no trial " + std::to_string(trial_id));
  Json out = Json::array();
  for (const auto& m : q.metric_series(trial_id, max_points, name)) {
    Json values = Json::array();
    for (double v : m.values) values.push_back(std::isfinite(v) ? Json(v) : Json(nullptr));
    out.push_back(
        {{"name", m.name}, {"attempt", m.attempt}, {"total_points", m.total_points}, {"steps", m.steps}, {"values", values}});
  }
  return out;
}

std::size_t artifact_index(const Queries& q, std::int64_t trial_id, const std::string& name) {
  const auto list = q.store().artifacts(trial_id);
  for (std::size_t i = 0; i < list.size(); ++i)
    if (list[i].name == name) return i;
  throw HttpError(404, "trial " + std::to_string(trial_id) + " has no artifact \"" + name + "\"");
}

std::string artifact_download_name(const Queries& q, std::int64_t trial_id, std::size_t index) {
  const auto t = q.trial(trial_id);
  const auto campaign_id = q.trial_campaign(trial_id);
  if (!t || !campaign_id) throw HttpError(404, "no trial " + std::to_string(trial_id));
  const auto list = q.store().artifacts(trial_id);
  if (index >= list.size())
    throw HttpError(404, "trial " + std::to_string(trial_id) + " has no artifact " + std::to_string(index));
  const auto stage = q.store().stages(*campaign_id);
  const auto st = std::find_if(stage.begin(), stage.end(), [&](const auto& s) { return s.id == t->stage_id; });
  return download_name(q.store().campaign(*campaign_id)->name, st->name, t->index, list[index]);
}

fs::path artifact_file(const Queries& q, const fs::path& database, std::int64_t trial_id, std::size_t index) {
  const auto campaign_id = q.trial_campaign(trial_id);
  if (!campaign_id) throw HttpError(404, "no trial " + std::to_string(trial_id));
  const auto list = q.store().artifacts(trial_id);
  if (index >= list.size())
    throw HttpError(404, "trial " + std::to_string(trial_id) + " has no artifact " + std::to_string(index));
  return file_in_run_folder(q, database, *campaign_id, list[index].path, "artifact");
}

namespace {

// The three features of a curves artifact, as curve files name them (heights in m, angles in degrees).
constexpr const char* kStyleFeatures[] = {"h_m", "theta_x_deg", "theta_z_deg"};

[[noreturn]] void bad_curves(const fs::path& file, const std::string& path, const std::string& what) {
  throw HttpError(500, "curves artifact " + file.string() + ": " + path + ": " + what);
}

std::string shown(const Json& value) {
  const std::string text = value.dump();
  return text.size() > 40 ? text.substr(0, 37) + "..." : text;
}

const Json& member(const Json& parent, const char* key, const fs::path& file, const std::string& path) {
  if (!parent.is_object()) bad_curves(file, path, shown(parent) + " is not an object");
  if (!parent.contains(key)) bad_curves(file, path.empty() ? key : path + "." + key, "missing");
  return parent[key];
}

// An array of numbers (null: a value that was not finite), `size` long if given.
void check_numbers(const Json& v, std::optional<std::size_t> size, const fs::path& file, const std::string& path) {
  if (!v.is_array()) bad_curves(file, path, shown(v) + " is not an array of numbers");
  if (size && v.size() != *size)
    bad_curves(file, path, "has " + std::to_string(v.size()) + " values where t_s has " + std::to_string(*size));
  for (std::size_t i = 0; i < v.size(); ++i)
    if (!v[i].is_number() && !v[i].is_null())
      bad_curves(file, path + "[" + std::to_string(i) + "]", shown(v[i]) + " is not a number");
}

void check_episode(const Json& e, const fs::path& file, const std::string& at) {
  const Json& t = member(e, "t_s", file, at);
  check_numbers(t, std::nullopt, file, at + ".t_s");
  for (const char* block : {"target", "achieved"})
    for (const char* f : kStyleFeatures)
      check_numbers(member(member(e, block, file, at), f, file, at + "." + block), t.size(), file, at + "." + block + "." + f);
  const std::string c = at + ".curve";
  const Json& curve = member(e, "curve", file, at);
  if (!member(curve, "name", file, c).is_string()) bad_curves(file, c + ".name", shown(curve["name"]) + " is not a string");
  const Json& duration = member(curve, "duration_s", file, c);
  if (!duration.is_number() || !(duration.get<double>() > 0.0))
    bad_curves(file, c + ".duration_s", shown(duration) + " is not > 0");
  for (const char* f : kStyleFeatures) {
    const Json& points = member(member(curve, "control_points", file, c), f, file, c + ".control_points");
    check_numbers(points, std::nullopt, file, c + ".control_points." + f);
    if (points.size() < 2) bad_curves(file, c + ".control_points." + f, "has fewer than 2 control points");
  }
}

}  // namespace

Json style_curves_document(const Queries& q, const fs::path& database, std::int64_t trial_id) {
  const fs::path file = artifact_file(q, database, trial_id, artifact_index(q, trial_id, "curves"));
  Json doc;
  try {
    doc = base::read_json_file(file);
  } catch (const std::exception& e) {
    throw HttpError(500, std::string("curves artifact: ") + e.what());
  }
  const Json& episodes = member(doc, "episodes", file, "");
  if (!episodes.is_array()) bad_curves(file, "episodes", shown(episodes) + " is not an array");
  for (std::size_t k = 0; k < episodes.size(); ++k) check_episode(episodes[k], file, "episodes[" + std::to_string(k) + "]");
  return doc;
}

fs::path trial_log_file(const Queries& q, const fs::path& database, std::int64_t trial_id) {
  const auto t = q.trial(trial_id);
  const auto campaign_id = q.trial_campaign(trial_id);
  if (!t || !campaign_id) throw HttpError(404, "no trial " + std::to_string(trial_id));
  const auto stages = q.store().stages(*campaign_id);
  const auto stage = std::find_if(stages.begin(), stages.end(), [&](const auto& s) { return s.id == t->stage_id; });
  const fs::path folder =
      store::trial_folder(store::campaign_run_dir(database, *q.store().campaign(*campaign_id)), *stage, t->index);
  if (!fs::exists(folder / store::kTrialLog))
    throw HttpError(404,
                    "trial " + std::to_string(trial_id) + " has no log (it has not started, or ran before podium kept logs)");
  return file_in_run_folder(q, database, *campaign_id, folder / store::kTrialLog, "log");
}

}  // namespace podium::web_dashboard
