#pragma once
// The front end, loaded into memory at startup. A request path is looked up in this map and
// nowhere else, so no request can name a file outside the front end (no path is ever joined).
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "encoded_body.h"

namespace podium::web_dashboard {

struct StaticFile {
  std::shared_ptr<const EncodedBody> body;  ///< compressed once, at startup
  std::string mime;
};

class StaticFiles {
 public:
  /// Loads every regular file under dir (keys: "index.html", "vendor/three.module.js", ...).
  explicit StaticFiles(const std::filesystem::path& dir);
  const StaticFile* find(const std::string& relative_path) const;

 private:
  std::map<std::string, StaticFile> files_;
};

}  // namespace podium::web_dashboard
