#pragma once
// Novelty search as a general outer loop (Lehman & Stanley 2011, in ask/tell form): the novelty
// (sparseness) of a feature vector f is the mean feature distance to its k nearest neighbours among
// every successful trial, ρ(f) = 1/k Σ_{i≤k} ‖f − μ_i‖ (metric of strategies.h). A trial whose
// sparseness at tell time exceeds `archive_threshold` joins the archive. Proposals after
// `initial_samples` random ones mutate an archive member chosen by tournament on current
// sparseness: x' = x + N(0, (mutation·range)²), reflected into the box.
#include <map>
#include <set>

#include "podium/base/rng.h"
#include "podium/search/search.h"

namespace podium::search {

struct NoveltyParams {
  int initial_samples = 4;         ///< random proposals before mutation starts
  int k = 3;                       ///< nearest neighbours in the sparseness
  double archive_threshold = 0.0;  ///< feature-distance units; 0 = 5% of the feature box diagonal
  double mutation = 0.3;           ///< Gaussian mutation σ as a fraction of each parameter's range
  int tournament = 3;              ///< archive members drawn per parent selection
  static NoveltyParams from_json(const Json& config, const std::vector<Feature>& features, const std::string& path);
};

class NoveltySearch final : public Search {
 public:
  NoveltySearch(const SearchSetup& setup, const std::string& json_path);
  std::string name() const override { return "novelty"; }
  std::vector<Proposal> ask(std::size_t n) override;
  void tell(const std::vector<Observation>& observations) override;
  Json save() const override;
  void load(const Json& state) override;

 private:
  double sparseness(const std::vector<double>& f, std::size_t skip) const;

  Space space_;
  std::vector<Feature> features_;
  NoveltyParams params_;
  base::Rng rng_;
  std::uint64_t next_id_ = 0;
  std::set<std::uint64_t> pending_;
  std::map<std::uint64_t, std::vector<double>> asked_x_;  // pending id → parameters
  std::vector<std::vector<double>> xs_, fs_;              // successful trials, in tell order
  std::vector<std::size_t> archive_;                      // indices into xs_/fs_
};

}  // namespace podium::search
