#include "podium/character/curriculum.h"

#include <algorithm>
#include <cmath>

#include "podium/base/config.h"
#include "podium/base/error.h"

namespace podium::character {

namespace {

using base::ConfigReader;

// Reads a config object with `read(reader)`, its unknown keys rejected.
template <class Config, class F>
Config read_config(const base::Json& json, const std::string& where, F&& read) {
  ConfigReader reader(json, where);
  Config c;
  read(reader, c);
  reader.finish();
  return c;
}

template <typename T>
T state_field(const base::Json& state, const char* key, const char* who) {
  try {
    return state.at(key).get<T>();
  } catch (const base::Json::exception& e) {
    throw base::UserError(std::string(who) + " state: " + key + ": " + e.what());
  }
}

}  // namespace

ThresholdCurriculum::Config ThresholdCurriculum::Config::from_json(const base::Json& json, const std::string& where) {
  return read_config<Config>(json, where, [](ConfigReader& r, Config& c) {
    r.field("initial", c.initial);
    c.factor = r.number("factor", c.factor, {.min = 0.0, .exclusive_min = true});
    r.field("increment", c.increment);
    r.field("threshold", c.threshold);
    r.field("accumulate", c.accumulate);
    r.field("limit", c.limit);
  });
}

ThresholdCurriculum::ThresholdCurriculum(Config config) : config_(config), value_(config.initial) {
  const double next = config_.factor * config_.initial + config_.increment;
  if (!(config_.factor > 0)) throw base::UserError("curriculum: factor " + std::to_string(config_.factor) + " is not > 0");
  if (next == config_.initial) throw base::UserError("curriculum: factor and increment leave the value unchanged");
  if ((next - config_.initial) * (config_.limit - config_.initial) < 0)
    throw base::UserError("curriculum: the schedule moves away from its limit " + std::to_string(config_.limit));
}

bool ThresholdCurriculum::observe(double score) {
  if (at_limit()) return false;
  double s = score;
  if (config_.accumulate) s = accumulated_ += score;
  if (!(s > config_.threshold)) return false;
  const double next = config_.factor * value_ + config_.increment;
  const bool rising = config_.limit > config_.initial;
  value_ = rising ? std::min(next, config_.limit) : std::max(next, config_.limit);
  accumulated_ = 0.0;
  ++level_;
  return true;
}

base::Json ThresholdCurriculum::state() const { return {{"value", value_}, {"accumulated", accumulated_}, {"level", level_}}; }

void ThresholdCurriculum::load_state(const base::Json& state) {
  value_ = state_field<double>(state, "value", "curriculum");
  accumulated_ = state_field<double>(state, "accumulated", "curriculum");
  level_ = state_field<int>(state, "level", "curriculum");
}

StepBudget::Config StepBudget::Config::from_json(const base::Json& json, const std::string& where) {
  return read_config<Config>(json, where, [](ConfigReader& r, Config& c) {
    c.factor = r.number("factor", c.factor, {.min = 0.0, .exclusive_min = true});
    c.min_steps = r.integer("min_steps", c.min_steps, {.min = 0});
    c.max_steps = r.integer("max_steps", c.max_steps, {.min = 1});
    if (c.min_steps > c.max_steps) r.fail("min_steps", "is above max_steps " + std::to_string(c.max_steps));
  });
}

void StepBudget::on_advance(std::int64_t steps) {
  last_level_steps_ = steps - level_start_;
  level_start_ = steps;
}

std::int64_t StepBudget::budget() const {
  if (last_level_steps_ < 0) return config_.max_steps;
  const auto m = static_cast<std::int64_t>(std::llround(config_.factor * static_cast<double>(last_level_steps_)));
  return std::clamp(m, config_.min_steps, config_.max_steps);
}

base::Json StepBudget::state() const { return {{"level_start", level_start_}, {"last_level_steps", last_level_steps_}}; }

void StepBudget::load_state(const base::Json& state) {
  level_start_ = state_field<std::int64_t>(state, "level_start", "step budget");
  last_level_steps_ = state_field<std::int64_t>(state, "last_level_steps", "step budget");
}

UnlockCurriculum::Config UnlockCurriculum::Config::from_json(const base::Json& json, const std::string& where) {
  return read_config<Config>(json, where, [](ConfigReader& r, Config& c) {
    r.field("levels", c.levels);
    if (c.levels.empty()) r.fail("levels", "needs at least one level");
    c.successes_to_unlock = r.integer("successes_to_unlock", c.successes_to_unlock, {.min = 1});
  });
}

UnlockCurriculum::UnlockCurriculum(Config config) : config_(std::move(config)) {
  if (config_.levels.empty()) throw base::UserError("unlock curriculum: needs at least one level");
}

bool UnlockCurriculum::record(int level, bool success) {
  if (!success || level != unlocked_ - 1 || unlocked_ == static_cast<int>(config_.levels.size())) return false;
  if (++successes_ < config_.successes_to_unlock) return false;
  ++unlocked_;
  successes_ = 0;
  return true;
}

bool UnlockCurriculum::open_next() {
  if (unlocked_ == static_cast<int>(config_.levels.size())) return false;
  ++unlocked_;
  successes_ = 0;
  return true;
}

base::Json UnlockCurriculum::state() const { return {{"unlocked", unlocked_}, {"successes", successes_}}; }

void UnlockCurriculum::load_state(const base::Json& state) {
  const int unlocked = state_field<int>(state, "unlocked", "unlock curriculum");
  if (unlocked < 1 || unlocked > static_cast<int>(config_.levels.size()))
    throw base::UserError("unlock curriculum state: unlocked: " + std::to_string(unlocked) + " is not in [1, " +
                          std::to_string(config_.levels.size()) + "]");
  unlocked_ = unlocked;
  successes_ = state_field<int>(state, "successes", "unlock curriculum");
}

}  // namespace podium::character
