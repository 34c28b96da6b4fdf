#include "progress.h"

#include <cstdio>

namespace podium::orchestrator {

using Clock = std::chrono::steady_clock;

void ProgressCounter::record_finished() { finished_.push_back(Clock::now()); }

double ProgressCounter::per_minute() {
  const auto now = Clock::now();
  while (!finished_.empty() && now - finished_.front() > std::chrono::minutes(1)) finished_.pop_front();
  // Over the first minute, scale by the time actually observed.
  const double window_s = std::min(60.0, std::chrono::duration<double>(now - since_).count());
  return window_s > 0.5 ? static_cast<double>(finished_.size()) * 60.0 / window_s : 0.0;
}

std::string format_progress(const ProgressLine& l) {
  char eta[32] = "--";
  const double remaining = static_cast<double>(l.budget - l.done - l.failed);
  if (l.trials_per_minute > 0 && remaining >= 0) {
    const long s = static_cast<long>(remaining / l.trials_per_minute * 60.0);
    std::snprintf(eta, sizeof eta, "%ld:%02ld:%02ld", s / 3600, s / 60 % 60, s % 60);
  }
  char buffer[512];
  std::snprintf(buffer, sizeof buffer, "#%lld %s [%s]%s %lld/%lld done, %lld running, %lld failed, %.0f trials/min, ETA %s",
                static_cast<long long>(l.campaign_id), l.name.c_str(), l.stage.c_str(),
                l.control == "running" ? "" : (" (" + l.control + ")").c_str(), static_cast<long long>(l.done),
                static_cast<long long>(l.budget), static_cast<long long>(l.running), static_cast<long long>(l.failed),
                l.trials_per_minute, eta);
  return buffer;
}

bool ProgressDisplay::due() {
  const auto now = Clock::now();
  if (now - last_ < std::chrono::milliseconds(500)) return false;
  last_ = now;
  return true;
}

void ProgressDisplay::show(const std::vector<ProgressLine>& lines) {
  std::string out;
  if (drawn_ > 0) out += "\x1b[" + std::to_string(drawn_) + "F";  // back to the first line drawn
  for (const auto& l : lines) out += "\x1b[2K" + format_progress(l) + "\n";
  for (std::size_t i = lines.size(); i < drawn_; ++i) out += "\x1b[2K\n";
  drawn_ = std::max(drawn_, lines.size());
  std::fputs(out.c_str(), stderr);
  std::fflush(stderr);
}

void ProgressDisplay::forget(std::int64_t) { last_ = {}; }

void ProgressDisplay::finish() { drawn_ = 0; }

}  // namespace podium::orchestrator
