#include "podium/base/config.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

namespace podium::base {

namespace {

const Json& empty_object() {
  static const Json empty = Json::object();
  return empty;
}

// A value as errors show it: its JSON, cut short so an error stays one readable line.
std::string shown(const Json& value) {
  constexpr std::size_t kMax = 80;
  std::string text = value.dump();
  if (text.size() > kMax) text = text.substr(0, kMax - 3) + "...";
  return text;
}

std::string number_text(double v) {
  std::ostringstream out;
  out.precision(15);
  out << v;
  return out.str();
}

std::string joined(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& item : items) out += (out.empty() ? "" : ", ") + item;
  return out;
}

constexpr auto kIntMin = std::numeric_limits<std::int64_t>::min();
constexpr auto kIntMax = std::numeric_limits<std::int64_t>::max();

// "in [1, 64]", ">= 0", "<= 9", or "" for no bound (the rule's wording in errors and lists).
std::string bound_text(bool has_min, const std::string& min, bool exclusive, bool has_max, const std::string& max) {
  if (has_min && has_max) return std::string("in ") + (exclusive ? "(" : "[") + min + ", " + max + "]";
  if (has_min) return (exclusive ? "> " : ">= ") + min;
  if (has_max) return "<= " + max;
  return "";
}
std::string bound_text(IntInterval r) {
  return bound_text(r.min != kIntMin, std::to_string(r.min), false, r.max != kIntMax, std::to_string(r.max));
}
std::string bound_text(Interval r) {
  return bound_text(std::isfinite(r.min), number_text(r.min), r.exclusive_min, std::isfinite(r.max), number_text(r.max));
}

void add_bounds(Json& info, IntInterval r) {
  if (r.min != kIntMin) info["min"] = r.min;
  if (r.max != kIntMax) info["max"] = r.max;
}
void add_bounds(Json& info, Interval r) {
  if (std::isfinite(r.min)) info["min"] = r.min;
  if (std::isfinite(r.max)) info["max"] = r.max;
  if (r.exclusive_min) info["exclusive_min"] = true;
}

// The problem with `v` as an integer in `range`, or "" if none.
std::string integer_problem(const Json& v, IntInterval range) {
  if (!v.is_number_integer()) return shown(v) + " is not an integer";
  // Above int64: out of every range, which then names its upper end even when unbounded.
  const bool too_big = v.is_number_unsigned() && v.get<std::uint64_t>() > static_cast<std::uint64_t>(kIntMax);
  if (too_big)
    return shown(v) + " is not " +
           bound_text(range.min != kIntMin, std::to_string(range.min), false, true, std::to_string(range.max));
  if (v.get<std::int64_t>() < range.min || v.get<std::int64_t>() > range.max) return shown(v) + " is not " + bound_text(range);
  return "";
}

std::string number_problem(const Json& v, Interval range) {
  if (!v.is_number() || !std::isfinite(v.get<double>())) return shown(v) + " is not a number";
  const double x = v.get<double>();
  if (x < range.min || (range.exclusive_min && x == range.min) || x > range.max) return shown(v) + " is not " + bound_text(range);
  return "";
}

}  // namespace

ConfigError::ConfigError(const std::string& source, const std::string& path, const std::string& problem)
    : UserError((source.empty() ? "" : source + ": ") + (path.empty() ? "" : path + ": ") + problem),
      path_(path),
      problem_(problem) {}

struct ConfigReader::Node {
  struct Entry {
    Json info;
    std::shared_ptr<Node> keys;  // an object's keys, or an array element's
  };
  std::vector<Entry> entries;

  Json description() const {
    Json out = Json::array();
    for (const auto& entry : entries) {
      Json info = entry.info;
      if (entry.keys) (info["type"] == "array" ? info["items"] : info)["keys"] = entry.keys->description();
      out.push_back(std::move(info));
    }
    return out;
  }
};

ConfigReader::ConfigReader(const Json& config, std::string path, std::string source)
    : ConfigReader(&config, std::move(path), std::move(source), std::make_shared<Node>(), false) {}

ConfigReader::ConfigReader() : ConfigReader(&empty_object(), "", "", std::make_shared<Node>(), true) {}

ConfigReader::ConfigReader(const Json* config, std::string path, std::string source, std::shared_ptr<Node> node, bool describing)
    : config_(config), path_(std::move(path)), source_(std::move(source)), node_(std::move(node)), describing_(describing) {
  if (!config_->is_object()) fail_at(path_, shown(*config_) + " is not an object");
}

std::string ConfigReader::path_of(const std::string& key) const { return json_path_join(path_, key); }

void ConfigReader::fail_at(const std::string& path, const std::string& problem) const {
  throw ConfigError(source_, path, problem);
}

void ConfigReader::fail(const std::string& key, const std::string& rule) const {
  fail_at(path_of(key), (!describing_ && config_->contains(key) ? shown(config_->at(key)) + " " : "") + rule);
}

void ConfigReader::fail(const std::string& key, std::size_t index, const std::string& rule) const {
  const Json* array = !describing_ && config_->contains(key) ? &config_->at(key) : nullptr;
  const bool shows = array && array->is_array() && index < array->size();
  fail_at(json_path_index(path_of(key), index), (shows ? shown((*array)[index]) + " " : "") + rule);
}

bool ConfigReader::has(const std::string& key) const { return !describing_ && config_->contains(key); }

const Json* ConfigReader::take(const std::string& key, bool is_required, const Json& info, const std::string& doc,
                               std::shared_ptr<Node> child) {
  read_.insert(key);
  auto& entries = node_->entries;
  if (std::none_of(entries.begin(), entries.end(), [&](const Node::Entry& e) { return e.info.at("key") == key; })) {
    Json entry = {{"key", key}};
    entry.update(info);
    if (is_required) {
      entry.erase("default");
      entry["required"] = true;
    }
    if (!doc.empty()) entry["doc"] = doc;
    entries.push_back({std::move(entry), std::move(child)});
  }
  if (describing_) return nullptr;
  if (config_->contains(key)) return &config_->at(key);
  if (is_required) fail_at(path_of(key), "missing (required)");
  return nullptr;
}

bool ConfigReader::boolean(const std::string& key, bool fallback, const std::string& doc) {
  const Json* v = take(key, false, {{"type", "boolean"}, {"default", fallback}}, doc);
  if (!v) return fallback;
  if (!v->is_boolean()) fail_at(path_of(key), shown(*v) + " is not a boolean (true or false)");
  return v->get<bool>();
}

std::int64_t ConfigReader::read_integer(const std::string& key, std::int64_t fallback, bool is_required, IntInterval range,
                                        const std::string& doc) {
  Json info = {{"type", "integer"}, {"default", fallback}};
  add_bounds(info, range);
  const Json* v = take(key, is_required, info, doc);
  if (!v) return fallback;
  if (const auto problem = integer_problem(*v, range); !problem.empty()) fail_at(path_of(key), problem);
  return v->get<std::int64_t>();
}

double ConfigReader::read_number(const std::string& key, double fallback, bool is_required, Interval range,
                                 const std::string& doc) {
  Json info = {{"type", "number"}, {"default", fallback}};
  add_bounds(info, range);
  const Json* v = take(key, is_required, info, doc);
  if (!v) return fallback;
  if (const auto problem = number_problem(*v, range); !problem.empty()) fail_at(path_of(key), problem);
  return v->get<double>();
}

double ConfigReader::number(const std::string& key, double fallback, Interval range, const std::string& doc) {
  return read_number(key, fallback, false, range, doc);
}

double ConfigReader::number(const std::string& key, Required, Interval range, const std::string& doc) {
  return read_number(key, std::isfinite(range.min) ? range.min : 0.0, true, range, doc);
}

std::string ConfigReader::string(const std::string& key, const std::string& fallback, const std::string& doc) {
  const Json* v = take(key, false, {{"type", "string"}, {"default", fallback}}, doc);
  if (!v) return fallback;
  if (!v->is_string()) fail_at(path_of(key), shown(*v) + " is not a string");
  return v->get<std::string>();
}

std::string ConfigReader::string(const std::string& key, Required, const std::string& doc) {
  const Json* v = take(key, true, {{"type", "string"}}, doc);
  if (!v) return "";
  if (!v->is_string()) fail_at(path_of(key), shown(*v) + " is not a string");
  if (v->get<std::string>().empty()) fail_at(path_of(key), "\"\" must not be empty");
  return v->get<std::string>();
}

std::string ConfigReader::file(const std::string& key, const std::string& fallback, const std::string& doc) {
  const Json* v = take(key, false, {{"type", "string"}, {"format", "file"}, {"default", fallback}}, doc);
  if (!v) return fallback;
  if (!v->is_string()) fail_at(path_of(key), shown(*v) + " is not a string (a file path)");
  return v->get<std::string>();
}

std::string ConfigReader::existing_file(const std::string& key, const std::string& fallback, const std::string& doc) {
  std::string f = file(key, fallback, doc);
  if (!f.empty() && !std::filesystem::is_regular_file(f)) fail(key, "is not a file");
  return f;
}

std::string ConfigReader::path(const std::string& key, const std::string& fallback, const std::string& doc) {
  const Json* v = take(key, false, {{"type", "string"}, {"format", "path"}, {"default", fallback}}, doc);
  if (!v) return fallback;
  if (!v->is_string()) fail_at(path_of(key), shown(*v) + " is not a string (a file or folder path)");
  return v->get<std::string>();
}

std::string ConfigReader::file(const std::string& key, Required, const std::string& doc) {
  const Json* v = take(key, true, {{"type", "string"}, {"format", "file"}}, doc);
  if (!v) return "";
  if (!v->is_string()) fail_at(path_of(key), shown(*v) + " is not a string (a file path)");
  if (v->get<std::string>().empty()) fail_at(path_of(key), "\"\" must not be empty");
  return v->get<std::string>();
}

std::string ConfigReader::read_choice(const std::string& key, const std::string& fallback, bool is_required,
                                      const std::vector<std::string>& allowed, const std::string& doc) {
  const Json* v = take(key, is_required, {{"type", "string"}, {"default", fallback}, {"choices", allowed}}, doc);
  if (!v) return fallback;
  if (v->is_string() && std::find(allowed.begin(), allowed.end(), v->get<std::string>()) != allowed.end())
    return v->get<std::string>();
  fail_at(path_of(key), shown(*v) + " is not one of " + joined(allowed));
}

std::string ConfigReader::choice(const std::string& key, const std::string& fallback, const std::vector<std::string>& allowed,
                                 const std::string& doc) {
  return read_choice(key, fallback, false, allowed, doc);
}

std::string ConfigReader::choice(const std::string& key, Required, const std::vector<std::string>& allowed,
                                 const std::string& doc) {
  return read_choice(key, allowed.empty() ? "" : allowed.front(), true, allowed, doc);
}

std::vector<std::int64_t> ConfigReader::read_integers(const std::string& key, const std::vector<std::int64_t>& fallback,
                                                      IntInterval range, const std::string& doc) {
  Json items = {{"type", "integer"}};
  add_bounds(items, range);
  const Json* v = take(key, false, {{"type", "array"}, {"default", fallback}, {"items", items}}, doc);
  if (!v) return fallback;
  const std::string rule = bound_text(range);
  if (!v->is_array()) fail_at(path_of(key), shown(*v) + " is not an array of integers" + (rule.empty() ? "" : " " + rule));
  std::vector<std::int64_t> out;
  for (std::size_t i = 0; i < v->size(); ++i) {
    if (const auto problem = integer_problem((*v)[i], range); !problem.empty())
      fail_at(json_path_index(path_of(key), i), problem);
    out.push_back((*v)[i].get<std::int64_t>());
  }
  return out;
}

std::vector<double> ConfigReader::numbers(const std::string& key, const std::vector<double>& fallback, Interval range,
                                          const std::string& doc) {
  Json items = {{"type", "number"}};
  add_bounds(items, range);
  const Json* v = take(key, false, {{"type", "array"}, {"default", fallback}, {"items", items}}, doc);
  if (!v) return fallback;
  const std::string rule = bound_text(range);
  if (!v->is_array()) fail_at(path_of(key), shown(*v) + " is not an array of numbers" + (rule.empty() ? "" : " " + rule));
  std::vector<double> out;
  for (std::size_t i = 0; i < v->size(); ++i) {
    if (const auto problem = number_problem((*v)[i], range); !problem.empty()) fail_at(json_path_index(path_of(key), i), problem);
    out.push_back((*v)[i].get<double>());
  }
  return out;
}

std::vector<std::string> ConfigReader::strings(const std::string& key, const std::vector<std::string>& fallback,
                                               const std::string& doc) {
  const Json* v = take(key, false, {{"type", "array"}, {"default", fallback}, {"items", {{"type", "string"}}}}, doc);
  if (!v) return fallback;
  if (!v->is_array()) fail_at(path_of(key), shown(*v) + " is not an array of strings");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < v->size(); ++i) {
    if (!(*v)[i].is_string()) fail_at(json_path_index(path_of(key), i), shown((*v)[i]) + " is not a string");
    out.push_back((*v)[i].get<std::string>());
  }
  return out;
}

Json ConfigReader::raw_object(const std::string& key, const std::string& doc) {
  const Json* v = take(key, false, {{"type", "object"}, {"default", Json::object()}}, doc);
  if (!v) return Json::object();
  if (!v->is_object()) fail_at(path_of(key), shown(*v) + " is not an object");
  return *v;
}

Json ConfigReader::raw(const std::string& key, Required, const std::string& doc) {
  const Json* v = take(key, true, {{"type", "any"}}, doc);
  return v ? *v : Json();
}

ConfigReader ConfigReader::enter_object(const std::string& key, bool is_required, const std::string& doc) {
  auto keys = std::make_shared<Node>();
  const Json* v = take(key, is_required, {{"type", "object"}}, doc, keys);
  return ConfigReader(v ? v : &empty_object(), path_of(key), source_, keys, describing_);
}

std::vector<ConfigReader> ConfigReader::enter_array(const std::string& key, const std::string& doc) {
  auto keys = std::make_shared<Node>();
  const Json* v = take(key, false, {{"type", "array"}, {"default", Json::array()}, {"items", {{"type", "object"}}}}, doc, keys);
  if (describing_) return {ConfigReader(&empty_object(), path_of(key) + "[]", source_, keys, true)};
  if (!v) return {};
  if (!v->is_array()) fail_at(path_of(key), shown(*v) + " is not an array of objects");
  // The first element records the element's keys; the others must not list them again.
  std::vector<ConfigReader> children;
  for (std::size_t i = 0; i < v->size(); ++i)
    children.push_back(
        ConfigReader(&(*v)[i], json_path_index(path_of(key), i), source_, i == 0 ? keys : std::make_shared<Node>(), false));
  return children;
}

void ConfigReader::finish() const {
  if (describing_) return;
  for (const auto& [key, value] : config_->items())
    if (!read_.count(key))
      fail_at(path_of(key),
              "unknown key (known: " + (read_.empty() ? std::string("none") : joined({read_.begin(), read_.end()})) + ")");
}

Json ConfigReader::description() const { return node_->description(); }

Json ConfigReader::defaults(const Json& description) {
  Json out = Json::object();
  for (const auto& entry : description) {
    if (entry.contains("default")) out[entry["key"].get<std::string>()] = entry["default"];
    else if (entry["type"] == "object" && entry.contains("keys") && !entry.value("required", false))
      out[entry["key"].get<std::string>()] = defaults(entry["keys"]);
  }
  return out;
}

}  // namespace podium::base
