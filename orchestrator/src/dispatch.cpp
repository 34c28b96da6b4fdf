// Trials in and out: asking the search for proposals, dispatching attempts to the executor (with
// the trial's hand-over and what its previous attempt left), and taking their results.
#include <cmath>
#include <system_error>

#include "hand_over.h"
#include "podium/base/rng.h"
#include "podium/store/run_folders.h"
#include "scheduler_impl.h"

namespace podium::orchestrator {

namespace {

// Checks a worker's result against the task's declaration; returns an error text or "".
std::string invalid_result(const Json& r, const StageRun& s) {
  const auto& objectives = r.at("objectives");
  const auto& features = r.at("features");
  if (features.size() != s.feature_names.size())
    return "task returned " + std::to_string(features.size()) + " features, declared " + std::to_string(s.feature_names.size());
  for (std::size_t i = 0; i < features.size(); ++i)
    if (!features[i].is_number() || !std::isfinite(features[i].get<double>()))
      return "non-finite feature " + s.feature_names[i] + " = " + features[i].dump();
  for (const auto& o : objectives)
    if (!o.is_number() || !std::isfinite(o.get<double>())) return "non-finite objective " + o.dump();
  return "";
}

}  // namespace

// The attempts of a trial that count against `retries`: those that ended badly on their own.
// An attempt interrupted by a stopped scheduler was no fault of the trial, so stopping and
// resuming `podium run` never uses up a trial's retries.
int Scheduler::failed_attempts(std::int64_t trial_id) const {
  int n = 0;
  for (const auto& a : store_.attempts(trial_id)) n += a.state != "done" && a.state != "interrupted";
  return n;
}

// Re-attaches to batch jobs an earlier scheduler left running (they are not resubmitted).
void Scheduler::adopt_running_jobs(CampaignRun& c) {
  StageRun& s = *c.stage;
  std::map<std::int64_t, store::TrialRecord> trials;
  for (auto& t : store_.trials(s.rec.id)) trials[t.id] = std::move(t);
  for (const auto& a : store_.running_attempts(s.rec.id)) {
    if (a.job_id.empty()) continue;  // died with the earlier scheduler; already interrupted
    const auto& t = trials.at(a.trial_id);
    PendingTrial p{t.id, t.index, t.params, t.context, t.seed, a.number - 1, recorded_input(t.info)};
    AttemptOrder order = make_order(c, s, p);
    if (!c.executor->adopt(order, a.job_id)) continue;
    in_flight_[order.key] = {c.rec.id, a.id, p, a.number, &s, {}};
    ++c.in_flight;
    ++s.in_flight;
    emit(c, "attempt_reattached", {{"stage", s.rec.name}, {"trial", t.index}, {"job_id", a.job_id}}, true);
  }
}

AttemptOrder Scheduler::make_order(const CampaignRun& c, const StageRun& s, const PendingTrial& t) {
  AttemptOrder order;
  order.key = next_key_++;
  order.task = s.rec.task;
  order.config = s.rec.task_config;
  order.params = t.params;
  order.context = t.context;
  if (s.spec->inputs) order.inputs = inputs_of_trial(s.input_trials, *s.spec->inputs, t.input);
  order.seed = t.seed;
  order.trial_index = static_cast<std::uint64_t>(t.index);
  order.attempt = t.attempts + 1;
  if (t.attempts > 0)
    for (const auto& a : store_.attempts(t.id))
      if (a.number == t.attempts) order.previous_attempt = {{"number", a.number}, {"state", a.state}, {"error", a.error}};
  order.work_dir = std::filesystem::absolute(store::trial_folder(c.run_dir, s.rec, t.index));
  order.timeout_s = c.spec.trial_timeout_s;
  return order;
}

void Scheduler::fill() {
  for (auto& [id, cp] : campaigns_) {
    CampaignRun& c = *cp;
    StageRun* s = c.stage.get();
    if (!s || c.control != "running") continue;
    advance_search(c, *s);
    while (c.executor->free_slots() > 0 && c.in_flight < c.spec.workers && !s->ready.empty()) dispatch(c, *s);
  }
}

// The search sees one sequence of calls whatever the trials' durations and completion order, so
// its proposals depend on the spec alone (seed, workers): results are told in the order their
// trials were asked (a result waits until every earlier-asked trial's is told), and the search is
// asked whenever fewer than `workers` trials are untold. So trial k is proposed knowing exactly
// the first k - workers + 1 results. The cost: a worker idles while an earlier trial runs long.
void Scheduler::advance_search(CampaignRun& c, StageRun& s) {
  for (;;) {
    if (s.ask_turn(c.spec.workers)) {
      ask(c, s, static_cast<std::size_t>(c.spec.workers) - s.untold.size());
      continue;
    }
    if (s.untold.empty()) return;
    const auto it = s.held.find(s.untold.front());
    if (it == s.held.end()) return;  // the earliest untold trial has not finished
    s.search->tell({it->second});
    s.held.erase(it);
    s.untold.pop_front();
    ++s.told;
    s.starved = false;
    s.dirty = true;
  }
}

// New trials from the search, stored with the search's state in this turn's transaction.
void Scheduler::ask(CampaignRun& c, StageRun& s, std::size_t room) {
  room = std::min<std::size_t>(room, static_cast<std::size_t>(s.rec.budget_trials - s.asked));
  const auto proposals = s.search->ask(room);
  s.dirty = true;
  if (proposals.empty()) (s.untold.empty() ? s.exhausted : s.starved) = true;
  const bool each = s.spec->inputs && s.spec->inputs->per_trial == "each";
  for (const auto& p : proposals) {
    Json params = Json::object();
    for (std::size_t i = 0; i < p.x.size(); ++i) params[s.param_names[i]] = p.x[i];
    const auto index = static_cast<std::int64_t>(p.id);
    std::optional<std::size_t> input = p.input;
    if (each) input = input_for_trial(index, p.input, s.input_trials.size());
    Json info = p.info;
    if (input) info["input"] = *input;  // which input the trial receives (or seeks novelty for)
    const auto seed = base::derive_seed(c.rec.seed, static_cast<std::uint64_t>(s.rec.index), p.id);
    const auto trial_id = store_.add_trial(s.rec.id, index, params, p.context, info, seed);
    s.ready.push_back({trial_id, index, params, p.context, seed, 0, input});
    s.untold.push_back(index);
    ++s.asked;
  }
}

void Scheduler::dispatch(CampaignRun& c, StageRun& s) {
  PendingTrial t = std::move(s.ready.front());
  s.ready.pop_front();
  const AttemptOrder order = make_order(c, s, t);
  // A first attempt starts in an empty folder (a reused run_dir may hold another campaign's);
  // later attempts find what the earlier ones left, e.g. a checkpoint to resume from.
  if (order.attempt == 1) {
    std::error_code ignored;
    std::filesystem::remove_all(order.work_dir, ignored);
  }
  const std::string worker = c.executor->submit(order);
  InFlight f;
  f.campaign_id = c.rec.id;
  f.attempt_id = store_.start_attempt(t.id, order.attempt, worker, c.executor->host());
  f.number = order.attempt;
  f.trial = std::move(t);
  f.stage = &s;
  in_flight_[order.key] = std::move(f);
  ++c.in_flight;
  ++s.in_flight;
}

void Scheduler::handle(const ExecutorEvent& e) {
  auto it = in_flight_.find(e.key);
  if (it == in_flight_.end()) return;
  InFlight& f = it->second;
  if (e.kind == ExecutorEvent::Kind::metric) {
    f.metrics.push_back({e.name, e.step, e.value, f.number});
    return;
  }
  if (e.kind == ExecutorEvent::Kind::progress) return;
  if (e.kind == ExecutorEvent::Kind::placed) {
    store_.set_attempt_placement(f.attempt_id, e.job_id, e.host);
    return;
  }

  CampaignRun& c = *campaigns_.at(f.campaign_id);
  StageRun& s = *f.stage;
  store_.add_metrics(f.trial.id, f.metrics);
  std::string state = e.state, error = e.error;
  if (state == "done") {
    error = invalid_result(e.result, s);
    if (!error.empty()) state = "failed";
  }
  search::Observation obs;
  obs.id = static_cast<std::uint64_t>(f.trial.index);
  if (state == "done") {
    store_.finish_attempt(f.attempt_id, "done", "", std::nullopt, std::nullopt);
    obs.ok = true;
    obs.objectives = e.result["objectives"].get<std::vector<double>>();
    obs.features = e.result["features"].get<std::vector<double>>();
    const Json info = e.result.value("info", Json::object());
    obs.success = search::trial_success(s.strategies.success, info);
    obs.x = search::evaluated_params(info);
    std::vector<store::ArtifactRecord> artifacts;
    for (const auto& a : e.result["artifacts"])
      artifacts.push_back({a["name"], a["path"], a["sha256"], a["size"].get<std::int64_t>()});
    store_.complete_trial(f.trial.id, obs.objectives, s.feature_names, obs.features, info, artifacts);
    s.held[f.trial.index] = obs;  // told in trial order (advance_search)
    if (const auto id = s.strategies.assign(obs.features, info)) store_.set_trial_strategy(f.trial.id, *id);
    c.counter.record_finished();
    emit(c, "trial_done", {{"stage", s.rec.name}, {"trial", f.trial.index}, {"objectives", obs.objectives}}, false);
  } else {
    store_.finish_attempt(f.attempt_id, state, error, e.exit_code, e.signal);
    const std::string reason = "attempt " + std::to_string(f.number) + " " + state + ": " + error +
                               (e.retry ? "" : " (not retried: the task rejected its input)");
    if (c.control == "cancelled" || state == "cancelled") {
      store_.set_trial_state(f.trial.id, "cancelled", reason);
      s.held[f.trial.index] = obs;  // told in trial order (advance_search)
    } else if (failed_attempts(f.trial.id) <= c.spec.retries && e.retry) {
      store_.set_trial_state(f.trial.id, "pending", reason);
      f.trial.attempts = f.number;
      s.ready.push_front(f.trial);
      emit(c, "attempt_failed", {{"stage", s.rec.name}, {"trial", f.trial.index}, {"error", reason}}, true);
    } else {
      store_.set_trial_state(f.trial.id, "failed", reason);
      s.held[f.trial.index] = obs;  // told in trial order (advance_search)
      c.counter.record_finished();
      emit(c, "trial_failed", {{"stage", s.rec.name}, {"trial", f.trial.index}, {"error", reason}}, true);
    }
  }
  s.dirty = true;
  --c.in_flight;
  --s.in_flight;
  in_flight_.erase(it);
}

}  // namespace podium::orchestrator
