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

// Distinct successful strategies among `rows` by one counting's feature set (a row that did not
// record the set is left out).
int count(const SearchView& view, const Counting& c, const std::vector<const PoolRow*>& rows) {
  const auto& features = c.orientation ? view.orientation : view.features;
  std::vector<std::vector<double>> vectors;
  for (const PoolRow* row : rows) {
    const auto& v = c.orientation ? row->orientation : row->features;
    if (row->success && v.size() == features.size()) vectors.push_back(v);
  }
  return search::count_strategies(features, vectors, c.threshold);
}

// The countings, without their baselines: the first feature set at τ and 2τ, the second's too.
std::vector<Counting> countings(const PoolTable& table, const SearchView& view) {
  std::vector<Counting> out;
  for (bool orientation : {false, true}) {
    if (orientation && view.orientation.empty()) break;
    const double tau = orientation ? table.orientation_threshold : table.strategy_threshold;
    for (double scale : {1.0, 2.0}) out.push_back({orientation, scale * tau, 0, 0, {}});
  }
  return out;
}

// One arm, one repetition: counts after each budget.
void run_once(const PoolTable& table, const SearchView& view, const ReplayOptions& o, const std::vector<Counting>& countings,
              const std::string& arm, int rep, ArmRuns& out) {
  search::SearchSetup setup;
  setup.space = view.space;
  setup.features = view.features;
  setup.strategy_threshold = table.strategy_threshold;
  setup.seed = o.first_seed + static_cast<std::uint64_t>(rep);
  setup.config = o.configs.count(arm) ? o.configs.at(arm) : base::Json::object();
  auto search = search::make_search(arm, setup, "arms." + arm);
  int failures = 0;
  std::set<std::string> techniques;
  std::vector<const PoolRow*> rows;
  const auto r = static_cast<std::size_t>(rep);
  for (int b : o.budgets) {
    while (static_cast<int>(rows.size()) < b) {
      const auto proposals = search->ask(1);
      if (proposals.empty()) throw base::UserError("pool replay: " + arm + " proposed nothing");
      const PoolRow& row = table.rows[table.nearest(proposals[0].x)];
      search::Observation obs{proposals[0].id, row.finished, {}, row.features, row.success};
      if (row.finished) obs.objectives = {row.bar_m};
      obs.x = row.params;  // the search models the recorded take-off's outcome where it was recorded
      search->tell({obs});
      failures += row.success ? 0 : 1;
      rows.push_back(&row);
      if (row.success && !row.technique.empty()) techniques.insert(row.technique);
    }
    out.techniques[r].push_back(static_cast<int>(techniques.size()));
    out.failures[r].push_back(failures);
    for (std::size_t c = 0; c < countings.size(); ++c) out.counts[c][r].push_back(count(view, countings[c], rows));
  }
}

// A counting's ceiling, occupancy and random expectation over the whole pool.
void baseline(const PoolTable& table, const SearchView& view, const ReplayOptions& o, Counting& c) {
  std::vector<const PoolRow*> all;
  for (const auto& row : table.rows) all.push_back(&row);
  c.occupied = count(view, c, all);
  const auto& features = c.orientation ? view.orientation : view.features;
  if (c.occupied > 0) {
    std::vector<double> low, high;
    table.reachable(low, high, c.orientation);
    c.ceiling = search::strategy_ceiling(features, c.threshold, low, high);
  }
  const search::Outcome lookup = outcome(table, c.orientation);
  for (int b : o.budgets) {
    const std::uint64_t seed = base::derive_seed(o.first_seed, kRandomExpectedSalt, static_cast<std::uint64_t>(b));
    c.random_expected.push_back(
        search::expected_random_count(features, c.threshold, view.space, lookup, b, o.expected_draws, seed));
  }
}
}  // namespace

ReplayResult replay(const PoolTable& table, const ReplayOptions& o) {
  PODIUM_CHECK(o.reps > 0 && !o.budgets.empty(), "pool replay: reps and budgets must be positive");
  ReplayResult r;
  const SearchView view(table, "pool table");
  r.countings = countings(table, view);
  const auto reps = static_cast<std::size_t>(o.reps);
  for (const auto& arm : o.arms) {
    ArmRuns runs;
    runs.failures.resize(reps);
    runs.techniques.resize(reps);
    runs.counts.assign(r.countings.size(), std::vector<std::vector<int>>(reps));
    for (int rep = 0; rep < o.reps; ++rep) run_once(table, view, o, r.countings, arm, rep, runs);
    r.arms[arm] = std::move(runs);
  }
  for (auto& c : r.countings) baseline(table, view, o, c);
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
