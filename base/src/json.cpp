#include "podium/base/json.h"

#include <fstream>
#include <sstream>
#include <unistd.h>

#include "podium/base/error.h"

namespace podium::base {

Json read_json_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw UserError(path.string() + ": cannot open file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  try {
    return Json::parse(buffer.str());
  } catch (const Json::parse_error& e) {
    // nlohmann reports a byte offset; turn it into line and column for people.
    const std::string text = buffer.str();
    std::size_t line = 1, column = 1;
    for (std::size_t i = 0; i + 1 < e.byte && i < text.size(); ++i) {
      if (text[i] == '\n') { ++line; column = 1; } else { ++column; }
    }
    std::string what = e.what();
    const auto colon = what.rfind(": ");
    throw UserError(path.string() + ": invalid JSON at line " + std::to_string(line) + " column " +
                    std::to_string(column) + ": " + (colon == std::string::npos ? what : what.substr(colon + 2)));
  }
}

void write_json_file_atomic(const std::filesystem::path& path, const Json& value) {
  const auto tmp = path.string() + ".tmp." + std::to_string(::getpid());
  {
    std::ofstream out(tmp);
    if (!out) throw RuntimeError(tmp + ": cannot write file");
    out << value.dump() << '\n';
    if (!out.flush()) throw RuntimeError(tmp + ": write failed");
  }
  std::filesystem::rename(tmp, path);
}

std::string json_path_join(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

std::string json_path_index(const std::string& parent, std::size_t index) {
  return parent + "[" + std::to_string(index) + "]";
}

}  // namespace podium::base
