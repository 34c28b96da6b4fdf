#pragma once
// Uniform random sampling in the parameter box: the baseline every diversity claim is compared with.
#include <set>

#include "podium/base/rng.h"
#include "podium/search/search.h"

namespace podium::search {

class RandomSearch final : public Search {
 public:
  RandomSearch(const SearchSetup& setup, const std::string& json_path);
  std::string name() const override { return "random"; }
  std::vector<Proposal> ask(std::size_t n) override;
  void tell(const std::vector<Observation>& observations) override;
  Json save() const override;
  void load(const Json& state) override;

 private:
  Space space_;
  base::Rng rng_;
  std::uint64_t next_id_ = 0;
  std::set<std::uint64_t> pending_;
};

}  // namespace podium::search
