#include "random_search.h"

#include <cmath>

#include "pending.h"

namespace podium::search {

RandomSearch::RandomSearch(const SearchSetup& setup, const std::string& json_path) : space_(setup.space), rng_(setup.seed) {
  if (!setup.config.is_object() || !setup.config.empty())
    throw base::UserError(json_path + ".config: random search takes no options, got " + setup.config.dump());
}

std::vector<Proposal> RandomSearch::ask(std::size_t n) {
  std::vector<Proposal> out;
  for (std::size_t k = 0; k < n; ++k) {
    Proposal p;
    p.id = next_id_++;
    for (const auto& param : space_.params) {
      double v = rng_.uniform(param.low, param.high);
      if (param.integer) v = std::round(v);
      p.x.push_back(v);
    }
    pending_.insert(p.id);
    out.push_back(std::move(p));
  }
  return out;
}

void RandomSearch::tell(const std::vector<Observation>& observations) {
  for (const auto& o : observations) take_pending(pending_, o.id, name());
}

Json RandomSearch::save() const { return {{"rng", rng_.save()}, {"next_id", next_id_}, {"pending", pending_to_json(pending_)}}; }

void RandomSearch::load(const Json& state) {
  rng_.load(state.at("rng").get<std::string>());
  next_id_ = state.at("next_id").get<std::uint64_t>();
  pending_ = pending_from_json(state.at("pending"));
}

}  // namespace podium::search
