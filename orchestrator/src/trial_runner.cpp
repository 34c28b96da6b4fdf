#include "trial_runner.h"

#include <fcntl.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>

#include "podium/base/config.h"
#include "podium/base/error.h"
#include "podium/base/log.h"
#include "podium/plugins/loader.h"
#include "podium/store/run_folders.h"
#include "sha256.h"
#include "slurm_files.h"

namespace podium::orchestrator {

using base::Json;

plugins::Task& TaskCache::get(const std::string& name) {
  auto& slot = tasks_[name];
  if (!slot) slot = plugins::load_task(name);
  return *slot;
}

namespace {

// From here on this process's stdout and stderr go to the end of `log` (as a local worker's go
// there through its executor); if it cannot be opened they stay where they were (the job's log).
void append_output_to(const std::filesystem::path& log, const std::string& header) {
  std::error_code ignored;
  std::filesystem::create_directories(log.parent_path(), ignored);
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (fd < 0) {
    base::log_warning("cannot write " + log.string() + "; this attempt logs to the job's output");
    return;
  }
  std::fflush(stdout), std::fflush(stderr);
  if (::write(fd, header.data(), header.size()) < 0) {
  }  // a log line lost never fails the trial
  ::dup2(fd, STDOUT_FILENO), ::dup2(fd, STDERR_FILENO);
  ::close(fd);
}

// One hand-over entry in the form SearchSetup::inputs documents (search.h).
plugins::InputTrial input_trial(const Json& j) {
  plugins::InputTrial in;
  in.stage = j.at("stage").get<std::string>();
  in.stage_index = j.at("stage_index").get<int>();
  in.trial_index = j.at("trial_index").get<std::int64_t>();
  in.params = j.at("params");
  in.objectives = j.at("objectives").get<std::vector<double>>();
  in.features = j.at("features").get<std::vector<double>>();
  if (!j.at("strategy").is_null()) in.strategy = j["strategy"].get<std::int64_t>();
  for (const auto& [name, path] : j.at("artifacts").items()) in.artifacts[name] = path.get<std::string>();
  in.info = j.value("info", Json::object());  // stages started by older versions stored none
  return in;
}

}  // namespace

Json run_attempt(TaskCache& tasks, const Json& order, const std::atomic<bool>& cancel, plugins::Sink& sink) {
  plugins::RunRequest request;
  request.params = order.at("params");
  request.context = order.at("context");
  request.config = order.at("config");
  request.seed = order.at("seed").get<std::uint64_t>();
  request.trial_index = order.at("trial_index").get<std::uint64_t>();
  request.attempt = order.at("attempt").get<int>();
  if (const Json& previous = order.at("previous_attempt"); !previous.is_null())
    request.previous_attempt = plugins::PreviousAttempt{previous.at("number").get<int>(), previous.at("state").get<std::string>(),
                                                        previous.at("error").get<std::string>()};
  for (const auto& in : order.at("inputs")) request.inputs.push_back(input_trial(in));
  request.work_dir = order.at("work_dir").get<std::string>();
  request.cancel = &cancel;
  std::filesystem::create_directories(request.work_dir);
  const plugins::RunResult result = tasks.get(order.at("task").get<std::string>()).run(request, sink);
  Json artifacts = Json::array();
  for (const auto& a : result.artifacts)
    artifacts.push_back({{"name", a.name},
                         {"path", a.path.string()},
                         {"sha256", sha256_file(a.path)},
                         {"size", std::filesystem::file_size(a.path)}});
  // nlohmann writes NaN as null; the scheduler rejects null features as non-finite.
  return {{"type", "result"},       {"key", order.at("key")}, {"objectives", result.objectives}, {"features", result.features},
          {"artifacts", artifacts}, {"info", result.info}};
}

namespace {

// Appends metric lines to an append-only stream the scheduler tails; flushed at most every
// 200 ms so a long trial's curve arrives live without a write per point.
class FileSink final : public plugins::Sink {
 public:
  explicit FileSink(const std::filesystem::path& path) : out_(std::fopen(path.c_str(), "a")) {
    if (!out_) throw base::RuntimeError(path.string() + ": cannot open metrics stream");
  }
  ~FileSink() override { std::fclose(out_); }
  void progress(double) override {}
  void metric(const std::string& name, double step, double value) override {
    const std::string line = Json{{"name", name}, {"step", step}, {"value", value}}.dump() + "\n";
    std::fwrite(line.data(), 1, line.size(), out_);
    const auto now = std::chrono::steady_clock::now();
    if (now - last_flush_ > std::chrono::milliseconds(200)) {
      std::fflush(out_);
      last_flush_ = now;
    }
  }

 private:
  FILE* out_;
  std::chrono::steady_clock::time_point last_flush_{};
};

}  // namespace

std::string attempt_log_header(int attempt) {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  ::gmtime_r(&now, &utc);
  char time[32];
  std::strftime(time, sizeof time, "%Y-%m-%d %H:%M:%S UTC", &utc);
  return "podium: attempt " + std::to_string(attempt) + " started " + time + "\n";
}

base::Json attempt_error(std::int64_t key, const std::exception& e) {
  base::log_error(std::string("attempt failed: ") + e.what());  // the log's last line says why
  Json error = {{"type", "error"}, {"key", key}, {"message", e.what()}};
  if (const auto* config = dynamic_cast<const base::ConfigError*>(&e))
    error.update({{"config_path", config->path()}, {"problem", config->problem()}});
  if (dynamic_cast<const base::UserError*>(&e)) error["retry"] = false;
  return error;
}

int run_batch_trial(const std::string& batch_file) {
  const char* index_text = std::getenv("SLURM_ARRAY_TASK_ID");
  const long index = index_text ? std::strtol(index_text, nullptr, 10) : 0;
  std::ifstream batch(batch_file);
  std::string order_path;
  for (long i = 0; i <= index; ++i)
    if (!std::getline(batch, order_path)) throw base::RuntimeError(batch_file + ": no line " + std::to_string(index));
  const Json order = base::read_json_file(order_path);
  const SlurmAttemptFiles files(std::filesystem::path(order_path).parent_path());
  append_output_to(std::filesystem::path(order.at("work_dir").get<std::string>()) / store::kTrialLog,
                   attempt_log_header(order.at("attempt").get<int>()));
  Json result;
  try {
    TaskCache tasks;
    std::atomic<bool> cancel{false};
    FileSink sink(files.metrics());
    result = run_attempt(tasks, order, cancel, sink);
  } catch (const std::exception& e) {
    result = attempt_error(order.at("key").get<std::int64_t>(), e);
  }
  base::write_json_file_atomic(files.result(), result);
  return 0;
}

}  // namespace podium::orchestrator
