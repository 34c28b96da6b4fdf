// Pool replay: BDS, random and novelty search replayed over a recorded pool of trials (a table
// exported by tasks/pool/export_pool.py), each arm --reps times paired by seed (repetition r uses
// search seed --first-seed + r in every arm), one trial at a time. Prints, per budget: distinct
// successful strategies per arm as mean ± sd (search/strategies.h: occupied grid cells at the
// pool's threshold τ and at 2τ), each arm's paired difference from random with its standard
// error, failures per arm (trials that did not succeed), the ceiling (the cells the pool's
// reachable feature range meets) and random's expected count (Monte Carlo over uniform draws),
// and the mean number of distinct nearest captured techniques among each arm's successes; for a
// table with a second feature set (a jump's 3-D bar-frame rotation), the same on it.
// The thesis's schedule is `--bds-config '{"schedule": "thesis"}'`. `--feature-set orientation`
// replays searches that see the table's second feature set (PoolTable::by_orientation: only the
// rows that recorded it), the first then counted beside it.
// The thesis's claim (§3.7.2: BDS found 6 strategies in 10 samples where random found 3) reads as
// reproduced at 10 samples when BDS ≥ 1.5 × random's mean with the paired difference beyond 2
// standard errors, and only on a complete pool where a replay can find at least twice random's
// expected count (the smaller of the ceiling and the cells the pool's successes occupy; printed as
// "comparable").
//
// Usage: search_pool_replay_bench --table FILE [--feature-set first|orientation] [--reps 200] [--budgets 5,10] [--arms
// bds,random,novelty]
//          [--first-seed 0] [--bds-config '{}'] [--novelty-config '{}']
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "bench_args.h"
#include "pool_replay.h"

using podium::base::Json;
using podium::bench::pool::mean_sd;

namespace {
using podium::bench::pool::ReplayOptions;
using podium::bench::pool::ReplayResult;
using Counts = std::vector<std::vector<int>>;

std::vector<double> at_budget(const Counts& counts, std::size_t b) {
  std::vector<double> v;
  for (const auto& rep : counts) v.push_back(rep[b]);
  return v;
}

// What every counting shares: each arm's failures and distinct nearest captured techniques.
void print_trials(const ReplayResult& r, const ReplayOptions& o) {
  std::printf(
      "\nper arm, mean ± sd: failures (trials that did not succeed); distinct nearest captured techniques among successes\n");
  for (std::size_t b = 0; b < o.budgets.size(); ++b) {
    std::printf("  @%d samples:\n", o.budgets[b]);
    for (const auto& arm : o.arms) {
      const auto f = mean_sd(at_budget(r.arms.at(arm).failures, b)), t = mean_sd(at_budget(r.arms.at(arm).techniques, b));
      std::printf("    %-8s failures %5.2f ± %.2f   techniques %4.2f ± %.2f\n", arm.c_str(), f.mean, f.sd, t.mean, t.sd);
    }
  }
}

// One counting: its ceiling and occupancy, then per budget random's expectation and each arm's
// count with its paired difference from random.
void print_counting(const ReplayResult& r, const ReplayOptions& o, std::size_t c, const std::string& what) {
  const auto& counting = r.countings[c];
  // A replay only visits the pool's rows: it finds at most the cells their successes occupy.
  const int most = std::min(counting.ceiling, counting.occupied);
  std::printf(
      "\n%sτ = %.3g: ceiling %d (cells of the reachable range); the whole pool's successes occupy %d, so a replay "
      "finds at most %d\n",
      what.c_str(), counting.threshold, counting.ceiling, counting.occupied, most);
  for (std::size_t b = 0; b < o.budgets.size(); ++b) {
    const double expected = counting.random_expected[b];
    std::printf("  @%d samples: random's expected count %.2f; at most %d ≥ 2 × expected: %s\n", o.budgets[b], expected, most,
                expected > 0 && most >= 2.0 * expected ? "yes (comparable)" : "no (a search cannot show 2× here)");
    for (const auto& arm : o.arms) {
      const auto v = at_budget(r.arms.at(arm).counts[c], b);
      const auto m = mean_sd(v);
      std::printf("    %-8s %5.2f ± %.2f", arm.c_str(), m.mean, m.sd);
      if (arm != "random" && r.arms.count("random")) {
        const auto random = at_budget(r.arms.at("random").counts[c], b);
        std::vector<double> d;
        for (std::size_t k = 0; k < v.size(); ++k) d.push_back(v[k] - random[k]);
        const auto dm = mean_sd(d);
        std::printf("   − random: %+.2f ± %.2f (SE)", dm.mean, dm.sd / std::sqrt(static_cast<double>(d.size())));
      }
      std::printf("\n");
    }
  }
}
}  // namespace

int main(int argc, char** argv) {
  std::string table_file, feature_set = "first";
  podium::bench::pool::ReplayOptions o;
  using podium::bench::checked, podium::bench::count, podium::bench::Flag;
  long long first_seed = 0;
  const auto read = [&](const std::string& key, const char* value) {
    if (key == "--table") table_file = value;
    else if (key == "--feature-set") {
      feature_set = value;
      return checked(feature_set == "first" || feature_set == "orientation");
    } else if (key == "--reps") return checked(count(value, 1, 1'000'000, o.reps));
    else if (key == "--first-seed") return checked(podium::bench::whole_number(value, 0, first_seed));
    else if (key == "--arms") return checked(podium::bench::list(value, o.arms, podium::bench::name));
    else if (key == "--bds-config") return checked(podium::bench::json_value(value, o.configs["bds"]));
    else if (key == "--novelty-config") return checked(podium::bench::json_value(value, o.configs["novelty"]));
    else if (key == "--budgets")
      return checked(podium::bench::list(value, o.budgets, [&](const char* b, int& v) { return count(b, 1, 10'000, v); }));
    else return Flag::unknown;
    return Flag::read;
  };
  if (!podium::bench::read_flags(argc, argv, "--table FILE [--FLAG VALUE ...] (the top of bench/search/pool_replay_bench.cpp)",
                                 read))
    return 2;
  if (table_file.empty() || o.budgets.empty() || !std::is_sorted(o.budgets.begin(), o.budgets.end())) {
    std::fprintf(stderr, "%s: needs --table FILE and ascending --budgets\n", argv[0]);
    return 2;
  }
  o.first_seed = static_cast<std::uint64_t>(first_seed);
  try {
    const auto recorded = podium::bench::pool::PoolTable::load(table_file);
    const auto table = feature_set == "orientation" ? recorded.by_orientation() : recorded;
    int finished = 0, succeeded = 0;
    for (const auto& row : table.rows) {
      finished += row.finished ? 1 : 0;
      succeeded += row.success ? 1 : 0;
    }
    const auto start = std::chrono::steady_clock::now();
    const auto r = podium::bench::pool::replay(table, o);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("pool %s (%s): %zu recorded trials, %d finished, %d successful; τ = %.3g\n", table_file.c_str(),
                table.source.dump().c_str(), table.rows.size(), finished, succeeded, table.strategy_threshold);
    std::printf("the searches see the %s feature set:", feature_set == "orientation" ? "second" : "first");
    for (const auto& f : table.features) std::printf(" %s", f.name.c_str());
    std::printf("\nreps %d paired by seed (first %llu), arms", o.reps, first_seed);
    for (const auto& a : o.arms) std::printf(" %s", a.c_str());
    std::printf("; %.1f s\n", seconds);
    print_trials(r, o);
    std::string first = "the features the searches see, ", second = "beside them, the ";
    for (const auto& f : table.orientation_features) second += f.name + " ";
    second += "(" + table.orientation_json.value("info", std::string()) + "), ";
    for (std::size_t c = 0; c < r.countings.size(); ++c) print_counting(r, o, c, r.countings[c].orientation ? second : first);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", argv[0], e.what());
    return 1;
  }
  return 0;
}
