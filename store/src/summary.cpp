#include "podium/store/summary.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>
#include <set>
#include <sstream>

#include "podium/base/error.h"
#include "podium/store/store.h"

namespace podium::store {

using base::Json;

std::string format_number(double value) {
  if (std::isnan(value)) return "nan";
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, value).ptr;
  return {text, end};
}

namespace {

// {"name", "unit"?, "description"?} of a description entry: what names it, without its bounds.
Json name_entry(const Json& entry) {
  Json e = {{"name", entry.is_object() ? entry.value("name", std::string()) : entry.get<std::string>()}};
  if (!entry.is_object()) return e;
  for (const char* key : {"unit", "description"})
    if (entry.contains(key) && entry[key].is_string() && !entry[key].get<std::string>().empty()) e[key] = entry[key];
  return e;
}

// [{"name", "unit"?, "value"}]: `values` named by `entries` (extra values are named by position).
Json named_values(const Json& entries, const std::vector<double>& values) {
  Json out = Json::array();
  for (std::size_t i = 0; i < values.size(); ++i) {
    Json e = i < entries.size() ? entries[i] : Json{{"name", "value" + std::to_string(i)}};
    e.erase("description");
    e["value"] = values[i];
    out.push_back(e);
  }
  return out;
}

std::vector<double> objective_values(const store::TrialRecord& t) {
  std::vector<double> out;
  if (!t.objectives.is_array()) return out;
  for (const auto& v : t.objectives) out.push_back(v.is_number() ? v.get<double>() : std::nan(""));
  return out;
}

bool has_primary(const store::TrialOutcome& t) { return t.objective && !std::isnan(*t.objective); }

// Whether trial a ranks above b: one with a primary objective above one without, a higher one,
// else the lower index.
bool ranks_above(const store::TrialOutcome& a, const store::TrialOutcome& b) {
  if (has_primary(a) != has_primary(b)) return has_primary(a);
  if (has_primary(a) && *a.objective != *b.objective) return *a.objective > *b.objective;
  return a.index < b.index;
}

Json trial_ref(const std::string& stage, const store::TrialOutcome& t) {
  return {{"trial", trial_name(stage, t.index)}, {"index", t.index}, {"id", t.id}};
}

std::vector<double> features_of(const store::Store& store, std::int64_t trial_id) {
  const auto t = store.trial(trial_id);
  return t ? t->features : std::vector<double>{};
}

// The done trials in the order they finished (the index breaks ties).
std::vector<const store::TrialOutcome*> in_finish_order(const std::vector<store::TrialOutcome>& done_trials) {
  std::vector<const store::TrialOutcome*> done;
  for (const auto& t : done_trials) done.push_back(&t);
  std::stable_sort(done.begin(), done.end(), [](const auto* a, const auto* b) {
    return a->finished_at != b->finished_at ? a->finished_at < b->finished_at : a->index < b->index;
  });
  return done;
}

// The labels Store::strategy_labels gives, from the same walk.
StrategyLabels strategy_labels(const std::vector<const store::TrialOutcome*>& done_in_finish_order) {
  StrategyLabels labels;
  for (const auto* t : done_in_finish_order)
    if (t->strategy) labels.emplace(*t->strategy, static_cast<std::int64_t>(labels.size()) + 1);
  return labels;
}

Json strategies_of(const store::Store& store, const std::string& stage, const std::vector<store::TrialOutcome>& done,
                   const StrategyLabels& labels, const Json& features) {
  std::map<std::int64_t, std::pair<std::int64_t, const store::TrialOutcome*>> by_label;  // label -> (trials, representative)
  for (const auto& t : done) {
    if (!t.strategy) continue;
    auto& [count, best] = by_label[labels.at(*t.strategy)];
    ++count;
    if (!best || ranks_above(t, *best)) best = &t;
  }
  Json out = Json::array();
  for (const auto& [label, entry] : by_label) {
    const store::TrialOutcome& rep = *entry.second;
    out.push_back({{"id", *rep.strategy},
                   {"label", label},
                   {"trials", entry.first},
                   {"best_objective", has_primary(rep) ? Json(*rep.objective) : Json(nullptr)},
                   {"representative", trial_ref(stage, rep)},
                   {"features", named_values(features, features_of(store, rep.id))}});
  }
  return out;
}

Json discovery_curve(const std::vector<const store::TrialOutcome*>& done) {
  Json curve = Json::array();
  std::set<std::int64_t> seen;
  std::size_t last_count = 0;
  for (std::size_t i = 0; i < done.size(); ++i) {
    if (done[i]->strategy) seen.insert(*done[i]->strategy);
    if (seen.size() != last_count || i == 0 || i + 1 == done.size()) curve.push_back({i + 1, seen.size()});
    last_count = seen.size();
  }
  return curve;
}

// The per-task tables (plugins/task.h "Result tables") of a stage's done trials, merged by title and columns.
Json stage_tables(const std::string& stage, const std::vector<store::TrialOutcome>& done) {
  Json tables = Json::array();
  for (const auto& t : done) {
    if (t.result_info.empty()) continue;
    const Json info = Json::parse(t.result_info, nullptr, false);
    if (!info.is_object() || !info.contains("table")) continue;
    const Json& table = info["table"];
    if (!table.is_object() || !table.contains("columns") || !table["columns"].is_array() || !table.contains("rows") ||
        !table["rows"].is_array())
      continue;
    const std::string title = table.value("title", std::string());
    auto it = std::find_if(tables.begin(), tables.end(),
                           [&](const Json& m) { return m["title"] == title && m["task_columns"] == table["columns"]; });
    if (it == tables.end()) {
      Json columns = Json::array({{{"name", "trial"}}});
      for (const auto& c : table["columns"]) columns.push_back(c);
      tables.push_back({{"title", title}, {"columns", columns}, {"task_columns", table["columns"]}, {"rows", Json::array()}});
      it = tables.end() - 1;
    }
    for (const auto& row : table["rows"]) {
      Json r = Json::array({trial_name(stage, t.index)});
      if (row.is_array())
        for (const auto& cell : row) r.push_back(cell);
      (*it)["rows"].push_back(r);
    }
  }
  for (auto& m : tables) m.erase("task_columns");
  return tables;
}

Json best_of(const store::Store& store, const std::string& stage, const std::vector<store::TrialOutcome>& done,
             const StrategyLabels& labels, const Json& objectives, const Json& features) {
  const store::TrialOutcome* best = nullptr;
  for (const auto& t : done)
    if (has_primary(t) && (!best || ranks_above(t, *best))) best = &t;
  if (!best) return nullptr;
  const auto record = store.trial(best->id);
  if (!record) return nullptr;
  Json out = trial_ref(stage, *best);
  out["strategy"] = best->strategy ? Json(*best->strategy) : Json(nullptr);
  out["strategy_label"] = best->strategy ? Json(labels.at(*best->strategy)) : Json(nullptr);
  out["objectives"] = named_values(objectives, objective_values(*record));
  out["features"] = named_values(features, record->features);
  return out;
}

Json stage_summary(const store::Store& store, const store::StageRecord& st, const std::string& campaign_state) {
  const auto counts = store.stage_trial_counts(st.id);
  const auto done = store.done_trials(st.id);
  const auto finished = in_finish_order(done);
  const StrategyLabels labels = strategy_labels(finished);
  const Json objectives = objective_entries(st.description), features = feature_entries(st.description);
  return {
      {"index", st.index},
      {"name", st.name},
      {"task", st.task},
      {"algorithm", st.algorithm},
      {"state", store::shown_stage_state(campaign_state, st.state)},
      {"config", st.task_config},
      {"trials",
       {{"budget", st.budget_trials},
        {"done", counts.done},
        {"failed", counts.failed},
        {"running", counts.running},
        {"pending", counts.pending + counts.interrupted},
        {"cancelled", counts.cancelled}}},
      {"objectives", objectives},
      {"features", features},
      {"best", best_of(store, st.name, done, labels, objectives, features)},
      {"strategies", strategies_of(store, st.name, done, labels, features)},
      {"discovery", discovery_curve(finished)},
      {"tables", stage_tables(st.name, done)},
      // What the search concluded, when its saved state says (CMA-ES: its mean and covariance).
      {"search_result", st.search_state && st.search_state->contains("result") ? st.search_state->at("result") : Json(nullptr)}};
}

}  // namespace

Json objective_entries(const Json& description) {
  const Json names = description.value("objectives", Json::array());
  const Json info = description.value("objective_info", Json::array());
  Json out = Json::array();
  for (std::size_t i = 0; i < names.size(); ++i) {
    const bool described = i < info.size() && info[i].is_object() && info[i].value("name", std::string()) == names[i];
    out.push_back(name_entry(described ? info[i] : names[i]));
  }
  return out;
}

Json feature_entries(const Json& description) {
  Json out = Json::array();
  for (const auto& f : description.value("features", Json::array())) out.push_back(name_entry(f));
  return out;
}

Json campaign_summary(const store::Store& store, std::int64_t campaign_id) {
  const auto c = store.campaign(campaign_id);
  if (!c) throw base::UserError("no campaign " + std::to_string(campaign_id) + " in " + store.path().string());
  Json stages = Json::array();
  for (const auto& st : store.stages(campaign_id)) stages.push_back(stage_summary(store, st, c->state));
  return {{"campaign", {{"id", c->id}, {"name", c->name}, {"state", c->state}}}, {"stages", stages}};
}

Json compare_summaries(const std::vector<Json>& summaries) {
  Json campaigns = Json::array(), stages = Json::array();
  for (const Json& s : summaries) {
    for (const auto& st : s["stages"]) {
      auto it = std::find_if(stages.begin(), stages.end(), [&](const Json& x) { return x["name"] == st["name"]; });
      if (it == stages.end()) {
        stages.push_back({{"name", st["name"]}, {"curves", Json::array()}});
        it = stages.end() - 1;
      }
      (*it)["curves"].push_back(
          {{"campaign", s["campaign"]["id"]}, {"campaign_name", s["campaign"]["name"]}, {"discovery", st["discovery"]}});
    }
    campaigns.push_back(s);
  }
  return {{"campaigns", campaigns}, {"stages", stages}};
}

Json compare_campaigns(const store::Store& store, const std::vector<std::int64_t>& campaign_ids) {
  std::vector<Json> summaries;
  for (const auto id : campaign_ids) summaries.push_back(campaign_summary(store, id));
  return compare_summaries(summaries);
}

}  // namespace podium::store
