#pragma once
// Live progress on a terminal: one line per running campaign, redrawn in place at most twice a
// second (done/running/failed, trials per minute, ETA).
#include <chrono>
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

namespace podium::orchestrator {

/// Finished trials in a sliding one-minute window.
class ProgressCounter {
 public:
  void record_finished();
  double per_minute();

 private:
  std::deque<std::chrono::steady_clock::time_point> finished_;
  std::chrono::steady_clock::time_point since_ = std::chrono::steady_clock::now();
};

struct ProgressLine {
  std::int64_t campaign_id = 0;
  std::string name, stage, control;
  std::int64_t done = 0, failed = 0, running = 0, budget = 0;
  double trials_per_minute = 0;
};

/// Formats one line, e.g. "#3 demo [explore] 120/200 done, 2 running, 0 failed, 540/min, ETA 0:09".
std::string format_progress(const ProgressLine& line);

class ProgressDisplay {
 public:
  bool due();
  void show(const std::vector<ProgressLine>& lines);
  void forget(std::int64_t campaign_id);
  void finish();

 private:
  std::size_t drawn_ = 0;
  std::chrono::steady_clock::time_point last_ = {};
};

}  // namespace podium::orchestrator
