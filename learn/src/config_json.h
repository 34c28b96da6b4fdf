#pragma once
// Reads a plain config struct from JSON field by field, starting from its defaults; errors name
// the config, the field, the value and the expected type; unknown fields are rejected.
#include <set>
#include <string>

#include "podium/base/error.h"
#include "podium/base/json.h"

namespace podium::learn::detail {

class ConfigReader {
 public:
  ConfigReader(std::string where, const base::Json& json) : where_(std::move(where)), json_(json) {
    if (!json_.is_object()) throw base::UserError(where_ + ": " + json_.dump() + " is not a JSON object");
  }
  template <class T>
  void read(const char* key, T& field) {
    seen_.insert(key);
    if (!json_.contains(key)) return;
    try {
      field = json_.at(key).get<T>();
    } catch (const base::Json::exception&) {
      throw base::UserError(where_ + ": " + key + ": " + json_.at(key).dump() + " has the wrong type (default " +
                            base::Json(field).dump() + ")");
    }
  }
  void finish() const {
    for (const auto& [key, value] : json_.items())
      if (!seen_.count(key)) throw base::UserError(where_ + ": unknown field \"" + key + "\"");
  }

 private:
  std::string where_;
  const base::Json& json_;
  std::set<std::string> seen_;
};

}  // namespace podium::learn::detail

/// Defines Config::to_json and Config::from_json (via ConfigReader, errors prefixed by `where`)
/// from an X-macro list of the config's fields, so every learner config reads and writes alike.
#define PODIUM_CONFIG_JSON(Config, FIELDS, where)      \
  base::Json Config::to_json() const {                  \
    base::Json j;                                       \
    FIELDS(PODIUM_CONFIG_WRITE_FIELD)                   \
    return j;                                           \
  }                                                     \
  Config Config::from_json(const base::Json& json) {    \
    Config c;                                           \
    detail::ConfigReader r(where, json);                \
    FIELDS(PODIUM_CONFIG_READ_FIELD)                    \
    r.finish();                                         \
    return c;                                           \
  }
#define PODIUM_CONFIG_WRITE_FIELD(f) j[#f] = f;
#define PODIUM_CONFIG_READ_FIELD(f) r.read(#f, c.f);
