#include "pool_replay.h"

#include <cmath>
#include <set>

#include "podium/base/error.h"
#include "podium/base/rng.h"
#include "podium/search/search.h"

namespace podium::bench::pool {

SearchView::SearchView(const PoolTable& table, const std::string& origin)
    : space(search::Space::from_json(table.params_json, origin + ": params")),
      features(search::Feature::list_from_json(table.features_json, origin + ": features")) {
  if (!table.orientation_json.is_null())
    orientation = search::Feature::list_from_json(table.orientation_json.at("features"), origin + ": orientation.features");
}

search::Outcome outcome(const PoolTable& table, bool orientation) {
  return [&table, orientation](const std::vector<double>& x) -> std::optional<std::vector<double>> {
    const PoolRow& r = table.rows[table.nearest(x)];
    const std::vector<double>& v = orientation ? r.orientation : r.features;
    if (!r.success || v.empty()) return std::nullopt;
    return v;
  };
}

namespace {
constexpr std::uint64_t kRandomExpectedSalt = 0x9001e;

// Distinct successful strategies by the second feature set among the rows found so far (those
// that recorded it).
int orientation_count(const SearchView& view, const std::vector<const PoolRow*>& found, double threshold) {
  std::vector<std::vector<double>> vectors;
  for (const PoolRow* row : found)
    if (row->success && row->orientation.size() == view.orientation.size()) vectors.push_back(row->orientation);
  return search::count_strategies(view.orientation, vectors, threshold);
}

// One arm, one repetition: counts after each budget.
void run_once(const PoolTable& table, const SearchView& view, const ReplayOptions& o, const std::string& arm, int rep,
              ArmRuns& out) {
  search::SearchSetup setup;
  setup.space = view.space;
  setup.features = view.features;
  setup.strategy_threshold = table.strategy_threshold;
  setup.seed = o.first_seed + static_cast<std::uint64_t>(rep);
  setup.config = o.configs.count(arm) ? o.configs.at(arm) : base::Json::object();
  auto search = search::make_search(arm, setup, "arms." + arm);
  std::vector<std::vector<double>> found;
  std::vector<bool> success;
  int failures = 0;
  std::set<std::string> techniques;
  std::vector<const PoolRow*> rows;
  std::vector<int> s, sc, f, tq, so, soc;
  for (int b : o.budgets) {
    while (static_cast<int>(found.size()) < b) {
      const auto proposals = search->ask(1);
      if (proposals.empty()) throw base::UserError("pool replay: " + arm + " proposed nothing");
      const PoolRow& row = table.rows[table.nearest(proposals[0].x)];
      search::Observation obs{proposals[0].id, row.finished, {}, row.features, row.success};
      if (row.finished) obs.objectives = {row.bar_m};
      search->tell({obs});
      found.push_back(row.finished ? row.features : std::vector<double>(table.features.size(), 0.0));
      success.push_back(row.success);
      failures += row.success ? 0 : 1;
      rows.push_back(&row);
      if (row.success && !row.technique.empty()) techniques.insert(row.technique);
    }
    tq.push_back(static_cast<int>(techniques.size()));
    s.push_back(search::count_strategies(view.features, found, table.strategy_threshold, &success));
    sc.push_back(search::count_strategies(view.features, found, 2.0 * table.strategy_threshold, &success));
    f.push_back(failures);
    if (!view.orientation.empty()) {
      so.push_back(orientation_count(view, rows, table.orientation_threshold));
      soc.push_back(orientation_count(view, rows, 2.0 * table.orientation_threshold));
    }
  }
  out.strategies[static_cast<std::size_t>(rep)] = s;
  out.strategies_coarse[static_cast<std::size_t>(rep)] = sc;
  out.failures[static_cast<std::size_t>(rep)] = f;
  out.techniques[static_cast<std::size_t>(rep)] = tq;
  if (!view.orientation.empty()) {
    out.orientations[static_cast<std::size_t>(rep)] = so;
    out.orientations_coarse[static_cast<std::size_t>(rep)] = soc;
  }
}

// The second feature set's ceiling, occupancy and random expectation at `threshold`.
CountBaseline orientation_baseline(const PoolTable& table, const SearchView& view, const ReplayOptions& o, double threshold) {
  CountBaseline c;
  c.threshold = threshold;
  std::vector<const PoolRow*> all;
  for (const auto& row : table.rows) all.push_back(&row);
  c.occupied = orientation_count(view, all, threshold);
  if (c.occupied > 0) {
    std::vector<double> low, high;
    table.reachable(low, high, true);
    c.ceiling = search::strategy_ceiling(view.orientation, threshold, low, high);
  }
  const search::Outcome lookup = outcome(table, true);
  for (int b : o.budgets) {
    const std::uint64_t seed = base::derive_seed(o.first_seed, kRandomExpectedSalt, static_cast<std::uint64_t>(b));
    c.random_expected.push_back(
        search::expected_random_count(view.orientation, threshold, view.space, lookup, b, o.expected_draws, seed));
  }
  return c;
}
}  // namespace

ReplayResult replay(const PoolTable& table, const ReplayOptions& o) {
  PODIUM_CHECK(o.reps > 0 && !o.budgets.empty(), "pool replay: reps and budgets must be positive");
  ReplayResult r;
  const SearchView view(table, "pool table");
  for (const auto& arm : o.arms) {
    ArmRuns runs;
    runs.strategies.resize(static_cast<std::size_t>(o.reps));
    runs.strategies_coarse.resize(static_cast<std::size_t>(o.reps));
    runs.failures.resize(static_cast<std::size_t>(o.reps));
    runs.techniques.resize(static_cast<std::size_t>(o.reps));
    if (!view.orientation.empty()) {
      runs.orientations.resize(static_cast<std::size_t>(o.reps));
      runs.orientations_coarse.resize(static_cast<std::size_t>(o.reps));
    }
    for (int rep = 0; rep < o.reps; ++rep) run_once(table, view, o, arm, rep, runs);
    r.arms[arm] = std::move(runs);
  }
  const double tau = table.strategy_threshold;
  std::vector<double> low, high;
  table.reachable(low, high);
  std::vector<std::vector<double>> all;
  std::vector<bool> success;
  for (const auto& row : table.rows) {
    all.push_back(row.finished ? row.features : std::vector<double>(table.features.size(), 0.0));
    success.push_back(row.success);
  }
  r.occupied = search::count_strategies(view.features, all, tau, &success);
  r.occupied_coarse = search::count_strategies(view.features, all, 2.0 * tau, &success);
  if (r.occupied > 0) {
    r.ceiling = search::strategy_ceiling(view.features, tau, low, high);
    r.ceiling_coarse = search::strategy_ceiling(view.features, 2.0 * tau, low, high);
  }
  const auto lookup = outcome(table);
  for (int b : o.budgets) {
    const std::uint64_t seed = base::derive_seed(o.first_seed, kRandomExpectedSalt, static_cast<std::uint64_t>(b));
    r.random_expected.push_back(search::expected_random_count(view.features, tau, view.space, lookup, b, o.expected_draws, seed));
    r.random_expected_coarse.push_back(
        search::expected_random_count(view.features, 2.0 * tau, view.space, lookup, b, o.expected_draws, seed));
  }
  if (!view.orientation.empty())
    for (double scale : {1.0, 2.0})
      r.orientation.push_back(orientation_baseline(table, view, o, scale * table.orientation_threshold));
  return r;
}

MeanSd mean_sd(const std::vector<double>& v) {
  MeanSd m;
  if (v.empty()) return m;
  for (double x : v) m.mean += x;
  m.mean /= static_cast<double>(v.size());
  if (v.size() < 2) return m;
  double s = 0.0;
  for (double x : v) s += (x - m.mean) * (x - m.mean);
  m.sd = std::sqrt(s / static_cast<double>(v.size() - 1));
  return m;
}

}  // namespace podium::bench::pool
