#pragma once
// The Slurm executor: each attempt is a job (several ready at once go in one job array) running
// `podium trial --batch FILE` against the campaign's run folder on a shared filesystem. The job
// appends metrics to an append-only stream and writes its result atomically; this executor tails
// the stream, ingests results, and watches job states with squeue (sacct for jobs squeue has
// forgotten) — the scheduler stays the only database writer.
#include <chrono>
#include <filesystem>
#include <map>
#include <vector>

#include "executor.h"
#include "podium/orchestrator/spec.h"
#include "slurm_files.h"

namespace podium::orchestrator {

class SlurmExecutor final : public Executor {
 public:
  SlurmExecutor(ExecutorSpec spec, std::filesystem::path run_dir, std::filesystem::path podium_binary, std::string job_name);
  std::size_t free_slots() const override;
  std::string submit(const AttemptOrder& order) override;
  void cancel(std::int64_t key) override;
  std::vector<ExecutorEvent> poll(double max_wait_s) override;
  std::string host() const override { return ""; }
  bool adopt(const AttemptOrder& order, const std::string& job_id) override;

  /// Checks that sbatch is on PATH and the partition exists; throws base::UserError naming
  /// `json_path` otherwise. Called when a campaign is submitted, before anything is queued.
  static void check_cluster(const ExecutorSpec& spec, const std::string& json_path);

 private:
  using Clock = std::chrono::steady_clock;
  struct Job {
    explicit Job(const AttemptOrder& o) : order(o), files(o.work_dir / ("slurm-attempt-" + std::to_string(o.attempt))) {}
    AttemptOrder order;
    SlurmAttemptFiles files;
    std::string job_id, node;
    std::uintmax_t metrics_offset = 0;
    bool cancel_requested = false, timed_out = false;
    int unknown_polls = 0;
    Clock::time_point started = Clock::now();
  };
  void submit_batch(std::vector<ExecutorEvent>& events);
  void tail_metrics(Job& job, std::vector<ExecutorEvent>& events);
  bool take_result(Job& job, std::vector<ExecutorEvent>& events);
  void query_states(std::vector<ExecutorEvent>& events);
  void finish(std::int64_t key, const std::string& state, const std::string& error, std::vector<ExecutorEvent>& events);

  ExecutorSpec spec_;
  std::filesystem::path run_dir_, binary_;
  std::string job_name_;
  std::map<std::int64_t, Job> jobs_;
  std::vector<std::int64_t> unsubmitted_;
  Clock::time_point last_query_{};
  int batches_ = 0;
};

}  // namespace podium::orchestrator
