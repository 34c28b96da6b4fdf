#include "podium/learn/training_checkpoint.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <limits>
#include <string>

#include "podium/base/error.h"

namespace podium::learn {

namespace {

// Flushes a file or directory to disk, so the rename below publishes complete data.
void sync_path(const std::filesystem::path& path, bool directory) {
  const int fd = ::open(path.c_str(), directory ? O_RDONLY | O_DIRECTORY : O_RDONLY);
  if (fd < 0) throw base::RuntimeError("learn: cannot open " + path.string() + " to sync it: " + std::strerror(errno));
  const int rc = ::fsync(fd);
  ::close(fd);
  if (rc != 0) throw base::RuntimeError("learn: fsync of " + path.string() + " failed: " + std::strerror(errno));
}

}  // namespace

TrainingCheckpoint::TrainingCheckpoint(std::filesystem::path file, int every_n_updates, MetricSink send)
    : file_(std::move(file)), every_(every_n_updates), send_(std::move(send)) {
  if (every_ < 1)
    throw base::UserError("learn: TrainingCheckpoint every_n_updates " + std::to_string(every_n_updates) + " is not ≥ 1");
}

bool TrainingCheckpoint::start_from(const std::filesystem::path& source) {
  if (std::filesystem::exists(file_)) return false;
  std::filesystem::path partial = file_;
  partial += ".warm";
  try {
    std::filesystem::copy_file(source, partial, std::filesystem::copy_options::overwrite_existing);
  } catch (const std::filesystem::filesystem_error& e) {
    throw base::UserError("learn: warm start from " + source.string() + ": " + e.code().message());
  }
  std::filesystem::rename(partial, file_);
  return true;
}

std::optional<base::Json> TrainingCheckpoint::resume(Learner& learner, VecEnv& envs) {
  if (!std::filesystem::exists(file_)) return std::nullopt;
  base::Json saved;
  try {
    saved = learner.load_checkpoint(file_, envs);
  } catch (const base::UserError&) {
    throw;
  } catch (const std::exception& e) {
    // torch's messages run over many lines (with a backtrace); the first says what went wrong.
    const std::string what = e.what();
    throw base::RuntimeError("learn: checkpoint " + file_.string() + " cannot be read: " + what.substr(0, what.find('\n')));
  }
  if (!saved.is_object() || !saved.contains("updates") || !saved.contains("metrics"))
    throw base::UserError("learn: " + file_.string() + " is a learner checkpoint not written by TrainingCheckpoint");
  if (const base::Json format = saved.value("format", base::Json()); format != kFormatVersion)
    throw base::UserError("learn: " + file_.string() + " is a training checkpoint of format " +
                          (format.is_null() ? std::string("1 (no version)") : format.dump()) + " but this build reads format " +
                          std::to_string(kFormatVersion) +
                          ": delete it to train the trial from scratch, or finish it with the build that wrote it");
  updates_ = saved.at("updates").get<std::int64_t>();
  metrics_.clear();
  for (const auto& [name, saved_series] : saved.at("metrics").items()) {
    Series& series = metrics_[name];
    series.steps = saved_series.at("steps").get<std::vector<double>>();
    // JSON has no NaN: dump() wrote a non-finite value as null (the store keeps it as NULL too).
    for (const auto& v : saved_series.at("values"))
      series.values.push_back(v.is_null() ? std::numeric_limits<double>::quiet_NaN() : v.get<double>());
    for (std::size_t i = 0; i < series.steps.size(); ++i) send(name, series.steps[i], series.values[i]);
  }
  return saved.at("extra");
}

void TrainingCheckpoint::metric(const std::string& name, double step, double value) {
  send(name, step, value);
  Series& series = metrics_[name];
  series.steps.push_back(step);
  series.values.push_back(value);
}

void TrainingCheckpoint::send(const std::string& name, double step, double value) const {
  if (!send_) throw base::RuntimeError("learn: TrainingCheckpoint has no metric sink for \"" + name + "\"");
  send_(name, step, value);
}

bool TrainingCheckpoint::on_update(const Learner& learner, const VecEnv& envs, const base::Json& extra) {
  if (++updates_ % every_ != 0) return false;
  std::filesystem::path temp = file_;
  temp += ".tmp";
  base::Json metrics = base::Json::object();
  for (const auto& [name, series] : metrics_) metrics[name] = {{"steps", series.steps}, {"values", series.values}};
  learner.save_checkpoint(temp, envs,
                          {{"format", kFormatVersion}, {"updates", updates_}, {"metrics", metrics}, {"extra", extra}});
  sync_path(temp, false);
  std::filesystem::rename(temp, file_);
  sync_path(file_.parent_path().empty() ? "." : file_.parent_path(), true);
  return true;
}

}  // namespace podium::learn
