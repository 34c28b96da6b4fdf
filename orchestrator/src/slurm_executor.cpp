#include "slurm_executor.h"

#include <unistd.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <thread>

#include "command.h"
#include "podium/base/error.h"
#include "podium/base/json.h"

namespace podium::orchestrator {

namespace fs = std::filesystem;
using base::Json;

SlurmExecutor::SlurmExecutor(ExecutorSpec spec, fs::path run_dir, fs::path podium_binary, std::string job_name)
    : spec_(std::move(spec)), run_dir_(std::move(run_dir)), binary_(std::move(podium_binary)), job_name_(std::move(job_name)) {}

void SlurmExecutor::check_cluster(const ExecutorSpec& spec, const std::string& json_path) {
  for (const char* tool : {"sbatch", "squeue", "scancel", "sinfo"})
    if (!on_path(tool)) throw base::UserError(json_path + ".kind: \"slurm\" needs " + tool + ", which is not on PATH");
  const auto partitions = run_command({"sinfo", "-h", "-o", "%R"});
  if (partitions.exit_code != 0)
    throw base::UserError(json_path + ": sinfo failed: " + partitions.err.substr(0, partitions.err.find('\n')));
  std::stringstream lines(partitions.out);
  std::string name, known;
  while (std::getline(lines, name)) {
    if (name == spec.partition) return;
    known += (known.empty() ? "" : ", ") + name;
  }
  throw base::UserError(json_path + ".partition: \"" + spec.partition +
                        "\" is not a partition of this cluster (sinfo lists: " + known + ")");
}

std::size_t SlurmExecutor::free_slots() const {
  const auto used = jobs_.size();
  return used >= static_cast<std::size_t>(spec_.max_jobs_in_queue) ? 0 : spec_.max_jobs_in_queue - used;
}

std::string SlurmExecutor::submit(const AttemptOrder& order) {
  Job job(order);
  fs::remove_all(job.files.folder());  // leftovers of a run whose scheduler died before it was placed
  fs::create_directories(job.files.folder());
  base::write_json_file_atomic(job.files.order(), to_json(order));
  jobs_.emplace(order.key, std::move(job));
  unsubmitted_.push_back(order.key);
  return "slurm";
}

bool SlurmExecutor::adopt(const AttemptOrder& order, const std::string& job_id) {
  Job job(order);
  job.job_id = job_id;
  jobs_.emplace(order.key, std::move(job));
  return true;
}

void SlurmExecutor::cancel(std::int64_t key) {
  auto it = jobs_.find(key);
  if (it == jobs_.end()) return;
  it->second.cancel_requested = true;
  if (!it->second.job_id.empty()) run_command({"scancel", it->second.job_id});
}

// All attempts waiting to go out leave as one job array: line i of the batch file names the
// order of array task i.
void SlurmExecutor::submit_batch(std::vector<ExecutorEvent>& events) {
  fs::create_directories(run_dir_ / "slurm");
  const fs::path batch = run_dir_ / "slurm" / ("batch-" + std::to_string(::getpid()) + "-" + std::to_string(++batches_) + ".txt");
  {
    std::ofstream out(batch);
    for (const auto key : unsubmitted_) out << fs::absolute(jobs_.at(key).files.order()).string() << "\n";
  }
  std::vector<std::string> argv = {"sbatch",          "--parsable",
                                   "--job-name",      job_name_,
                                   "--array",         "0-" + std::to_string(unsubmitted_.size() - 1),
                                   "--partition",     spec_.partition,
                                   "--cpus-per-task", std::to_string(spec_.cpus_per_task),
                                   "--output",        (run_dir_ / "slurm" / "%A_%a.log").string()};
  if (!spec_.account.empty()) argv.insert(argv.end(), {"--account", spec_.account});
  if (!spec_.time.empty()) argv.insert(argv.end(), {"--time", spec_.time});
  if (!spec_.mem.empty()) argv.insert(argv.end(), {"--mem", spec_.mem});
  argv.insert(argv.end(), spec_.extra_sbatch.begin(), spec_.extra_sbatch.end());
  argv.insert(argv.end(),
              {"--wrap", "exec '" + fs::absolute(binary_).string() + "' trial --batch '" + fs::absolute(batch).string() + "'"});
  const auto result = run_command(argv);
  const std::string array_id = result.out.substr(0, result.out.find_first_of(";\n"));
  if (result.exit_code != 0 || array_id.empty()) {
    const std::string why = "sbatch failed: " + result.err.substr(0, result.err.find('\n'));
    for (const auto key : unsubmitted_) finish(key, "failed", why, events);
  } else {
    for (std::size_t i = 0; i < unsubmitted_.size(); ++i) {
      Job& job = jobs_.at(unsubmitted_[i]);
      job.job_id = array_id + "_" + std::to_string(i);
      job.started = Clock::now();
      ExecutorEvent e;
      e.kind = ExecutorEvent::Kind::placed;
      e.key = job.order.key;
      e.job_id = job.job_id;
      events.push_back(e);
      if (job.cancel_requested) run_command({"scancel", job.job_id});
    }
  }
  unsubmitted_.clear();
}

void SlurmExecutor::tail_metrics(Job& job, std::vector<ExecutorEvent>& events) {
  std::error_code ec;
  const auto size = fs::file_size(job.files.metrics(), ec);
  if (ec || size <= job.metrics_offset) return;
  std::ifstream in(job.files.metrics(), std::ios::binary);
  in.seekg(static_cast<std::streamoff>(job.metrics_offset));
  std::string chunk(size - job.metrics_offset, '\0');
  in.read(chunk.data(), static_cast<std::streamsize>(chunk.size()));
  // Only complete lines: the job may be in the middle of writing the last one.
  const auto end = chunk.rfind('\n');
  if (end == std::string::npos) return;
  job.metrics_offset += end + 1;
  std::stringstream lines(chunk.substr(0, end));
  std::string line;
  while (std::getline(lines, line)) {
    const Json m = Json::parse(line, nullptr, false);
    if (m.is_discarded()) continue;
    ExecutorEvent e;
    e.kind = ExecutorEvent::Kind::metric;
    e.key = job.order.key;
    e.name = m.value("name", "");
    e.step = m.value("step", 0.0);
    e.value = m["value"].is_number() ? m["value"].get<double>() : std::nan("");
    events.push_back(e);
  }
}

bool SlurmExecutor::take_result(Job& job, std::vector<ExecutorEvent>& events) {
  if (!fs::exists(job.files.result())) return false;
  tail_metrics(job, events);
  const Json r = base::read_json_file(job.files.result());
  ExecutorEvent e;
  e.key = job.order.key;
  if (r.value("type", "") == "result") {
    e.state = "done";
    e.result = r;
  } else {
    e.state = job.cancel_requested ? "cancelled" : "failed";
    e.error = r.value("message", "task failed");
    e.retry = r.value("retry", true);
  }
  events.push_back(e);
  jobs_.erase(job.order.key);
  return true;
}

void SlurmExecutor::finish(std::int64_t key, const std::string& state, const std::string& error,
                           std::vector<ExecutorEvent>& events) {
  ExecutorEvent e;
  e.key = key;
  e.state = state;
  e.error = error;
  events.push_back(e);
  jobs_.erase(key);
}

// Maps Slurm job states to attempt states; Slurm's own state and reason go into the error text.
void SlurmExecutor::query_states(std::vector<ExecutorEvent>& events) {
  const auto q = run_command({"squeue", "-h", "-r", "-t", "all", "-o", "%i|%T|%r|%N"});
  if (q.exit_code != 0) return;  // the controller may be restarting: try again next time
  std::map<std::string, std::vector<std::string>> rows;
  std::stringstream lines(q.out);
  std::string line;
  while (std::getline(lines, line)) {
    std::vector<std::string> fields;
    std::stringstream parts(line);
    std::string field;
    while (std::getline(parts, field, '|')) fields.push_back(field);
    if (fields.size() >= 3) rows[fields[0]] = fields;
  }
  std::vector<std::int64_t> keys;
  for (const auto& [key, job] : jobs_) keys.push_back(key);
  for (const auto key : keys) {
    Job& job = jobs_.at(key);
    if (job.job_id.empty() || take_result(job, events)) continue;
    auto row = rows.find(job.job_id);
    std::string state, reason;
    if (row == rows.end()) {
      // squeue forgets finished jobs after MinJobAge (and never lists an array task cancelled
      // while pending): ask accounting, else the job-completion log, if the cluster keeps either.
      for (const bool completion_log : {false, true}) {
        std::vector<std::string> argv = {"sacct", "-n", "-P", "-X", "-j", job.job_id, "-o", "State"};
        if (completion_log) argv.insert(argv.begin() + 1, "-c");
        const auto acct = run_command(argv);
        if (acct.exit_code == 0 && !acct.out.empty()) {
          state = acct.out.substr(0, acct.out.find_first_of("| \n"));
          reason = completion_log ? "from sacct -c" : "from sacct";
          break;
        }
      }
      if (state.empty()) {
        if (++job.unknown_polls >= 3)
          finish(key, "failed", "slurm job " + job.job_id + " is no longer known to Slurm and left no result", events);
        continue;
      }
    } else {
      state = row->second[1];
      reason = row->second[2];
      const std::string node = row->second.size() > 3 ? row->second[3] : "";
      if (!node.empty() && node != job.node && node != "(null)") {
        job.node = node;
        ExecutorEvent e;
        e.kind = ExecutorEvent::Kind::placed;
        e.key = key;
        e.job_id = job.job_id;
        e.host = node;
        events.push_back(e);
      }
    }
    const bool active = state == "PENDING" || state == "RUNNING" || state == "CONFIGURING" || state == "COMPLETING" ||
                        state == "SUSPENDED" || state == "REQUEUED" || state == "RESIZING";
    if (active) {
      const double age_s = std::chrono::duration<double>(Clock::now() - job.started).count();
      if (!job.timed_out && age_s > job.order.timeout_s) {
        job.timed_out = true;
        run_command({"scancel", job.job_id});
      }
      continue;
    }
    const std::string why =
        "slurm job " + job.job_id + " " + state + (reason.empty() || reason == "None" ? "" : " (" + reason + ")");
    if (job.cancel_requested) finish(key, "cancelled", why, events);
    else if (job.timed_out) finish(key, "timeout", why + " after the trial timeout", events);
    else if (state == "TIMEOUT" || state == "DEADLINE") finish(key, "timeout", why, events);
    else finish(key, "failed", why, events);
  }
}

std::vector<ExecutorEvent> SlurmExecutor::poll(double max_wait_s) {
  std::vector<ExecutorEvent> events;
  if (!unsubmitted_.empty()) submit_batch(events);
  std::vector<std::int64_t> keys;
  for (const auto& [key, job] : jobs_) keys.push_back(key);
  for (const auto key : keys) {
    Job& job = jobs_.at(key);
    if (job.job_id.empty()) continue;
    tail_metrics(job, events);
    take_result(job, events);
  }
  if (Clock::now() - last_query_ > std::chrono::seconds(1) && !jobs_.empty()) {
    query_states(events);
    last_query_ = Clock::now();
  }
  if (events.empty() && max_wait_s > 0) std::this_thread::sleep_for(std::chrono::duration<double>(std::min(max_wait_s, 0.2)));
  return events;
}

}  // namespace podium::orchestrator
