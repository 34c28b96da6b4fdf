#include "landscape_model.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "podium/base/error.h"
#include "podium/base/rng.h"

namespace podium::tasks::landscape {

LandscapeModel::LandscapeModel(const LandscapeOptions& options) : options_(options) {
  if (options.dim < 1) throw base::UserError("landscape: dim " + std::to_string(options.dim) + " is not >= 1");
  if (options.regions < 2) throw base::UserError("landscape: regions " + std::to_string(options.regions) + " is not >= 2");
  base::Rng rng(base::derive_seed(options.landscape_seed, 0x1a2d5ca9e));
  const int d = options.dim;
  auto random_point = [&] {
    std::vector<double> p(d);
    for (auto& v : p) v = rng.uniform();
    return p;
  };
  auto random_feature = [&] {
    std::vector<double> f(kFeatureDim);
    for (auto& v : f) v = rng.uniform();
    return f;
  };
  optimum_ = random_point();

  if (options.family == "basins") {
    base_value_ = random_feature();
    for (int k = 0; k < options.regions; ++k) {
      centres_.push_back(random_point());
      weights_.push_back(rng.uniform(0.05, 0.12));  // radius: each basin covers a few % of the box
      values_.push_back(random_feature());
    }
  } else if (options.family == "voronoi") {
    for (int k = 0; k < options.regions; ++k) {
      centres_.push_back(random_point());
      weights_.push_back(rng.uniform(0.0, 0.05));  // additive weights make cells unequal
      values_.push_back(random_feature());
    }
  } else if (options.family == "plateaus" || options.family == "plateaus_rough") {
    const double max_frequency = options.max_frequency > 0.0 ? options.max_frequency : options.family == "plateaus" ? 1.0 : 1.5;
    for (int f = 0; f < kFeatureDim; ++f) {
      std::vector<Cosine> trend;
      for (int c = 0; c < 3; ++c) {
        Cosine cos_term;
        for (int i = 0; i < d; ++i) cos_term.frequency.push_back(rng.uniform(-max_frequency, max_frequency));
        cos_term.phase = rng.uniform(0.0, 2.0 * std::numbers::pi);
        cos_term.amplitude = rng.uniform(0.5, 1.0);
        trend.push_back(cos_term);
      }
      trends_.push_back(trend);
      // Unequal level widths: sorted random cut points of the squashed trend's range (0,1).
      std::vector<double> cuts;
      for (int k = 0; k + 1 < options.regions; ++k) cuts.push_back(rng.uniform(0.1, 0.9));
      std::sort(cuts.begin(), cuts.end());
      thresholds_.push_back(cuts);
    }
  } else {
    throw base::UserError("landscape: family \"" + options.family + "\" is not one of basins, plateaus, plateaus_rough, voronoi");
  }
  if (!(options.fail_fraction >= 0.0 && options.fail_fraction < 1.0))
    throw base::UserError("landscape: fail_fraction " + std::to_string(options.fail_fraction) + " is not in [0, 1)");
  if (options.fail_fraction > 0.0) {
    base::Rng fail_rng(base::derive_seed(options.landscape_seed, 0xfa11ed));
    for (int c = 0; c < 3; ++c) {
      Cosine term;
      for (int i = 0; i < d; ++i) term.frequency.push_back(fail_rng.uniform(-1.0, 1.0));
      term.phase = fail_rng.uniform(0.0, 2.0 * std::numbers::pi);
      term.amplitude = fail_rng.uniform(0.5, 1.0);
      failure_field_.push_back(term);
    }
    // The quantile over uniform points of the box: about fail_fraction of it fails.
    std::vector<double> values;
    for (int k = 0; k < 4096; ++k) {
      std::vector<double> p(d);
      for (auto& v : p) v = fail_rng.uniform();
      values.push_back(cosine_sum(failure_field_, p));
    }
    std::sort(values.begin(), values.end());
    failure_cut_ = values[static_cast<std::size_t>(options.fail_fraction * static_cast<double>(values.size()))];
  }
}

double LandscapeModel::cosine_sum(const std::vector<Cosine>& terms, const std::vector<double>& x) {
  double t = 0.0;
  for (const auto& c : terms) {
    double phase = c.phase;
    for (std::size_t i = 0; i < x.size(); ++i) phase += 2.0 * std::numbers::pi * c.frequency[i] * x[i];
    t += c.amplitude * std::cos(phase);
  }
  return t;
}

bool LandscapeModel::succeeds(const std::vector<double>& x) const {
  PODIUM_CHECK(static_cast<int>(x.size()) == options_.dim, "landscape: x has the wrong dimension");
  return failure_field_.empty() || cosine_sum(failure_field_, x) >= failure_cut_;
}

std::vector<double> LandscapeModel::feature(const std::vector<double>& x) const {
  PODIUM_CHECK(static_cast<int>(x.size()) == options_.dim, "landscape: x has the wrong dimension");
  auto squared_distance = [&](const std::vector<double>& c) {
    double s = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) s += (x[i] - c[i]) * (x[i] - c[i]);
    return s;
  };
  if (options_.family == "basins") {
    for (std::size_t k = 0; k < centres_.size(); ++k)
      if (squared_distance(centres_[k]) < weights_[k] * weights_[k] * options_.dim) return values_[k];
    return base_value_;
  }
  if (options_.family == "voronoi") {
    std::size_t best = 0;
    double best_score = 1e300;
    for (std::size_t k = 0; k < centres_.size(); ++k) {
      const double score = squared_distance(centres_[k]) - weights_[k];
      if (score < best_score) {
        best_score = score;
        best = k;
      }
    }
    return values_[best];
  }
  // plateaus: report the centre of the squashed trend's level.
  const auto squashed = trend(x);
  std::vector<double> out(kFeatureDim);
  for (int f = 0; f < kFeatureDim; ++f) {
    const auto& cuts = thresholds_[f];
    const auto level = std::upper_bound(cuts.begin(), cuts.end(), squashed[f]) - cuts.begin();
    const double lo = level == 0 ? 0.0 : cuts[level - 1];
    const double hi = level == static_cast<long>(cuts.size()) ? 1.0 : cuts[level];
    out[f] = 0.5 * (lo + hi);
  }
  return out;
}

std::vector<double> LandscapeModel::trend(const std::vector<double>& x) const {
  PODIUM_CHECK(static_cast<int>(x.size()) == options_.dim, "landscape: x has the wrong dimension");
  if (trends_.empty()) throw base::UserError("landscape: trend() is defined for the plateau families only");
  std::vector<double> out(kFeatureDim);
  for (int f = 0; f < kFeatureDim; ++f) out[f] = 0.5 + 0.5 * std::tanh(cosine_sum(trends_[f], x));
  return out;
}

double LandscapeModel::objective(const std::vector<double>& x) const {
  double s = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) s += (x[i] - optimum_[i]) * (x[i] - optimum_[i]);
  return -s;
}

}  // namespace podium::tasks::landscape
