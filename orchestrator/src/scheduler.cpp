#include "podium/orchestrator/scheduler.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <deque>
#include <map>
#include <memory>

#include "local_executor.h"
#include "slurm_executor.h"
#include "podium/base/error.h"
#include "podium/base/log.h"
#include "podium/base/rng.h"
#include "podium/orchestrator/campaigns.h"
#include "podium/orchestrator/spec.h"
#include "podium/search/search.h"
#include "podium/search/strategies.h"
#include "podium/store/store.h"
#include "progress.h"

namespace podium::orchestrator {

namespace {

using base::Json;
using Clock = std::chrono::steady_clock;

volatile std::sig_atomic_t g_stop = 0;
void on_stop_signal(int) { g_stop = 1; }

constexpr std::uint64_t kSearchSeedSalt = 0x5ea4c4;

struct PendingTrial {
  std::int64_t id = 0, index = 0;
  Json params, context;
  std::uint64_t seed = 0;
  int attempts = 0;  // attempts already made
};

// Live strategy ids: a finished trial joins the first strategy whose leader lies within the
// threshold, else founds one (search::group_strategies' rule, applied in completion order). When
// the stage ends, every trial is regrouped in trial order, the one definition the store keeps.
struct StrategyTracker {
  std::vector<search::Feature> features;
  double threshold = 0;
  std::vector<std::vector<double>> leaders;
  std::int64_t assign(const std::vector<double>& f) {
    for (std::size_t i = 0; i < leaders.size(); ++i)
      if (search::feature_distance(features, leaders[i], f) <= threshold) return static_cast<std::int64_t>(i);
    leaders.push_back(f);
    return static_cast<std::int64_t>(leaders.size()) - 1;
  }
};

struct StageRun {
  store::StageRecord rec;
  std::unique_ptr<search::Search> search;
  std::vector<std::string> param_names, feature_names;
  StrategyTracker strategies;
  std::deque<PendingTrial> ready;
  std::int64_t asked = 0;
  int in_flight = 0;
  bool exhausted = false;  // the search had nothing to propose with nothing in flight
  bool starved = false;    // the search had nothing to propose until a result comes back
  bool dirty = false;      // search state changed since the last save
  Clock::time_point active_since = Clock::now();

  double elapsed_s() const {
    return rec.elapsed_s + std::chrono::duration<double>(Clock::now() - active_since).count();
  }
  bool out_of_time() const { return rec.budget_seconds > 0 && elapsed_s() >= rec.budget_seconds; }
  bool can_ask() const { return !exhausted && !starved && asked < rec.budget_trials && !out_of_time(); }
};

struct InFlight {
  std::int64_t campaign_id = 0, attempt_id = 0;
  PendingTrial trial;
  int number = 1;
  StageRun* stage = nullptr;
  std::vector<store::MetricPoint> metrics;
};

struct CampaignRun {
  store::CampaignRecord rec;
  CampaignSpec spec;
  std::vector<store::StageRecord> stages;
  std::unique_ptr<StageRun> stage;
  std::string control = "running";  // running, paused, cancelled (as last read from the store)
  std::filesystem::path run_dir;
  Executor* executor = nullptr;              // the shared local pool, or own_executor
  std::unique_ptr<Executor> own_executor;    // a Slurm executor of this campaign's own
  int in_flight = 0;
  ProgressCounter counter;
};

class LockFile {
 public:
  explicit LockFile(const std::filesystem::path& path) {
    fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw base::RuntimeError(path.string() + ": cannot create the scheduler lock file");
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0)
      throw base::RuntimeError(path.string() + ": another `podium run` is using this database");
  }
  ~LockFile() { ::close(fd_); }

 private:
  int fd_ = -1;
};

class Scheduler {
 public:
  Scheduler(store::Store& store, const SchedulerOptions& options)
      : store_(store), options_(options), local_(options.worker_binary, options.workers) {}

  void run() {
    const int recovered = store_.recover_interrupted();
    if (recovered > 0) base::log_info(std::to_string(recovered) + " attempt(s) interrupted by a stopped scheduler will run again");
    auto last_control = Clock::time_point{};
    for (;;) {
      if (g_stop) break;
      const bool busy = in_flight_.size() > 0 || has_dispatchable();
      auto events = local_.poll(has_dispatchable() ? 0.0 : 0.1);
      for (auto& [id, c] : campaigns_)
        if (c->own_executor)
          for (auto& e : c->own_executor->poll(0.0)) events.push_back(std::move(e));
      store_.begin();
      try {
        for (auto& e : events) handle(e);
        if (Clock::now() - last_control > std::chrono::milliseconds(250) || campaigns_.empty()) {
          refresh_control();
          last_control = Clock::now();
        }
        fill();
        advance();
        flush();
      } catch (...) {
        store_.rollback();
        throw;
      }
      store_.commit();
      show_progress();
      if (campaigns_.empty() && in_flight_.empty() && !options_.follow && !busy) break;
    }
    if (g_stop) {
      store_.recover_interrupted();
      base::log_info("stopped; interrupted attempts will run again on the next `podium run`");
    }
    progress_.finish();
  }

 private:
  bool has_dispatchable() const {
    for (const auto& [id, c] : campaigns_)
      if (c->control == "running" && c->stage && c->executor->free_slots() > 0 && c->in_flight < c->spec.workers &&
          (!c->stage->ready.empty() || c->stage->can_ask()))
        return true;
    return false;
  }

  void emit(const CampaignRun& c, const std::string& kind, Json payload, bool record) {
    payload["campaign"] = c.rec.id;
    if (record) store_.add_event(c.rec.id, kind, payload);
    if (options_.log_json) {
      payload["event"] = kind;
      payload["time"] = store::now_unix_s();
      std::printf("%s\n", payload.dump().c_str());
      std::fflush(stdout);
    }
  }

  // Picks up newly queued campaigns and pause/resume/cancel requests written by the CLI.
  void refresh_control() {
    for (const auto& rec : store_.campaigns()) {
      auto it = campaigns_.find(rec.id);
      if (it == campaigns_.end()) {
        if (rec.state == "queued" || rec.state == "running") activate(rec);
        continue;
      }
      CampaignRun& c = *it->second;
      const std::string wanted = rec.state == "queued" ? "running" : rec.state;
      if (wanted == c.control) continue;
      if (wanted == "paused") emit(c, "campaign_paused", {}, true);
      if (wanted == "cancelled") {
        emit(c, "campaign_cancelled", {}, true);
        for (const auto& [key, f] : in_flight_)
          if (f.campaign_id == c.rec.id) c.executor->cancel(key);
      }
      if (wanted == "running") {
        store_.set_campaign_state(c.rec.id, "running");
        emit(c, "campaign_resumed", {}, true);
      }
      c.control = wanted;
    }
  }

  void activate(const store::CampaignRecord& rec) {
    auto c = std::make_unique<CampaignRun>();
    c->rec = rec;
    c->spec = parse_spec(rec.spec, "campaign " + std::to_string(rec.id));
    c->stages = store_.stages(rec.id);
    c->run_dir = campaign_run_dir(options_.database, rec);
    if (c->spec.executor.kind == "slurm") {
      c->own_executor = std::make_unique<SlurmExecutor>(c->spec.executor, c->run_dir, options_.worker_binary,
                                                        "podium-" + std::to_string(rec.id));
      c->executor = c->own_executor.get();
    } else {
      c->executor = &local_;
    }
    std::size_t current = 0;
    while (current < c->stages.size() && c->stages[current].state == "done") ++current;
    store_.set_campaign_state(rec.id, "running");
    emit(*c, rec.state == "queued" && rec.started_at == 0 ? "campaign_started" : "campaign_resumed",
         {{"name", rec.name}}, true);
    auto& ref = *c;
    campaigns_[rec.id] = std::move(c);
    if (current < ref.stages.size()) load_stage(ref, current);
  }

  Json stage_inputs(const CampaignRun& c, const Json& inputs) {
    Json out = Json::array();
    if (inputs.is_null()) return out;
    for (const auto& st : c.stages) {
      if (st.name != inputs["stage"].get<std::string>()) continue;
      std::vector<store::TrialRecord> done;
      for (auto& t : store_.trials(st.id))
        if (t.state == "done") done.push_back(std::move(t));
      if (inputs["select"] == "best" && !done.empty()) {
        auto best = std::max_element(done.begin(), done.end(), [](const auto& a, const auto& b) {
          return a.objectives[0].template get<double>() < b.objectives[0].template get<double>();
        });
        done = {*best};
      }
      for (const auto& t : done) {
        Json artifacts = Json::object();
        for (const auto& a : store_.artifacts(t.id)) artifacts[a.name] = a.path;
        out.push_back({{"trial_index", t.index}, {"params", t.params}, {"objectives", t.objectives},
                       {"features", t.features}, {"artifacts", artifacts},
                       {"strategy", t.strategy ? Json(*t.strategy) : Json(nullptr)}});
      }
    }
    return out;
  }

  void load_stage(CampaignRun& c, std::size_t index) {
    auto s = std::make_unique<StageRun>();
    s->rec = c.stages[index];
    const std::string path = "stages[" + std::to_string(index) + "]";
    search::SearchSetup setup;
    setup.space = search::Space::from_json(s->rec.description.at("params"), path + ".params");
    setup.features = search::Feature::list_from_json(s->rec.description.at("features"), path + ".features");
    setup.config = s->rec.search_config;
    setup.seed = base::derive_seed(c.rec.seed, index, kSearchSeedSalt);
    setup.inputs = stage_inputs(c, s->rec.inputs);
    for (const auto& p : setup.space.params) s->param_names.push_back(p.name);
    for (const auto& f : setup.features) s->feature_names.push_back(f.name);
    s->search = search::make_search(s->rec.algorithm, setup, path + ".search");
    if (s->rec.search_state) s->search->load(*s->rec.search_state);
    s->strategies.features = setup.features;
    s->strategies.threshold = s->rec.description.at("strategy_threshold").get<double>();
    for (const auto& t : store_.trials(s->rec.id)) {
      ++s->asked;
      if (t.state == "done") s->strategies.assign(t.features);
      if (t.state == "pending" || t.state == "interrupted")
        s->ready.push_back({t.id, t.index, t.params, t.context, t.seed, t.attempts});
    }
    if (s->rec.state == "waiting") {
      store_.set_stage_state(s->rec.id, "running");
      emit(c, "stage_started", {{"stage", s->rec.name}}, true);
    }
    c.stage = std::move(s);
    adopt_running_jobs(c);
  }

  // Re-attaches to batch jobs an earlier scheduler left running (they are not resubmitted).
  void adopt_running_jobs(CampaignRun& c) {
    StageRun& s = *c.stage;
    std::map<std::int64_t, store::TrialRecord> trials;
    for (auto& t : store_.trials(s.rec.id)) trials[t.id] = std::move(t);
    for (const auto& a : store_.running_attempts(s.rec.id)) {
      if (a.job_id.empty()) continue;  // died with the earlier scheduler; already interrupted
      const auto& t = trials.at(a.trial_id);
      PendingTrial p{t.id, t.index, t.params, t.context, t.seed, a.number - 1};
      AttemptOrder order = make_order(c, s, p);
      if (!c.executor->adopt(order, a.job_id)) continue;
      in_flight_[order.key] = {c.rec.id, a.id, p, a.number, &s, {}};
      ++c.in_flight;
      ++s.in_flight;
      emit(c, "attempt_reattached", {{"stage", s.rec.name}, {"trial", t.index}, {"job_id", a.job_id}}, true);
    }
  }

  AttemptOrder make_order(const CampaignRun& c, const StageRun& s, const PendingTrial& t) {
    AttemptOrder order;
    order.key = next_key_++;
    order.task = s.rec.task;
    order.config = s.rec.task_config;
    order.params = t.params;
    order.context = t.context;
    order.seed = t.seed;
    order.trial_index = static_cast<std::uint64_t>(t.index);
    order.attempt = t.attempts + 1;
    order.work_dir = c.run_dir / ("stage-" + std::to_string(s.rec.index) + "-" + s.rec.name) /
                     ("trial-" + std::to_string(t.index));
    order.timeout_s = c.spec.trial_timeout_s;
    return order;
  }

  void fill() {
    for (auto& [id, cp] : campaigns_) {
      CampaignRun& c = *cp;
      StageRun* s = c.stage.get();
      if (!s || c.control != "running") continue;
      while (c.executor->free_slots() > 0 && c.in_flight < c.spec.workers) {
        if (s->ready.empty()) {
          if (!s->can_ask()) break;
          const auto room = std::min<std::int64_t>(
              {static_cast<std::int64_t>(c.executor->free_slots()), c.spec.workers - c.in_flight, s->rec.budget_trials - s->asked});
          const auto proposals = s->search->ask(static_cast<std::size_t>(room));
          s->dirty = true;
          if (proposals.empty()) {
            (s->in_flight == 0 ? s->exhausted : s->starved) = true;
            break;
          }
          for (const auto& p : proposals) {
            Json params = Json::object();
            for (std::size_t i = 0; i < p.x.size(); ++i) params[s->param_names[i]] = p.x[i];
            const auto seed = base::derive_seed(c.rec.seed, static_cast<std::uint64_t>(s->rec.index), p.id);
            const auto trial_id = store_.add_trial(s->rec.id, static_cast<std::int64_t>(p.id), params, p.context, p.info, seed);
            s->ready.push_back({trial_id, static_cast<std::int64_t>(p.id), params, p.context, seed, 0});
            ++s->asked;
          }
        }
        dispatch(c, *s);
      }
    }
  }

  void dispatch(CampaignRun& c, StageRun& s) {
    PendingTrial t = std::move(s.ready.front());
    s.ready.pop_front();
    const AttemptOrder order = make_order(c, s, t);
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

  // Checks a worker's result against the task's declaration; returns an error text or "".
  static std::string invalid_result(const Json& r, const StageRun& s) {
    const auto& objectives = r.at("objectives");
    const auto& features = r.at("features");
    if (features.size() != s.feature_names.size())
      return "task returned " + std::to_string(features.size()) + " features, declared " +
             std::to_string(s.feature_names.size());
    for (std::size_t i = 0; i < features.size(); ++i)
      if (!features[i].is_number() || !std::isfinite(features[i].get<double>()))
        return "non-finite feature " + s.feature_names[i] + " = " + features[i].dump();
    for (const auto& o : objectives)
      if (!o.is_number() || !std::isfinite(o.get<double>())) return "non-finite objective " + o.dump();
    return "";
  }

  void handle(const ExecutorEvent& e) {
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
      std::vector<store::ArtifactRecord> artifacts;
      for (const auto& a : e.result["artifacts"])
        artifacts.push_back({a["name"], a["path"], a["sha256"], a["size"].get<std::int64_t>()});
      store_.complete_trial(f.trial.id, obs.objectives, s.feature_names, obs.features, e.result.value("info", Json::object()),
                            artifacts);
      s.search->tell({obs});
      store_.set_trial_strategy(f.trial.id, s.strategies.assign(obs.features));
      c.counter.record_finished();
      emit(c, "trial_done", {{"stage", s.rec.name}, {"trial", f.trial.index}, {"objectives", obs.objectives}}, false);
    } else {
      store_.finish_attempt(f.attempt_id, state, error, e.exit_code, e.signal);
      const std::string reason = "attempt " + std::to_string(f.number) + " " + state + ": " + error;
      if (c.control == "cancelled" || state == "cancelled") {
        store_.set_trial_state(f.trial.id, "cancelled", reason);
        s.search->tell({obs});
      } else if (f.number <= c.spec.retries) {
        store_.set_trial_state(f.trial.id, "pending", reason);
        f.trial.attempts = f.number;
        s.ready.push_front(f.trial);
        emit(c, "attempt_failed", {{"stage", s.rec.name}, {"trial", f.trial.index}, {"error", reason}}, true);
      } else {
        store_.set_trial_state(f.trial.id, "failed", reason);
        s.search->tell({obs});
        c.counter.record_finished();
        emit(c, "trial_failed", {{"stage", s.rec.name}, {"trial", f.trial.index}, {"error", reason}}, true);
      }
    }
    s.dirty = true;
    s.starved = false;
    --c.in_flight;
    --s.in_flight;
    in_flight_.erase(it);
  }

  // Ends finished stages and campaigns, starts next stages, and lets go of paused campaigns.
  void advance() {
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
      } else if (c.control == "running" && c.stage && c.stage->in_flight == 0 && !c.stage->can_ask() &&
                 (c.stage->ready.empty() || c.stage->out_of_time())) {
        StageRun& s = *c.stage;
        for (const auto& t : s.ready) store_.set_trial_state(t.id, "cancelled", "stage wall-time budget reached");
        regroup_strategies(s);
        store_.save_search_state(s.rec.id, s.search->save(), s.elapsed_s());
        store_.set_stage_state(s.rec.id, "done");
        emit(c, "stage_done", {{"stage", s.rec.name}}, true);
        const auto next = static_cast<std::size_t>(s.rec.index) + 1;
        c.stages[s.rec.index].state = "done";
        c.stage.reset();
        if (next < c.stages.size()) {
          load_stage(c, next);
        } else {
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

  void regroup_strategies(const StageRun& s) {
    std::vector<store::TrialRecord> done;
    for (auto& t : store_.trials(s.rec.id))
      if (t.state == "done") done.push_back(std::move(t));
    std::vector<std::vector<double>> features;
    for (const auto& t : done) features.push_back(t.features);
    const auto ids = search::group_strategies(s.strategies.features, features, s.strategies.threshold);
    for (std::size_t i = 0; i < done.size(); ++i)
      if (done[i].strategy != ids[i]) store_.set_trial_strategy(done[i].id, ids[i]);
  }

  // Streams metrics of running attempts and saves changed search states.
  void flush() {
    for (auto& [key, f] : in_flight_) {
      if (f.metrics.empty()) continue;
      store_.add_metrics(f.trial.id, f.metrics);
      f.metrics.clear();
    }
    for (auto& [id, c] : campaigns_) {
      if (!c->stage || !c->stage->dirty) continue;
      store_.save_search_state(c->stage->rec.id, c->stage->search->save(), c->stage->elapsed_s());
      c->stage->dirty = false;
    }
  }

  void show_progress() {
    if (!options_.progress || !progress_.due()) return;
    std::vector<ProgressLine> lines;
    for (const auto& [id, c] : campaigns_) {
      ProgressLine line;
      line.campaign_id = id;
      line.name = c->rec.name;
      line.control = c->control;
      const auto counts = store_.trial_counts(id);
      line.done = counts.done;
      line.failed = counts.failed;
      line.running = c->in_flight;
      std::int64_t budget = 0;
      for (const auto& st : c->stages) budget += st.budget_trials;
      line.budget = budget;
      line.stage = c->stage ? c->stage->rec.name : "";
      line.trials_per_minute = c->counter.per_minute();
      lines.push_back(line);
    }
    progress_.show(lines);
  }

  store::Store& store_;
  SchedulerOptions options_;
  LocalExecutor local_;
  std::map<std::int64_t, std::unique_ptr<CampaignRun>> campaigns_;
  std::map<std::int64_t, InFlight> in_flight_;
  std::int64_t next_key_ = 1;
  ProgressDisplay progress_;
};

}  // namespace

void run_scheduler(store::Store& store, const SchedulerOptions& options) {
  LockFile lock(options.database.string() + ".lock");
  g_stop = 0;
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
  std::signal(SIGPIPE, SIG_IGN);  // a dead worker's pipe must not kill the scheduler
  Scheduler(store, options).run();
}

}  // namespace podium::orchestrator
