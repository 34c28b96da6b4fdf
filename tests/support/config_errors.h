#pragma once
// Where a config reader refuses a config: the tests of each task's config keys check the JSON path.
#include <string>

#include "podium/base/config.h"
#include "podium/base/error.h"

namespace podium::testing {

/// The JSON path of the error `read(ConfigReader&)` raises on the whole of `config`, or
/// "(accepted)" when it reads it all.
template <class Read>
std::string config_error_path(const base::Json& config, Read&& read) {
  try {
    base::ConfigReader::parse(config, "config", read);
  } catch (const base::ConfigError& e) {
    return e.path();
  }
  return "(accepted)";
}

}  // namespace podium::testing
