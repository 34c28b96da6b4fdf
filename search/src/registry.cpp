// The one place that maps an algorithm name in a campaign spec to its implementation.
#include "podium/base/error.h"
#include "podium/search/search.h"
#include "random_search.h"

namespace podium::search {

std::vector<std::string> algorithm_names() { return {"random"}; }

std::unique_ptr<Search> make_search(const std::string& algorithm, const SearchSetup& setup,
                                    const std::string& json_path) {
  if (algorithm == "random") return std::make_unique<RandomSearch>(setup, json_path);
  std::string known;
  for (const auto& n : algorithm_names()) known += (known.empty() ? "" : ", ") + n;
  throw base::UserError(json_path + ".algorithm: unknown algorithm \"" + algorithm + "\" (known: " + known + ")");
}

}  // namespace podium::search
