#pragma once
// The scheduler's state and class, shared by the files that implement its jobs:
//   scheduler.cpp        the loop (one transaction per turn), control requests, progress lines;
//   stage_lifecycle.cpp  starting a stage (hand-over resolved and stored), ending it done or
//                        failed, ending campaigns;
//   dispatch.cpp         asking the search, dispatching attempts, taking their results;
//   hand_over.cpp        which earlier trials a stage's inputs select (free functions).
#include <chrono>
#include <deque>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "executor.h"
#include "local_executor.h"
#include "podium/orchestrator/scheduler.h"
#include "podium/orchestrator/spec.h"
#include "podium/search/search.h"
#include "podium/search/strategies.h"
#include "podium/store/store.h"
#include "progress.h"

namespace podium::orchestrator {

using Clock = std::chrono::steady_clock;

struct PendingTrial {
  std::int64_t id = 0, index = 0;
  Json params, context;
  std::uint64_t seed = 0;
  int attempts = 0;                  // attempts already made
  std::optional<std::size_t> input;  // per_trial "each": the input it receives
};

// Strategy ids (search/strategies.h): a successful trial's id is its feature grid cell, final when
// it finishes (order-free); a trial the task's success rule rejects has none.
struct StrategyTracker {
  std::vector<search::Feature> features;
  double threshold = 0;
  Json success = nullptr;  // the description's "success" rule
  std::optional<std::int64_t> assign(const std::vector<double>& f, const Json& info) const;
};

struct StageRun {
  store::StageRecord rec;
  const StageSpec* spec = nullptr;    // into the campaign's parsed spec
  Json input_trials = Json::array();  // the hand-over, as stored with the stage
  std::unique_ptr<search::Search> search;
  std::vector<std::string> param_names, feature_names;
  StrategyTracker strategies;
  std::deque<PendingTrial> ready;
  std::int64_t asked = 0;
  // Results are told in the order the trials were asked (Scheduler::advance_search): `told` of
  // them so far; `untold` holds the later ones' indexes in that order, `held` those finished.
  std::int64_t told = 0;
  std::deque<std::int64_t> untold;
  std::map<std::int64_t, search::Observation> held;
  int in_flight = 0;
  bool exhausted = false;  // the search had nothing to propose with nothing untold
  bool starved = false;    // the search had nothing to propose until it is told a result
  bool dirty = false;      // search state changed since the last save
  Clock::time_point active_since = Clock::now();

  double elapsed_s() const { return rec.elapsed_s + std::chrono::duration<double>(Clock::now() - active_since).count(); }
  bool out_of_time() const { return rec.budget_seconds > 0 && elapsed_s() >= rec.budget_seconds; }
  bool can_ask() const { return !exhausted && !starved && asked < rec.budget_trials && !out_of_time(); }
  // Whether the rule lets the search be asked now: fewer than `workers` trials untold.
  bool ask_turn(int workers) const { return can_ask() && untold.size() < static_cast<std::size_t>(workers); }
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
  std::string failure;              // why a stage failed: the campaign ends failed with it
  std::filesystem::path run_dir;
  Executor* executor = nullptr;            // the shared local pool, or own_executor
  std::unique_ptr<Executor> own_executor;  // a Slurm executor of this campaign's own
  int in_flight = 0;
  ProgressCounter counter;
};

class Scheduler {
 public:
  Scheduler(store::Store& store, const SchedulerOptions& options);
  int run();  // run_scheduler's exit code

 private:
  // scheduler.cpp
  bool has_dispatchable() const;
  void emit(const CampaignRun& c, const std::string& kind, Json payload, bool record);
  void refresh_control();
  void activate(const store::CampaignRecord& rec);
  void flush();
  void show_progress();

  // stage_lifecycle.cpp
  void load_stage(CampaignRun& c, std::size_t index);
  void start_stage(CampaignRun& c, StageRun& s);
  void fail_stage(CampaignRun& c, StageRun& s, const std::string& reason);
  void end_stage(CampaignRun& c);
  void advance();
  void regroup_strategies(const StageRun& s);

  // dispatch.cpp
  void adopt_running_jobs(CampaignRun& c);
  AttemptOrder make_order(const CampaignRun& c, const StageRun& s, const PendingTrial& t);
  int failed_attempts(std::int64_t trial_id) const;
  void fill();
  void advance_search(CampaignRun& c, StageRun& s);
  void ask(CampaignRun& c, StageRun& s, std::size_t room);
  void dispatch(CampaignRun& c, StageRun& s);
  void handle(const ExecutorEvent& e);

  store::Store& store_;
  SchedulerOptions options_;
  LocalExecutor local_;
  std::map<std::int64_t, std::unique_ptr<CampaignRun>> campaigns_;
  std::map<std::int64_t, InFlight> in_flight_;
  std::int64_t next_key_ = 1;
  ProgressDisplay progress_;
};

}  // namespace podium::orchestrator
