// The pool task plugin: a trial looks its result up in a recorded pool (pool_table.h) instead of
// running, so `podium` runs any search over real recorded trials in seconds. Parameters read as
// the nearest recorded take-off; its recorded success, feature and bar are the trial's result; a
// recorded trial that failed outright fails this one too.
#include <cmath>

#include "podium/base/config.h"
#include "podium/base/error.h"
#include "podium/plugins/export.h"
#include "pool_table.h"

namespace podium::tasks::pool {

using base::Json;

namespace {
struct TaskConfig {
  std::string table;
  std::string feature_set = "first";
};

TaskConfig read_config(base::ConfigReader& r) {
  TaskConfig c;
  c.table = r.file("table", "", "the pool's table (export_pool.py; README.md); required to run");
  c.feature_set = r.choice("feature_set", c.feature_set, {"first", "orientation"},
                           "the features a search sees: the table's first set, or its second (a jump's 3-D bar-frame "
                           "rotation; only the rows that recorded it)");
  return c;
}

PoolTable load_table(const TaskConfig& c) {
  const PoolTable t = PoolTable::load(c.table);
  return c.feature_set == "orientation" ? t.by_orientation() : t;
}

TaskConfig parse_config(const Json& config) { return base::ConfigReader::parse(config, "pool config", read_config); }
}  // namespace

class PoolTask final : public plugins::Task {
 public:
  Json describe(const Json& config) const override {
    const TaskConfig c = parse_config(config);
    const Json accepted = base::ConfigReader::describe([](base::ConfigReader& r) { read_config(r); });
    Json d = {{"params", Json::array()},
              {"features", Json::array()},
              {"objectives", {"bar_m"}},
              {"metrics", Json::array()},
              {"success", {{"info", "/success"}}},  // the recorded trial's success (a jump: it cleared its bar)
              {"presets", {{"smoke", Json::object()}}},
              {"config", accepted},
              {"config_defaults", base::ConfigReader::defaults(accepted)}};
    if (!c.table.empty()) {
      const PoolTable t = load_table(c);
      d["params"] = t.params_json;
      d["features"] = t.features_json;
      d["strategy_threshold"] = t.strategy_threshold;
    }
    return d;
  }

  plugins::RunResult run(const plugins::RunRequest& request, plugins::Sink& sink) override {
    const TaskConfig c = parse_config(request.config);
    if (c.table.empty()) throw base::UserError("pool: config.table is required (the pool's table file)");
    const PoolTable t = load_table(c);
    std::vector<double> x;
    for (const auto& p : t.box) {
      if (!request.params.contains(p.name) || !request.params[p.name].is_number())
        throw base::UserError("pool: params." + p.name + " is missing or not a number (got " + request.params.dump() + ")");
      x.push_back(request.params[p.name].get<double>());
    }
    const std::size_t i = t.nearest(x);
    const PoolRow& row = t.rows[i];
    if (!row.finished)
      throw std::runtime_error("pool: the nearest recorded take-off (row " + std::to_string(i) + ", trial " +
                               std::to_string(row.trial) + ") failed when it was recorded");
    sink.progress(1.0);
    plugins::RunResult result;
    result.objectives = {row.bar_m};
    result.features = row.features;
    // evaluated_params: the recorded row's take-off, where the result was measured (search.h).
    result.info = {{"success", row.success},
                   {"row", i},
                   {"recorded_trial", row.trial},
                   {"evaluated_params", row.params},
                   {"bar_m", row.bar_m}};
    Json summary = {{"recorded trial", row.trial}, {"success", row.success}, {"bar m", row.bar_m}};
    if (!row.technique.empty()) {
      result.info["nearest_technique"] = {{"name", row.technique}};
      summary["nearest captured technique"] = row.technique;
    }
    result.info["summary"] = summary;
    return result;
  }
};

}  // namespace podium::tasks::pool

PODIUM_EXPORT_TASK(podium::tasks::pool::PoolTask, "pool")
