#include "novelty_search.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "pending.h"
#include "podium/base/config.h"
#include "podium/search/strategies.h"

namespace podium::search {

NoveltyParams NoveltyParams::from_json(const Json& config, const std::vector<Feature>& features, const std::string& path) {
  base::ConfigReader r(config, path);
  NoveltyParams p;
  p.initial_samples = r.integer("initial_samples", p.initial_samples, {1, 100000});
  p.k = r.integer("k", p.k, {1, 1000});
  p.archive_threshold = r.number("archive_threshold", p.archive_threshold, {0.0, 1e300});
  p.mutation = r.number("mutation", p.mutation, {1e-9, 10.0});
  p.tournament = r.integer("tournament", p.tournament, {1, 1000});
  r.finish();
  if (p.archive_threshold == 0.0) {
    double diagonal = 0.0;
    for (const auto& f : features) diagonal += (f.high - f.low) * (f.high - f.low);
    p.archive_threshold = 0.05 * std::sqrt(diagonal);
  }
  return p;
}

NoveltySearch::NoveltySearch(const SearchSetup& setup, const std::string& json_path)
    : space_(setup.space),
      features_(setup.features),
      params_(NoveltyParams::from_json(setup.config, setup.features, json_path + ".config")),
      rng_(setup.seed) {
  if (features_.empty()) throw base::UserError(json_path + ": novelty search needs the task to declare at least one feature");
}

double NoveltySearch::sparseness(const std::vector<double>& f, std::size_t skip) const {
  std::vector<double> d;
  for (std::size_t i = 0; i < fs_.size(); ++i)
    if (i != skip) d.push_back(feature_distance(features_, f, fs_[i]));
  if (d.empty()) return std::numeric_limits<double>::infinity();
  const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(params_.k), d.size());
  std::partial_sort(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(k), d.end());
  double sum = 0.0;
  for (std::size_t i = 0; i < k; ++i) sum += d[i];
  return sum / static_cast<double>(k);
}

std::vector<Proposal> NoveltySearch::ask(std::size_t n) {
  std::vector<Proposal> out;
  for (std::size_t q = 0; q < n; ++q) {
    Proposal p;
    p.id = next_id_++;
    if (p.id < static_cast<std::uint64_t>(params_.initial_samples) || archive_.empty()) {
      for (const auto& param : space_.params) p.x.push_back(rng_.uniform(param.low, param.high));
      p.info = {{"step", "initial"}};
    } else {
      // Tournament on current sparseness: the archive member farthest from its neighbours wins.
      std::size_t parent = archive_[static_cast<std::size_t>(rng_.integer(0, static_cast<std::int64_t>(archive_.size()) - 1))];
      double best = sparseness(fs_[parent], parent);
      for (int t = 1; t < params_.tournament; ++t) {
        const std::size_t c = archive_[static_cast<std::size_t>(rng_.integer(0, static_cast<std::int64_t>(archive_.size()) - 1))];
        const double s = sparseness(fs_[c], c);
        if (s > best) {
          best = s;
          parent = c;
        }
      }
      for (std::size_t i = 0; i < space_.dim(); ++i) {
        const auto& param = space_.params[i];
        const double width = param.high - param.low;
        double v = xs_[parent][i] + rng_.normal(0.0, params_.mutation * width);
        // Reflect into the box (repeatedly for large steps), then guard round-off.
        for (int r = 0; r < 8 && (v < param.low || v > param.high); ++r)
          v = v < param.low ? 2 * param.low - v : 2 * param.high - v;
        p.x.push_back(std::clamp(v, param.low, param.high));
      }
      p.info = {{"step", "mutate"}, {"parent_sparseness", best}};
    }
    for (std::size_t i = 0; i < space_.dim(); ++i)
      if (space_.params[i].integer)
        p.x[i] = std::clamp(std::round(p.x[i]), std::ceil(space_.params[i].low), std::floor(space_.params[i].high));
    pending_.insert(p.id);
    asked_x_[p.id] = p.x;
    out.push_back(std::move(p));
  }
  return out;
}

void NoveltySearch::tell(const std::vector<Observation>& observations) {
  for (const auto& o : observations) {
    take_pending(pending_, o.id, name());
    const auto x = asked_x_.at(o.id);
    asked_x_.erase(o.id);
    if (!o.ok) continue;  // failures carry no features: nothing to archive
    if (o.features.size() != features_.size())
      throw base::UserError(name() + ": trial " + std::to_string(o.id) + " reported " + std::to_string(o.features.size()) +
                            " feature values but the task declares " + std::to_string(features_.size()));
    const bool novel = sparseness(o.features, fs_.size()) > params_.archive_threshold;
    xs_.push_back(x);
    fs_.push_back(o.features);
    if (novel || archive_.empty()) archive_.push_back(fs_.size() - 1);
  }
}

Json NoveltySearch::save() const {
  Json asked = Json::array();
  for (const auto& [id, x] : asked_x_) asked.push_back({{"id", id}, {"x", x}});
  return {{"rng", rng_.save()}, {"next_id", next_id_}, {"pending", pending_to_json(pending_)}, {"asked", asked}, {"xs", xs_},
          {"fs", fs_},          {"archive", archive_}};
}

void NoveltySearch::load(const Json& state) {
  rng_.load(state.at("rng").get<std::string>());
  next_id_ = state.at("next_id").get<std::uint64_t>();
  pending_ = pending_from_json(state.at("pending"));
  asked_x_.clear();
  for (const auto& a : state.at("asked")) asked_x_[a.at("id").get<std::uint64_t>()] = a.at("x").get<std::vector<double>>();
  xs_ = state.at("xs").get<std::vector<std::vector<double>>>();
  fs_ = state.at("fs").get<std::vector<std::vector<double>>>();
  archive_ = state.at("archive").get<std::vector<std::size_t>>();
}

}  // namespace podium::search
