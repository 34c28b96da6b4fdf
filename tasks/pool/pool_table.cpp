#include "pool_table.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "podium/base/error.h"

namespace podium::tasks::pool {

using base::Json;
using base::UserError;

namespace {
const Json& field(const Json& j, const std::string& key, const std::string& path) {
  if (!j.is_object() || !j.contains(key)) throw UserError(path + "." + key + ": missing");
  return j[key];
}

std::vector<double> numbers(const Json& j, std::size_t size, const std::string& path) {
  if (!j.is_array() || j.size() != size)
    throw UserError(path + ": expected " + std::to_string(size) + " numbers, got " + j.dump());
  std::vector<double> out;
  for (const auto& v : j) {
    if (!v.is_number() || !std::isfinite(v.get<double>())) throw UserError(path + ": " + v.dump() + " is not a finite number");
    out.push_back(v.get<double>());
  }
  return out;
}

// [{"name", "low", "high", ...}, ...] (other keys pass through in the JSON): names and ranges.
std::vector<Range> ranges(const Json& j, const std::string& path, bool need_params) {
  if (!j.is_array() || (need_params && j.empty())) throw UserError(path + ": expected a non-empty array, got " + j.dump());
  std::vector<Range> out;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const std::string at = base::json_path_index(path, i);
    const Json& name = field(j[i], "name", at);
    const Json& low = field(j[i], "low", at);
    const Json& high = field(j[i], "high", at);
    if (!name.is_string() || name.get<std::string>().empty()) throw UserError(at + ".name: " + name.dump() + " is not a name");
    if (!low.is_number() || !high.is_number() || !(low.get<double>() < high.get<double>()))
      throw UserError(at + ": [low, high] = [" + low.dump() + ", " + high.dump() + "] is not a range of numbers with low < high");
    out.push_back({name.get<std::string>(), low.get<double>(), high.get<double>()});
  }
  return out;
}

PoolRow parse_row(const Json& r, std::size_t dim, std::size_t nf, std::size_t n_orientation, const std::string& path) {
  PoolRow row;
  const Json& trial = field(r, "trial", path);
  if (!trial.is_number_integer()) throw UserError(path + ".trial: " + trial.dump() + " is not an integer");
  row.trial = trial.get<std::int64_t>();
  row.params = numbers(field(r, "params", path), dim, path + ".params");
  const Json& finished = r.value("finished", Json(true));
  const Json& success = field(r, "success", path);
  if (!finished.is_boolean()) throw UserError(path + ".finished: " + finished.dump() + " is not true or false");
  if (!success.is_boolean()) throw UserError(path + ".success: " + success.dump() + " is not true or false");
  row.finished = finished.get<bool>();
  row.success = row.finished && success.get<bool>();
  if (row.finished) row.features = numbers(field(r, "features", path), nf, path + ".features");
  const Json& bar = r.value("bar_m", Json(0.0));
  if (!bar.is_number()) throw UserError(path + ".bar_m: " + bar.dump() + " is not a number");
  row.bar_m = bar.get<double>();
  const Json& technique = r.value("technique", Json(""));
  row.technique = technique.is_string() ? technique.get<std::string>() : "";
  const Json& orientation = r.value("orientation", Json(nullptr));
  if (n_orientation > 0 && row.finished && !orientation.is_null())
    row.orientation = numbers(orientation, n_orientation, path + ".orientation");
  return row;
}
}  // namespace

PoolTable PoolTable::load(const std::filesystem::path& file) { return parse(base::read_json_file(file), file.string()); }

PoolTable PoolTable::parse(const Json& j, const std::string& origin) {
  PoolTable t;
  t.params_json = field(j, "params", origin);
  t.features_json = field(j, "features", origin);
  t.box = ranges(t.params_json, origin + ": params", true);
  t.features = ranges(t.features_json, origin + ": features", false);
  const Json& threshold = field(j, "strategy_threshold", origin);
  if (!threshold.is_number() || !(threshold.get<double>() > 0))
    throw UserError(origin + ": strategy_threshold: " + threshold.dump() + " is not a number > 0");
  t.strategy_threshold = threshold.get<double>();
  t.source = j.value("source", Json::object());
  t.orientation_json = j.value("orientation", Json(nullptr));
  if (!t.orientation_json.is_null()) {
    const std::string at = origin + ": orientation";
    t.orientation_features = ranges(field(t.orientation_json, "features", at), at + ".features", true);
    const Json& tau = field(t.orientation_json, "strategy_threshold", at);
    if (!tau.is_number() || !(tau.get<double>() > 0))
      throw UserError(at + ".strategy_threshold: " + tau.dump() + " is not a number > 0");
    t.orientation_threshold = tau.get<double>();
  }
  const Json& rows = field(j, "rows", origin);
  if (!rows.is_array() || rows.empty()) throw UserError(origin + ": rows: expected a non-empty array");
  for (std::size_t i = 0; i < rows.size(); ++i)
    t.rows.push_back(parse_row(rows[i], t.box.size(), t.features.size(), t.orientation_features.size(),
                               origin + ": " + base::json_path_index("rows", i)));
  return t;
}

Json PoolTable::to_json() const {
  Json out = Json::array();
  for (const auto& r : rows) {
    Json row = {{"trial", r.trial}, {"params", r.params}, {"finished", r.finished}, {"success", r.success}, {"bar_m", r.bar_m}};
    row["features"] = r.finished ? Json(r.features) : Json(nullptr);
    if (!r.technique.empty()) row["technique"] = r.technique;
    if (!orientation_json.is_null()) row["orientation"] = r.orientation.empty() ? Json(nullptr) : Json(r.orientation);
    out.push_back(row);
  }
  Json table = {{"params", params_json},
                {"features", features_json},
                {"strategy_threshold", strategy_threshold},
                {"source", source},
                {"rows", out}};
  if (!orientation_json.is_null()) table["orientation"] = orientation_json;
  return table;
}

PoolTable PoolTable::by_orientation() const {
  if (orientation_json.is_null()) throw UserError("pool: the table has no second feature set (\"orientation\")");
  PoolTable t = *this;
  t.features_json = orientation_json.at("features");
  t.features = orientation_features;
  t.strategy_threshold = orientation_threshold;
  t.orientation_json = {
      {"info", "the first feature set"}, {"features", features_json}, {"strategy_threshold", strategy_threshold}};
  t.orientation_features = features;
  t.orientation_threshold = strategy_threshold;
  t.rows.clear();
  bool recorded = false;
  for (const PoolRow& r : rows) {
    if (r.finished && r.orientation.empty()) continue;  // a row that did not record the set
    PoolRow swapped = r;
    std::swap(swapped.features, swapped.orientation);
    recorded = recorded || r.finished;
    t.rows.push_back(std::move(swapped));
  }
  if (!recorded) throw UserError("pool: no row of the table recorded its second feature set");
  return t;
}

std::size_t PoolTable::nearest(const std::vector<double>& x) const {
  PODIUM_CHECK(x.size() == box.size(), "pool: parameters of the wrong dimension");
  std::size_t best = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    double d = 0.0;
    for (std::size_t k = 0; k < x.size(); ++k) {
      const double range = box[k].high - box[k].low;
      const double u = (x[k] - rows[i].params[k]) / range;
      d += u * u;
    }
    if (d < best_d) {
      best_d = d;
      best = i;
    }
  }
  return best;
}

void PoolTable::reachable(std::vector<double>& low, std::vector<double>& high, bool orientation) const {
  const std::size_t n = orientation ? orientation_features.size() : features.size();
  low.assign(n, std::numeric_limits<double>::infinity());
  high.assign(n, -std::numeric_limits<double>::infinity());
  for (const auto& r : rows) {
    const std::vector<double>& v = orientation ? r.orientation : r.features;
    if (!r.success || v.size() != n) continue;
    for (std::size_t j = 0; j < n; ++j) {
      low[j] = std::min(low[j], v[j]);
      high[j] = std::max(high[j], v[j]);
    }
  }
}

}  // namespace podium::tasks::pool
