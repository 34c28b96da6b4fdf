#pragma once
// Replays searches over a recorded pool (tasks/pool/pool_table.h): each arm (a search algorithm) runs
// `reps` times, one trial at a time, repetition r with the same search seed in every arm (paired
// by seed), and after each budget counts the distinct successful strategies it found
// (search/strategies.h, at the pool's strategy threshold τ and at 2τ) and its failures (trials
// that did not succeed). Beside them: the ceiling (the cells the pool's reachable feature range
// meets) and random search's expected count (Monte Carlo over uniform draws of the box). A table
// with a second feature set (PoolTable::orientation: a jump's 3-D bar-frame rotation) gets the same
// count, ceiling and expectation on it at its own threshold and twice it, for the same replays
// (the searches see the first feature set only).
#include <map>
#include <string>
#include <vector>

#include "podium/search/space.h"
#include "podium/search/strategies.h"
#include "pool_table.h"

namespace podium::bench::pool {

using tasks::pool::PoolRow;
using tasks::pool::PoolTable;

/// The search side of a table (the adapter that keeps tasks/pool free of search/): its box and
/// features parsed as a task description's, and its lookup as strategies.h's Outcome.
struct SearchView {
  search::Space space;
  std::vector<search::Feature> features;
  std::vector<search::Feature> orientation;  ///< the table's second feature set (empty when none)
  /// Throws UserError naming `origin` when the table's params or features are not a task's.
  SearchView(const PoolTable& table, const std::string& origin);
};

/// The lookup as an Outcome: the nearest row's features (with `orientation`, its second feature
/// set's, when it recorded them) when it succeeded, else nothing. The table must outlive it.
search::Outcome outcome(const PoolTable& table, bool orientation = false);

struct ReplayOptions {
  std::vector<std::string> arms = {"bds", "random", "novelty"};
  std::vector<int> budgets = {5, 10};  ///< ascending
  int reps = 200;
  std::uint64_t first_seed = 0;               ///< repetition r uses search seed first_seed + r in every arm
  std::map<std::string, base::Json> configs;  ///< per arm, its search config (default {})
  int expected_draws = 20000;                 ///< Monte Carlo draws for random's expected count
};

/// One way of counting distinct successful strategies: a feature set of the table (its first, or
/// its second) at one threshold, with that count's baseline over the whole pool.
struct Counting {
  bool orientation = false;  ///< the table's second feature set, else its first
  double threshold = 0.0;
  int ceiling = 0;                      ///< cells the reachable range of the set meets (0 when nothing succeeded)
  int occupied = 0;                     ///< cells the whole pool's successes occupy
  std::vector<double> random_expected;  ///< random search's expected count, per budget
};

/// One arm's runs: [rep][budget] values.
struct ArmRuns {
  std::vector<std::vector<int>> failures;    ///< trials that did not succeed
  std::vector<std::vector<int>> techniques;  ///< distinct nearest captured techniques among successes
  /// Distinct successful strategies, [counting][rep][budget] in ReplayResult::countings' order.
  std::vector<std::vector<std::vector<int>>> counts;
};

struct ReplayResult {
  std::map<std::string, ArmRuns> arms;
  /// The first feature set at τ and 2τ, then (for a table with one) the second at its τ and 2τ.
  std::vector<Counting> countings;
};

/// Runs the replay; throws UserError for an unknown arm or a bad search config.
ReplayResult replay(const PoolTable& table, const ReplayOptions& options);

/// Mean and sample standard deviation.
struct MeanSd {
  double mean = 0.0, sd = 0.0;
};
MeanSd mean_sd(const std::vector<double>& v);

}  // namespace podium::bench::pool
