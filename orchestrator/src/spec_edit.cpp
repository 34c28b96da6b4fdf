#include "spec_edit.h"

#include <algorithm>
#include <cctype>
#include <vector>

#include "podium/base/error.h"

namespace podium::orchestrator {

namespace {

using base::Json;

constexpr const char* kForm = "PATH=VALUE, e.g. seed=29 or stages[0].config.total_steps=4000000";

// Every refusal names the edit it refuses.
base::UserError bad_edit(const std::string& edit, const std::string& why) {
  return base::UserError("--set " + edit + ": " + why);
}

// One step of a path: an object member, or an array item when `index` ≥ 0.
struct Step {
  std::string member;
  long index = -1;
};

std::vector<Step> parse_path(const std::string& path, const std::string& edit) {
  const auto bad = [&](const std::string& why) { return bad_edit(edit, why); };
  std::vector<Step> steps;
  std::size_t i = 0;
  while (i < path.size()) {
    if (path[i] == '[') {
      const auto close = path.find(']', i);
      const std::string digits = path.substr(i + 1, close == std::string::npos ? std::string::npos : close - i - 1);
      if (close == std::string::npos || digits.empty() || digits.size() > 6 ||
          !std::all_of(digits.begin(), digits.end(), [](unsigned char c) { return std::isdigit(c); }))
        throw bad("\"" + path.substr(i) + "\" is not an array index like [0]");
      steps.push_back({"", std::stol(digits)});
      i = close + 1;
      if (i < path.size() && path[i] != '.' && path[i] != '[') throw bad("\"" + path.substr(i) + "\" after an index needs a '.'");
      if (i < path.size() && path[i] == '.') ++i;
      continue;
    }
    const auto end = path.find_first_of(".[", i);
    const std::string member = path.substr(i, end == std::string::npos ? std::string::npos : end - i);
    if (member.empty()) throw bad("the path has an empty key");
    steps.push_back({member, -1});
    i = end == std::string::npos ? path.size() : end;
    if (i < path.size() && path[i] == '.') {
      if (i + 1 == path.size()) throw bad("the path ends with '.'");
      ++i;
    }
  }
  if (steps.empty()) throw bad(std::string("no path before '=' (") + kForm + ")");
  return steps;
}

}  // namespace

void apply_spec_edit(Json& spec, const std::string& edit) {
  const auto equals = edit.find('=');
  if (equals == std::string::npos) throw bad_edit(edit, std::string("no '=' (") + kForm + ")");
  const std::string path = edit.substr(0, equals), text = edit.substr(equals + 1);
  const auto steps = parse_path(path, edit);
  Json value = Json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (value.is_discarded()) value = text;

  Json* at = &spec;
  std::string walked;  // the path so far, for errors
  const auto here = [&] { return walked.empty() ? std::string("the spec") : walked; };
  for (std::size_t k = 0; k < steps.size(); ++k) {
    const Step& s = steps[k];
    const bool last = k + 1 == steps.size();
    if (s.index >= 0) {
      if (!at->is_array()) throw bad_edit(edit, here() + " is not an array");
      if (static_cast<std::size_t>(s.index) >= at->size())
        throw bad_edit(edit, here() + " has " + std::to_string(at->size()) + " items, no [" + std::to_string(s.index) + "]");
      walked += "[" + std::to_string(s.index) + "]";
      at = &(*at)[static_cast<std::size_t>(s.index)];
    } else {
      if (!at->is_object()) throw bad_edit(edit, here() + " is not an object");
      walked += (walked.empty() ? "" : ".") + s.member;
      if (!at->contains(s.member) && !last) (*at)[s.member] = Json::object();
      at = &(*at)[s.member];
    }
    if (last) *at = value;
  }
}

}  // namespace podium::orchestrator
