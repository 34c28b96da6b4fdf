// A stage's life: started (its hand-over resolved and stored), resumed, ended done or failed;
// and a campaign's end when its last stage is done or a stage fails.
#include <algorithm>

#include "hand_over.h"
#include "podium/base/error.h"
#include "podium/base/rng.h"
#include "podium/orchestrator/campaigns.h"
#include "scheduler_impl.h"

namespace podium::orchestrator {

namespace {
constexpr std::uint64_t kSearchSeedSalt = 0x5ea4c4;
}  // namespace

std::optional<std::int64_t> StrategyTracker::assign(const std::vector<double>& f, const Json& info) const {
  if (!search::trial_success(success, info)) return std::nullopt;
  return search::strategy_id(features, f, threshold);
}

void Scheduler::load_stage(CampaignRun& c, std::size_t index) {
  c.stage = std::make_unique<StageRun>();
  StageRun& s = *c.stage;
  s.rec = c.stages[index];
  s.spec = &c.spec.stages[index];
  const std::string path = "stages[" + std::to_string(index) + "]";
  // A stage started by a scheduler older than stored hand-overs (schema v3) resolves it now.
  if (s.rec.state == "waiting" || (s.spec->inputs && !s.rec.input_trials)) start_stage(c, s);
  else if (s.rec.input_trials) s.input_trials = *s.rec.input_trials;  // resumed: the stored hand-over
  if (const auto& inputs = s.spec->inputs; inputs && s.input_trials.empty()) {
    const std::string why = empty_selection_reason(store_, c.stages, *inputs);
    if (inputs->per_trial == "each") return fail_stage(c, s, path + ".inputs: per_trial \"each\" got 0 inputs (" + why + ")");
    if (s.spec->budget_per_input > 0)
      return fail_stage(c, s,
                        path + ".budget.trials: {\"per_input\": " + std::to_string(s.spec->budget_per_input) +
                            "} with 0 inputs gives 0 trials (" + why + ")");
  }

  search::SearchSetup setup;
  setup.space = search::Space::from_json(s.rec.description.at("params"), path + ".params");
  setup.features = search::Feature::list_from_json(s.rec.description.at("features"), path + ".features");
  setup.config = s.rec.search_config;
  setup.seed = base::derive_seed(c.rec.seed, index, kSearchSeedSalt);
  setup.inputs = s.input_trials;
  setup.strategy_threshold = s.rec.description.at("strategy_threshold").get<double>();
  for (const auto& p : setup.space.params) s.param_names.push_back(p.name);
  for (const auto& f : setup.features) s.feature_names.push_back(f.name);
  try {
    s.search = search::make_search(s.rec.algorithm, setup, path + ".search");
  } catch (const base::UserError& e) {  // e.g. novel-policy seeking given no inputs
    return fail_stage(c, s, e.what());
  }
  if (s.rec.search_state) s.search->load(*s.rec.search_state);
  s.strategies.features = setup.features;
  s.strategies.threshold = s.rec.description.at("strategy_threshold").get<double>();
  s.strategies.success = s.rec.description.value("success", Json());
  auto trials = store_.trials(s.rec.id);
  for (const auto& t : trials) {
    ++s.asked;
    if (t.state == "pending" || t.state == "interrupted")
      s.ready.push_back({t.id, t.index, t.params, t.context, t.seed, t.attempts, recorded_input(t.info)});
  }
  // The results not yet told, in the order asked (trial ids grow with it); finished ones wait.
  std::sort(trials.begin(), trials.end(), [](const auto& a, const auto& b) { return a.id < b.id; });
  s.told = s.rec.told;
  const auto first_untold = static_cast<std::size_t>(std::min(s.told, static_cast<std::int64_t>(trials.size())));
  for (std::size_t i = first_untold; i < trials.size(); ++i) {
    const auto& t = trials[i];
    s.untold.push_back(t.index);
    if (t.state != "done" && t.state != "failed" && t.state != "cancelled") continue;
    search::Observation& obs = s.held[t.index];
    obs.id = static_cast<std::uint64_t>(t.index);
    obs.ok = t.state == "done";
    if (obs.ok) {
      obs.objectives = t.objectives.get<std::vector<double>>();
      obs.features = t.features;
      obs.success = search::trial_success(s.strategies.success, t.result_info);
      obs.x = search::evaluated_params(t.result_info);
    }
  }
  adopt_running_jobs(c);
}

// Resolves the hand-over once and stores it with the stage, with the budget it implies.
void Scheduler::start_stage(CampaignRun& c, StageRun& s) {
  Json stored = nullptr;
  if (s.spec->inputs) {
    s.input_trials = select_input_trials(store_, c.stages, *s.spec->inputs);
    stored = s.input_trials;
    s.rec.input_trials = stored;
  }
  if (s.spec->budget_per_input > 0)
    s.rec.budget_trials = s.spec->budget_per_input * static_cast<std::int64_t>(s.input_trials.size());
  store_.start_stage(s.rec.id, stored, s.rec.budget_trials);
  const bool waiting = s.rec.state == "waiting";
  s.rec.state = "running";
  c.stages[s.rec.index] = s.rec;
  Json payload = {{"stage", s.rec.name}};
  if (s.spec->inputs) payload["inputs"] = s.input_trials.size();
  if (waiting) emit(c, "stage_started", payload, true);
}

// The stage ends failed with `reason`, and the campaign with it (advance() records that).
void Scheduler::fail_stage(CampaignRun& c, StageRun& s, const std::string& reason) {
  store_.set_stage_state(s.rec.id, "failed", reason);
  c.stages[s.rec.index].state = "failed";
  c.stages[s.rec.index].error = reason;
  emit(c, "stage_failed", {{"stage", s.rec.name}, {"error", reason}}, true);
  c.failure = "stage \"" + s.rec.name + "\" failed: " + reason;
  c.stage.reset();  // s is gone
}

// The stage has nothing left to run: done (and the next one starts) unless no trial succeeded.
void Scheduler::end_stage(CampaignRun& c) {
  StageRun& s = *c.stage;
  for (const auto& t : s.ready) store_.set_trial_state(t.id, "cancelled", "stage wall-time budget reached");
  for (const auto& [index, obs] : s.held) s.search->tell({obs});  // after a wall-time stop: in trial order
  s.told += static_cast<std::int64_t>(s.held.size());
  regroup_strategies(s);
  store_.save_search_state(s.rec.id, s.search->save(), s.elapsed_s(), s.told);
  const auto counts = store_.stage_trial_counts(s.rec.id);
  if (counts.done == 0 && counts.failed > 0) {
    store::TrialRecord last;  // the failure that ended the stage
    for (auto& t : store_.trials(s.rec.id))
      if (t.state == "failed" && t.finished_at >= last.finished_at) last = std::move(t);
    const std::string all = "all " + std::to_string(counts.failed) + " trials" + (counts.cancelled > 0 ? " that ran" : "");
    return fail_stage(c, s, all + " failed (last: trial " + store::trial_name(s.rec.name, last.index) + ", " + last.error + ")");
  }
  store_.set_stage_state(s.rec.id, "done");
  emit(c, "stage_done", {{"stage", s.rec.name}}, true);
  const auto next = static_cast<std::size_t>(s.rec.index) + 1;
  c.stages[s.rec.index].state = "done";
  c.stage.reset();
  if (next < c.stages.size()) load_stage(c, next);
}

// Ends finished stages and campaigns, starts next stages, and lets go of paused campaigns.
void Scheduler::advance() {
  for (auto it = campaigns_.begin(); it != campaigns_.end();) {
    CampaignRun& c = *it->second;
    bool release = false;
    if (c.control == "cancelled" && c.in_flight == 0) {
      if (c.stage)
        for (const auto& t : c.stage->ready) store_.set_trial_state(t.id, "cancelled", "campaign cancelled");
      store_.set_campaign_state(c.rec.id, "cancelled");
      release = true;
    } else if (c.control == "paused" && c.in_flight == 0) {
      release = true;
    } else if (c.control == "running") {
      if (c.stage && c.stage->in_flight == 0 && !c.stage->can_ask() && (c.stage->ready.empty() || c.stage->out_of_time()))
        end_stage(c);
      if (!c.failure.empty()) {
        store_.set_campaign_state(c.rec.id, "failed", c.failure);
        emit(c, "campaign_failed", {{"error", c.failure}}, true);
        release = true;
      } else if (!c.stage) {
        store_.set_campaign_state(c.rec.id, "done");
        emit(c, "campaign_done", {}, true);
        release = true;
      }
    }
    if (release) {
      progress_.forget(c.rec.id);
      it = campaigns_.erase(it);
    } else {
      ++it;
    }
  }
}

void Scheduler::regroup_strategies(const StageRun& s) {
  // Ids stored by an older rule (leader clusters) are brought to the grid's.
  for (const auto& t : store_.trials(s.rec.id))
    if (t.state == "done")
      if (const auto id = s.strategies.assign(t.features, t.result_info); id && t.strategy != id)
        store_.set_trial_strategy(t.id, *id);
}

}  // namespace podium::orchestrator
