// The one place that maps an algorithm name in a campaign spec to its implementation, and the
// search.h helpers every search shares.
#include "bds.h"
#include "cmaes.h"
#include "novel_policy_seeking.h"
#include "novelty_search.h"
#include "podium/base/error.h"
#include "podium/search/search.h"
#include "random_search.h"

namespace podium::search {

std::vector<double> evaluated_params(const Json& info) {
  const auto it = info.find("evaluated_params");
  if (it == info.end() || !it->is_array()) return {};
  std::vector<double> x;
  for (const Json& v : *it) {
    if (!v.is_number()) return {};
    x.push_back(v.get<double>());
  }
  return x;
}

std::vector<std::string> algorithm_names() { return {"random", "bds", "novelty", "novel_policy", "cmaes"}; }

std::unique_ptr<Search> make_search(const std::string& algorithm, const SearchSetup& setup, const std::string& json_path) {
  if (algorithm == "random") return std::make_unique<RandomSearch>(setup, json_path);
  if (algorithm == "novelty") return std::make_unique<NoveltySearch>(setup, json_path);
  if (algorithm == "novel_policy") return std::make_unique<NovelPolicySeeking>(setup, json_path);
  if (algorithm == "cmaes") return std::make_unique<Cmaes>(setup, json_path);
  if (algorithm == "bds") return std::make_unique<BayesianDiversitySearch>(setup, json_path);
  std::string known;
  for (const auto& n : algorithm_names()) known += (known.empty() ? "" : ", ") + n;
  throw base::UserError(json_path + ".algorithm: unknown algorithm \"" + algorithm + "\" (known: " + known + ")");
}

void check_search(const std::string& algorithm, const SearchSetup& setup, bool has_inputs, const std::string& json_path) {
  if (algorithm != "novel_policy") {
    SearchSetup without_inputs = setup;
    without_inputs.inputs = Json::array();
    make_search(algorithm, without_inputs, json_path);
    return;
  }
  NovelPolicyParams::from_json(setup.config, json_path + ".config");
  if (!has_inputs)
    throw base::UserError(json_path +
                          ".algorithm: \"novel_policy\" seeks novel policies for an earlier stage's "
                          "trials, but the stage has no \"inputs\"");
}

}  // namespace podium::search
