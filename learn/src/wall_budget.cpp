#include "podium/learn/wall_budget.h"

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

base::Json WallBudget::state() const { return {{"spent_s", spent_s_}, {"last_round_s", last_round_s_}}; }

}  // namespace podium::learn
