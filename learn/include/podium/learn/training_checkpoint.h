#pragma once
/// Checkpointing a training run into its trial folder so that a later attempt (after a kill,
/// crash, timeout or requeue) continues it exactly: the resumed run ends with the same final
/// parameters, bitwise, and the same per-update TrainStats (timings aside) as an uninterrupted
/// one. Use from a task:
///
///     TrainingCheckpoint checkpoint(trial_dir / "training.ckpt", 10,
///                                   [&](const std::string& n, double step, double v) { sink.metric(n, step, v); });
///     base::Json extra;  // the task's own state (curriculum, ...)
///     if (auto saved = checkpoint.resume(learner, envs)) extra = *saved;  // replays the metrics
///     learner.train_until(envs, budget, [&](const TrainStats& s) {
///       checkpoint.metric("train_return", s.env_steps, s.mean_return);
///       ... update extra ...
///       checkpoint.on_update(learner, envs, extra);
///     });
///
/// Metric points go through metric(), which sends them on and keeps them in the checkpoint:
/// resume() sends every point up to the checkpoint again, because a kill may come after the
/// checkpoint was written but before the points sent just before it were stored. Points after
/// the checkpoint come again from the updates the resumed run repeats. The receiver must drop a
/// (name, step) it already has (the store does: plugins/task.h).
///
/// The learner and envs must be built exactly as in the first attempt (same config, seeds,
/// copies); load_checkpoint() rejects another config. An "update" is one TrainCallback call:
/// a PPO iteration, or a SAC log interval (SacConfig::log_interval_steps).
///
/// Each file carries kFormatVersion, raised whenever what is saved (here or in the `extra` of
/// character::run_training_stage, its main user) changes layout or meaning: resume() refuses a file
/// of another version with one line saying what to do, instead of reading it half right.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "podium/base/json.h"
#include "podium/learn/learner.h"
#include "podium/learn/vec_env.h"

namespace podium::learn {

class TrainingCheckpoint {
 public:
  /// The layout saved; resume() reads this version only.
  static constexpr int kFormatVersion = 2;

  /// Where metric() sends points (a task binds its plugins::Sink here).
  using MetricSink = std::function<void(const std::string& name, double step, double value)>;

  /// `every_n_updates` ≥ 1: on_update() saves on every Nth call. `send` may be empty for a run
  /// that reports no metric points through metric() (metric() then throws).
  TrainingCheckpoint(std::filesystem::path file, int every_n_updates, MetricSink send = {});

  /// If the file exists: loads it into learner + envs, sends every metric point saved with it
  /// through `send` (per name in the order metric() kept them, names in alphabetical order) and
  /// returns the `extra` saved with it (null if none was given); otherwise std::nullopt and
  /// nothing changes. Call it before metric(): a resume replaces the points kept so far. Throws
  /// base::UserError for a file of another format version (or of none: an older build's).
  std::optional<base::Json> resume(Learner& learner, VecEnv& envs);

  /// Training on from another run's checkpoint (a warm start): if this checkpoint's file does not
  /// exist yet, copies `source` to it, whole before it takes the name, so a kill mid-copy leaves
  /// nothing to resume from. Returns whether it copied; resume() then loads the copy (its
  /// learner, environments, metric points and extra). Throws base::UserError naming `source`.
  bool start_from(const std::filesystem::path& source);

  /// Sends one metric point through `send` and keeps it for the next checkpoint.
  void metric(const std::string& name, double step, double value);

  /// Call from the TrainCallback after every update. Every Nth call saves learner, envs, the
  /// metric points and `extra` atomically: written to `file`.tmp, flushed to disk, then renamed
  /// over `file`, so a kill at any moment leaves either the previous checkpoint or the new one,
  /// never a torn file. Returns whether it saved.
  bool on_update(const Learner& learner, const VecEnv& envs, const base::Json& extra);

  /// Updates counted so far, including those before the checkpoint resumed from: after resume()
  /// the next callback is update updates() + 1.
  std::int64_t updates() const { return updates_; }
  const std::filesystem::path& file() const { return file_; }
  /// Later saves go to `file`; the metric points kept and the update count carry over. For a task
  /// whose environments must be rebuilt mid-run (a new control rate): a checkpoint loads only into
  /// environments like those it saved, so it keeps one file per kind of environment.
  void retarget(std::filesystem::path file) { file_ = std::move(file); }

 private:
  // One metric's points, as two columns: a checkpoint may hold thousands of points.
  struct Series {
    std::vector<double> steps, values;
  };

  void send(const std::string& name, double step, double value) const;

  std::filesystem::path file_;
  int every_;
  MetricSink send_;
  std::int64_t updates_ = 0;
  std::map<std::string, Series> metrics_;
};

}  // namespace podium::learn
