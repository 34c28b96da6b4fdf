// The scheduler's loop, control requests and progress lines (scheduler_impl.h lists the other
// files of the class).
#include "podium/orchestrator/scheduler.h"

#include <csignal>
#include <cstdio>
#include <cstring>

#include "podium/base/error.h"
#include "podium/base/log.h"
#include "podium/orchestrator/campaigns.h"
#include "podium/store/run_folders.h"
#include "scheduler_impl.h"
#include "slurm_executor.h"

namespace podium::orchestrator {

namespace {

volatile std::sig_atomic_t g_stop = 0;  // the signal that asked to stop, 0 for none
void on_stop_signal(int signal) { g_stop = signal; }

}  // namespace

Scheduler::Scheduler(store::Store& store, const SchedulerOptions& options)
    : store_(store), options_(options), local_(options.worker_binary, options.workers) {}

int Scheduler::run() {
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
  progress_.finish();
  if (!g_stop) return 0;
  // The local workers are killed when the pool goes (with the scheduler, now); batch jobs live on.
  const int interrupted = store_.recover_interrupted();
  const std::string name = strsignal(g_stop);
  if (campaigns_.empty()) {
    base::log_info("stopped by " + name + " with no campaign left to run");
    return 0;
  }
  base::log_info("stopped by " + name + ": " + std::to_string(interrupted) +
                 " running attempt(s) killed and recorded interrupted, " + std::to_string(campaigns_.size()) +
                 " campaign(s) unfinished; `podium run` runs the interrupted attempts again" +
                 (in_flight_.size() > static_cast<std::size_t>(interrupted) ? " and re-attaches the batch jobs" : ""));
  return 128 + g_stop;
}

bool Scheduler::has_dispatchable() const {
  for (const auto& [id, c] : campaigns_)
    if (c->control == "running" && c->stage && c->executor->free_slots() > 0 && c->in_flight < c->spec.workers &&
        (!c->stage->ready.empty() || c->stage->ask_turn(c->spec.workers)))
      return true;
  return false;
}

void Scheduler::emit(const CampaignRun& c, const std::string& kind, Json payload, bool record) {
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
void Scheduler::refresh_control() {
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

void Scheduler::activate(const store::CampaignRecord& rec) {
  auto c = std::make_unique<CampaignRun>();
  c->rec = rec;
  c->spec = parse_spec(rec.spec, "campaign " + std::to_string(rec.id));
  c->stages = store_.stages(rec.id);
  c->run_dir = store::campaign_run_dir(options_.database, rec);
  if (c->spec.executor.kind == "slurm") {
    c->own_executor =
        std::make_unique<SlurmExecutor>(c->spec.executor, c->run_dir, options_.worker_binary, "podium-" + std::to_string(rec.id));
    c->executor = c->own_executor.get();
  } else {
    c->executor = &local_;
  }
  std::size_t current = 0;
  while (current < c->stages.size() && c->stages[current].state == "done") ++current;
  store_.set_campaign_state(rec.id, "running");
  emit(*c, rec.state == "queued" && rec.started_at == 0 ? "campaign_started" : "campaign_resumed", {{"name", rec.name}}, true);
  auto& ref = *c;
  campaigns_[rec.id] = std::move(c);
  if (current < ref.stages.size()) load_stage(ref, current);
}

// Streams metrics of running attempts and saves changed search states.
void Scheduler::flush() {
  for (auto& [key, f] : in_flight_) {
    if (f.metrics.empty()) continue;
    store_.add_metrics(f.trial.id, f.metrics);
    f.metrics.clear();
  }
  for (auto& [id, c] : campaigns_) {
    if (!c->stage || !c->stage->dirty) continue;
    store_.save_search_state(c->stage->rec.id, c->stage->search->save(), c->stage->elapsed_s(), c->stage->told);
    c->stage->dirty = false;
  }
}

void Scheduler::show_progress() {
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

int run_scheduler(store::Store& store, const SchedulerOptions& options) {
  g_stop = 0;
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
  std::signal(SIGPIPE, SIG_IGN);  // a dead worker's pipe must not kill the scheduler
  return Scheduler(store, options).run();
}

}  // namespace podium::orchestrator
