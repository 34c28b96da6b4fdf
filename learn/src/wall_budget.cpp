#include "podium/learn/wall_budget.h"

#include <cstdio>

#include "podium/base/error.h"

namespace podium::learn {

WallBudget::WallBudget(double minutes, const base::Json& state) : limit_s_(minutes > 0.0 ? 60.0 * minutes : 0.0) {
  if (state.is_null()) return;
  try {
    spent_s_ = state.at("spent_s").get<double>();
    last_round_s_ = state.at("last_round_s").get<double>();
  } catch (const base::Json::exception& e) {
    throw base::UserError(std::string("wall budget state: ") + e.what());
  }
}

bool WallBudget::another_round_fits() const { return !limited() || spent_s_ + last_round_s_ <= limit_s_; }

void WallBudget::add_round(double seconds) {
  spent_s_ += seconds;
  last_round_s_ = seconds;
}

void WallBudget::start_round() { round_start_ = std::chrono::steady_clock::now(); }

void WallBudget::end_round() {
  add_round(std::chrono::duration<double>(std::chrono::steady_clock::now() - round_start_).count());
}

std::string WallBudget::stopped_by(std::int64_t steps, std::int64_t total_steps) {
  return steps < total_steps ? "time" : "steps";
}

std::string WallBudget::end_message(std::string_view who, std::int64_t steps, std::int64_t total_steps) const {
  char tail[128];
  std::snprintf(tail, sizeof tail, " at environment step %lld after %.1f min", static_cast<long long>(steps), spent_s_ / 60.0);
  return std::string(who) + ": training ended by " + stopped_by(steps, total_steps) + tail;
}

base::Json WallBudget::state() const { return {{"spent_s", spent_s_}, {"last_round_s", last_round_s_}}; }

}  // namespace podium::learn
