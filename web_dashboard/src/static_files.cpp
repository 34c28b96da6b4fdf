#include "static_files.h"

#include <fstream>
#include <sstream>

#include "podium/base/error.h"

namespace podium::web_dashboard {

namespace fs = std::filesystem;

namespace {
std::string mime_of(const fs::path& p) {
  const std::string ext = p.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".json") return "application/json";
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".png") return "image/png";
  return "application/octet-stream";
}
}  // namespace

StaticFiles::StaticFiles(const fs::path& dir) {
  if (!fs::is_regular_file(dir / "index.html"))
    throw base::UserError("front end folder " + dir.string() +
                          ": no index.html (build the podium_web_front_end target, or pass --static DIR)");
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (!entry.is_regular_file()) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    files_[fs::relative(entry.path(), dir).generic_string()] = {EncodedBody::make(text.str()), mime_of(entry.path())};
  }
}

const StaticFile* StaticFiles::find(const std::string& relative_path) const {
  const auto it = files_.find(relative_path);
  return it == files_.end() ? nullptr : &it->second;
}

}  // namespace podium::web_dashboard
