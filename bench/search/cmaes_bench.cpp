// CMA-ES against python-cmaes 0.9: median evaluations to reach f <= 1e-8 on
// 10-D sphere and Rosenbrock over 10 seeds, same start, step size and bounds; bar: ours within
// 1.5x of the Python library's. Runs cmaes_reference.py as a subprocess for the reference.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "podium/base/json.h"
#include "podium/search/search.h"

using podium::search::Json;

namespace {
constexpr int kDim = 10, kSeeds = 10, kMaxEvals = 200000;

int evaluations_to_target(const std::function<double(const std::vector<double>&)>& f, double x0, double sigma0,
                          std::uint64_t seed) {
  podium::search::SearchSetup setup;
  Json space = Json::array(), start = Json::object();
  for (int i = 0; i < kDim; ++i) {
    space.push_back({{"name", "x" + std::to_string(i)}, {"low", -10.0}, {"high", 10.0}});
    start["x" + std::to_string(i)] = x0;
  }
  setup.space = podium::search::Space::from_json(space, "space");
  setup.config = {{"direction", "minimize"}, {"sigma0", sigma0 / 20.0}, {"x0", start}, {"min_step", 0.0}};  // to 1e-8
  setup.seed = seed;
  auto search = podium::search::make_search("cmaes", setup);
  int evals = 0;
  while (evals < kMaxEvals) {
    for (const auto& p : search->ask(1000)) {
      const double value = f(p.x);
      ++evals;
      if (value <= 1e-8) return evals;
      search->tell({{p.id, true, {value}, {}}});
    }
  }
  return evals;
}

double median(std::vector<int> v) {
  std::sort(v.begin(), v.end());
  return 0.5 * (v[(v.size() - 1) / 2] + v[v.size() / 2]);
}
}  // namespace

int main() {
  const auto sphere = [](const std::vector<double>& x) {
    double s = 0;
    for (double v : x) s += v * v;
    return s;
  };
  const auto rosenbrock = [](const std::vector<double>& x) {
    double s = 0;
    for (std::size_t i = 0; i + 1 < x.size(); ++i) s += 100.0 * std::pow(x[i + 1] - x[i] * x[i], 2) + std::pow(1.0 - x[i], 2);
    return s;
  };
  const std::string command = std::string(PODIUM_PYTHON) + " " + PODIUM_CMAES_REFERENCE + " " + std::to_string(kSeeds);
  FILE* pipe = popen(command.c_str(), "r");
  std::string text;
  char buffer[4096];
  while (pipe && fgets(buffer, sizeof buffer, pipe)) text += buffer;
  if (!pipe || pclose(pipe) != 0) {
    std::printf("SKIP: %s failed (is python3-cmaes installed?)\n", command.c_str());
    return 0;
  }
  const Json reference = Json::parse(text);
  bool pass = true;
  for (const auto& [name, f, x0, sigma0] :
       {std::tuple<std::string, std::function<double(const std::vector<double>&)>, double, double>{"sphere", sphere, 3.0, 1.0},
        {"rosenbrock", rosenbrock, 0.0, 0.5}}) {
    std::vector<int> ours;
    for (int seed = 0; seed < kSeeds; ++seed)
      ours.push_back(evaluations_to_target(f, x0, sigma0, static_cast<std::uint64_t>(seed)));
    const double m_ours = median(ours), m_ref = median(reference[name].get<std::vector<int>>());
    const bool ok = m_ours <= 1.5 * m_ref;
    pass = pass && ok;
    std::printf(
        "%-10s 10-D: median evaluations to 1e-8 over %d seeds: podium %.0f, python-cmaes %.0f, ratio %.2f (bar <= 1.5) %s\n",
        name.c_str(), kSeeds, m_ours, m_ref, m_ours / m_ref, ok ? "PASS" : "FAIL");
  }
  std::printf("%s\n", pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}
