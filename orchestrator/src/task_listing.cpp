#include "task_listing.h"

#include <iomanip>
#include <map>
#include <sstream>

#include "podium/base/config.h"
#include "podium/base/error.h"
#include "podium/base/json.h"
#include "podium/plugins/loader.h"
#include "podium/store/summary.h"
#include "worker_process.h"

namespace podium::orchestrator {

namespace fs = std::filesystem;
using base::Json;

namespace {

Json described(const fs::path& worker_binary, const std::string& name, const fs::path& file, const Json& config) {
  Json task = {{"name", name}, {"file", file.string()}};
  try {
    task.update(describe_task_isolated(worker_binary, name, config));
  } catch (const base::ConfigError& e) {
    throw base::UserError(base::json_path_join("--config", e.path()) + ": " + e.problem());
  }
  if (!config.empty()) task["described_with"] = config;
  return task;
}

std::string number_text(const Json& v) {
  if (!v.is_number_float()) return v.dump();
  std::ostringstream out;
  out.precision(15);
  out << v.get<double>();
  return out.str();
}

// "one of a, b", "in [1, 64]", ">= 0", or "" (the rule of a key or of an array's elements).
std::string rule_text(const Json& key) {
  if (key.contains("choices")) {
    std::string out = "one of ";
    for (std::size_t i = 0; i < key["choices"].size(); ++i) out += (i ? ", " : "") + key["choices"][i].get<std::string>();
    return out;
  }
  const bool lo = key.contains("min"), hi = key.contains("max"), open = key.value("exclusive_min", false);
  if (lo && hi) return std::string("in ") + (open ? "(" : "[") + number_text(key["min"]) + ", " + number_text(key["max"]) + "]";
  if (lo) return (open ? "> " : ">= ") + number_text(key["min"]);
  if (hi) return "<= " + number_text(key["max"]);
  return "";
}

void format_keys(std::ostringstream& out, const Json& keys, const std::string& prefix) {
  for (const auto& key : keys) {
    const std::string name = prefix + key.at("key").get<std::string>();
    const std::string type = key.at("type").get<std::string>();
    const Json items = key.value("items", Json::object());
    const auto kind = [](const Json& k) {
      const std::string format = k.value("format", std::string());
      return format == "file" || format == "path" ? format : k.value("type", std::string("value"));
    };
    const std::string shown_type = type == "array" ? "array of " + kind(items) + "s" : kind(key);
    const std::string fallback = key.value("required", false) ? "required" : key.contains("default") ? key["default"].dump() : "";
    std::string rule = rule_text(type == "array" ? items : key);
    if (key.contains("doc")) rule += (rule.empty() ? "" : "; ") + key["doc"].get<std::string>();
    out << "    " << std::left << std::setw(22) << name << " " << std::setw(18) << shown_type << " " << std::setw(12) << fallback
        << " " << rule << "\n";
    if (key.contains("keys")) format_keys(out, key["keys"], name + ".");
    if (items.contains("keys")) format_keys(out, items["keys"], name + "[].");
  }
}

std::string range_list(const Json& entries) {
  std::string out;
  for (const auto& e : entries) {
    out += (out.empty() ? "" : ", ") + e.at("name").get<std::string>() + " [" + number_text(e.at("low")) + ", " +
           number_text(e.at("high")) + "]";
    if (e.contains("unit")) out += " " + e["unit"].get<std::string>();
    if (e.contains("metric")) out += " " + e["metric"].get<std::string>();
  }
  return out.empty() ? "none" : out;
}

}  // namespace

Json list_tasks(const fs::path& worker_binary, const std::string& name, bool with_test_plugins, const Json& config) {
  const auto plugins = plugins::installed_plugins();
  if (!name.empty()) {
    const auto it = plugins.find(name);
    return Json::array({described(worker_binary, name, it == plugins.end() ? fs::path() : it->second, config)});
  }
  if (!config.empty()) throw base::UserError("--config describes one task: name it (podium tasks NAME --config JSON)");
  Json tasks = Json::array();
  for (const auto& [task, file] : plugins) {
    if (!with_test_plugins && plugins::is_test_plugin(file)) continue;
    try {
      tasks.push_back(described(worker_binary, task, file, Json::object()));
    } catch (const base::UserError& e) {
      tasks.push_back({{"name", task}, {"file", file.string()}, {"error", e.what()}});
    }
  }
  return tasks;
}

std::string format_tasks(const Json& tasks) {
  std::ostringstream out;
  for (const auto& t : tasks) {
    out << t.at("name").get<std::string>() << "  (" << t.at("file").get<std::string>() << ")\n";
    if (t.contains("error")) {
      out << "  cannot be described: " << t["error"].get<std::string>() << "\n\n";
      continue;
    }
    const std::string at = t.contains("described_with") ? "config " + t["described_with"].dump() : "default config";
    out << "  params (" << at << "): " << range_list(t.value("params", Json::array())) << "\n";
    out << "  features: " << range_list(t.value("features", Json::array())) << "\n";
    std::string metrics;
    for (const auto& m : t.value("metrics", Json::array()))
      metrics += (metrics.empty() ? "" : ", ") + m.at("name").get<std::string>() +
                 (m.contains("description") ? " (" + m["description"].get<std::string>() + ")" : "");
    out << "  metrics: " << (metrics.empty() ? "none" : metrics) << "\n";
    std::string objectives;  // with unit and meaning (the default config's stage; a stage may name them otherwise)
    for (const auto& o : store::objective_entries(t))
      objectives += (objectives.empty() ? "" : ", ") + o.at("name").get<std::string>() +
                    (o.contains("description") ? " (" + (o.contains("unit") ? o["unit"].get<std::string>() + "; " : "") +
                                                     o["description"].get<std::string>() + ")"
                                               : "");
    out << "  objectives: " << (objectives.empty() ? "none" : objectives) << "\n";
    out << "  presets:\n";
    const Json presets = t.value("presets", Json::object());
    for (const auto& [preset, config] : presets.items()) out << "    " << preset << "  " << config.dump() << "\n";
    if (t.contains("config")) {
      out << "  config:\n";
      format_keys(out, t["config"], "");
    } else {
      out << "  config (defaults; the task does not describe its keys): " << t.value("config_defaults", Json::object()).dump()
          << "\n";
    }
    out << "\n";
  }
  return out.str();
}

}  // namespace podium::orchestrator
