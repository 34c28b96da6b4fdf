// Time per BDS proposal with 100 observations in 4-D on one core (bar: ≤ 1 s).
// Each timed ask(1) follows a tell, so it includes the hyperparameter refit (2 features × 3 L-BFGS
// runs), the believer conditioning and the acquisition optimisation (L-BFGS or DIRECT-L).
//
// Usage: search_bds_proposal_time_bench [--observations 100] [--proposals 12] [--bds-config '{}']
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>
#include <string>

#include "bench_args.h"
#include "landscape_model.h"
#include "podium/search/search.h"

using podium::search::Json;

int main(int argc, char** argv) {
  int observations = 100, proposals = 12;
  Json config = Json::object();
  // A million at most each: far beyond a useful run, and the proposal loop counts in int.
  using podium::bench::checked, podium::bench::Flag;
  if (!podium::bench::read_flags(argc, argv, "[--observations N ≥ 1] [--proposals N ≥ 1] [--bds-config JSON]",
                                 [&](const std::string& key, const char* value) {
                                   if (key == "--observations")
                                     return checked(podium::bench::count(value, 1, 1'000'000, observations));
                                   if (key == "--proposals") return checked(podium::bench::count(value, 1, 1'000'000, proposals));
                                   if (key == "--bds-config") return checked(podium::bench::json_value(value, config));
                                   return Flag::unknown;
                                 }))
    return 2;
  const int dim = 4;
  const podium::tasks::landscape::LandscapeModel model({"plateaus", dim, 1, 6});
  podium::search::SearchSetup setup;
  Json space = Json::array();
  for (int i = 0; i < dim; ++i) space.push_back({{"name", "x" + std::to_string(i)}, {"low", 0.0}, {"high", 1.0}});
  setup.space = podium::search::Space::from_json(space, "space");
  setup.features = podium::search::Feature::list_from_json(
      Json::parse(R"([{"name": "f0", "low": 0, "high": 1}, {"name": "f1", "low": 0, "high": 1}])"), "features");
  config["initial_samples"] = observations;  // the first 100 are random: time only GP-guided proposals
  setup.config = config;
  setup.seed = 5;
  auto search = podium::search::make_search("bds", setup);
  auto evaluate = [&](const podium::search::Proposal& p) {
    return podium::search::Observation{p.id, true, {model.objective(p.x)}, model.feature(p.x)};
  };
  for (const auto& p : search->ask(static_cast<std::size_t>(observations))) search->tell({evaluate(p)});

  std::map<std::string, std::vector<double>> seconds;
  for (int k = 0; k < proposals; ++k) {
    const auto start = std::chrono::steady_clock::now();
    const auto p = search->ask(1).at(0);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    seconds[p.info.at("step").get<std::string>()].push_back(s);
    seconds["all"].push_back(s);
    search->tell({evaluate(p)});
  }
  double worst = 0;
  for (auto& [step, v] : seconds) {
    std::sort(v.begin(), v.end());
    worst = std::max(worst, v.back());
    std::printf("%-9s proposals: %2zu, median %.3f s, max %.3f s (observations %d..%d, 4-D, 2 features)\n", step.c_str(),
                v.size(), v[v.size() / 2], v.back(), observations, observations + proposals - 1);
  }
  std::printf("%s (bar: every proposal <= 1 s)\n", worst <= 1.0 ? "PASS" : "FAIL");
  return worst <= 1.0 ? 0 : 1;
}
