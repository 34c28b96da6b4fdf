#pragma once
// Reads an algorithm's config object from the spec: typed fields with defaults and ranges, and an
// error for every key no field asked for (a typo must not silently fall back to a default).
#include <set>
#include <string>
#include <vector>

#include "podium/base/json.h"

namespace podium::search {

class ConfigReader {
 public:
  /// `path` names the config object in errors, e.g. "stages[0].search.config".
  ConfigReader(const base::Json& config, std::string path);
  int integer(const std::string& key, int fallback, int min, int max);
  double number(const std::string& key, double fallback, double min, double max);
  std::string choice(const std::string& key, const std::string& fallback, const std::vector<std::string>& allowed);
  /// The raw value, or null when absent (for fields with their own parser).
  const base::Json* raw(const std::string& key);
  /// Throws UserError naming the first key that no getter asked for.
  void finish() const;
  std::string path(const std::string& key) const { return path_ + "." + key; }

 private:
  const base::Json& config_;
  std::string path_;
  std::set<std::string> used_;
};

}  // namespace podium::search
