// Scheduler throughput beside a hammering dashboard client (docs/architecture.md "The store contract": the dashboard must
// not slow a running campaign). Each round runs a 2,000-trial landscape campaign alone and with
// `podium serve` answering a client that requests the dashboard's endpoints back to back, in
// alternating order; the figure is the median paired drop. Bar: under 20%.
// Usage: web_dashboard_concurrency_bench [--rounds N]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "bench_args.h"
#include "concurrency_load.h"

using podium::web_dashboard::testing::LoadRun;
using podium::web_dashboard::testing::run_landscape_load;

int main(int argc, char** argv) {
  ::setenv("PODIUM_BIN", PODIUM_BENCH_BIN, 0);
  ::setenv("PODIUM_PLUGIN_PATH", PODIUM_BENCH_PLUGIN_DIR, 0);
  int rounds = 5;
  // A million at most: far beyond a useful run.
  if (!podium::bench::read_flags(argc, argv, "[--rounds N ≥ 1]", [&](const std::string& key, const char* value) {
        if (key != "--rounds") return podium::bench::Flag::unknown;
        return podium::bench::checked(podium::bench::count(value, 1, 1'000'000, rounds));
      }))
    return 2;
  constexpr int kTrials = 2000;
  std::vector<double> alone, hammered, ratios;
  long long requests = 0, errors = 0, locked = 0;
  for (int round = 0; round < rounds; ++round) {
    // Alternating which goes first keeps slow drifts of a shared machine out of the comparison.
    LoadRun a, h;
    if (round % 2 == 0) a = run_landscape_load(kTrials, false);
    h = run_landscape_load(kTrials, true);
    if (round % 2 == 1) a = run_landscape_load(kTrials, false);
    if (!a.ok || !h.ok) {
      std::fprintf(stderr, "round %d: a campaign did not finish: %s%s\n", round, a.problem.c_str(), h.problem.c_str());
      return 1;
    }
    alone.push_back(a.trials_per_second);
    hammered.push_back(h.trials_per_second);
    ratios.push_back(h.trials_per_second / a.trials_per_second);
    requests += h.requests;
    errors += h.errors;
    locked += h.locked;
    std::printf("round %d: alone %.0f trials/s, hammered %.0f trials/s (%+.1f%%), %lld API requests\n", round, alone.back(),
                hammered.back(), 100 * (ratios.back() - 1), static_cast<long long>(h.requests));
  }
  auto median = [](std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  // Paired within a round: the machine's throughput drifts across rounds (seen: 2100 -> 1300
  // trials/s alone over 15 s), which unpaired medians would mistake for the client's effect.
  const double drop = 1.0 - median(ratios);
  std::printf(
      "median over %d rounds: alone %.0f trials/s, hammered %.0f trials/s; median paired drop %.1f%% (bar < 20%%); "
      "%lld API requests, %lld errors, %lld 'locked'\n",
      rounds, median(alone), median(hammered), 100 * drop, requests, errors, locked);
  return 0;
}
