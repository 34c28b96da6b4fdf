#include "podium/base/json.h"

#include <unistd.h>

#include <fstream>
#include <sstream>

#include "podium/base/error.h"

namespace podium::base {

namespace {

constexpr std::size_t kMaxJsonDepth = 100;  // json.h documents it

// "line L column C" of byte `offset` (0-based) of `text`.
std::string position_of(const std::string& text, std::size_t offset) {
  std::size_t line = 1, column = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return "line " + std::to_string(line) + " column " + std::to_string(column);
}

// The offset of the first bracket nested deeper than kMaxJsonDepth, or npos. Checked before
// parsing: nlohmann::json copies, dumps and destroys values recursively, so a 60,000-deep array
// would overflow the stack.
std::size_t too_deep_at(const std::string& text) {
  std::size_t depth = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth) return i;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    }
  }
  return std::string::npos;
}

}  // namespace

Json read_json_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw UserError(path.string() + ": cannot open file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  if (const auto at = too_deep_at(text); at != std::string::npos)
    throw UserError(path.string() + ": invalid JSON at " + position_of(text, at) + ": nested deeper than " +
                    std::to_string(kMaxJsonDepth) + " levels");
  try {
    return Json::parse(text);
  } catch (const Json::parse_error& e) {
    // nlohmann reports a byte offset (1-based); turn it into line and column for people.
    std::string what = e.what();
    const auto colon = what.rfind(": ");
    throw UserError(path.string() + ": invalid JSON at " + position_of(text, e.byte > 0 ? e.byte - 1 : 0) + ": " +
                    (colon == std::string::npos ? what : what.substr(colon + 2)));
  } catch (const Json::out_of_range& e) {
    // A number beyond double range (1e400): nlohmann reports no position, only the number.
    const std::string what = e.what();
    throw UserError(path.string() + ": invalid JSON: " + what.substr(what.find(']') + 2));
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

std::string json_path_index(const std::string& parent, std::size_t index) { return parent + "[" + std::to_string(index) + "]"; }

}  // namespace podium::base
