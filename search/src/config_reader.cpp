#include "config_reader.h"

#include <cmath>

#include "podium/base/error.h"

namespace podium::search {

using base::Json;
using base::UserError;

ConfigReader::ConfigReader(const Json& config, std::string path) : config_(config), path_(std::move(path)) {
  if (!config_.is_object()) throw UserError(path_ + ": expected an object, got " + config_.dump());
}

const Json* ConfigReader::raw(const std::string& key) {
  used_.insert(key);
  return config_.contains(key) ? &config_.at(key) : nullptr;
}

double ConfigReader::number(const std::string& key, double fallback, double min, double max) {
  const Json* j = raw(key);
  if (!j) return fallback;
  if (!j->is_number()) throw UserError(path(key) + ": " + j->dump() + " is not a number");
  const double v = j->get<double>();
  if (!std::isfinite(v) || v < min || v > max)
    throw UserError(path(key) + ": " + j->dump() + " is not in [" + Json(min).dump() + ", " + Json(max).dump() + "]");
  return v;
}

int ConfigReader::integer(const std::string& key, int fallback, int min, int max) {
  const Json* j = raw(key);
  if (!j) return fallback;
  if (!j->is_number_integer()) throw UserError(path(key) + ": " + j->dump() + " is not an integer");
  const auto v = j->get<long long>();
  if (v < min || v > max)
    throw UserError(path(key) + ": " + j->dump() + " is not in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
  return static_cast<int>(v);
}

std::string ConfigReader::choice(const std::string& key, const std::string& fallback,
                                 const std::vector<std::string>& allowed) {
  const Json* j = raw(key);
  if (!j) return fallback;
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
  if (j->is_string())
    for (const auto& a : allowed)
      if (j->get<std::string>() == a) return a;
  throw UserError(path(key) + ": " + j->dump() + " is not one of " + list);
}

void ConfigReader::finish() const {
  for (const auto& [key, value] : config_.items())
    if (!used_.count(key)) {
      std::string known;
      for (const auto& k : used_) known += (known.empty() ? "" : ", ") + k;
      throw UserError(path(key) + ": unknown option (known: " + (known.empty() ? "none" : known) + ")");
    }
}

}  // namespace podium::search
