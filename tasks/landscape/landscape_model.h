#pragma once
// A seeded analytic "strategy landscape": maps the box [0,1]^d to a strategy feature vector with
// large flat regions, so diversity searches have something to find and the test suite has a task
// that costs microseconds. Hand-written: no library offers such synthetic landscapes.
//
// Families (all >= 1-D, feature of 2 dimensions in [0,1]):
//  - "basins":   one base feature over most of the box, plus a few small Gaussian-shaped basins of
//                distinct feature values (rare strategies).
//  - "plateaus": a smooth random trend per feature dimension (sum of 3 random cosines, each
//                frequency uniform in ±1 cycle per unit on each axis), squashed and quantised
//                into levels of unequal width: strategies are plateaus, and the feature has
//                structure a surrogate can learn (as take-off velocities shape a jump). The
//                frequency bound is the roughest (on a grid of 0.25) that meets a criterion involving
//                no search algorithm: a GP fitted to 20 random samples explains median R² ≥ 0.5 of
//                the squashed trend (bench/search/landscape_smoothness_bench.cpp, landscapes
//                1001–1020: R² 0.58 at ±1, 0.32 at ±1.25, 0.13 at ±1.5).
//  - "plateaus_rough": the same construction with frequencies in ±1.5 (the first version of
//                "plateaus"; a GP on 20 samples explains median R² ≈ 0.2 of it), kept for comparison.
//  - "voronoi":  weighted-Voronoi regions of constant random feature: no structure beyond space.
#include <cstdint>
#include <string>
#include <vector>

namespace podium::tasks::landscape {

struct LandscapeOptions {
  std::string family = "basins";
  int dim = 3;
  std::uint64_t landscape_seed = 1;
  int regions = 6;  // basins, quantisation levels per feature, or Voronoi cells
  /// Plateau families: bound of the trend's cosine frequencies (cycles per unit per axis); 0 means
  /// the family's own (1.0 for "plateaus", 1.5 for "plateaus_rough"). For smoothness studies.
  double max_frequency = 0.0;
  /// Fraction of the box where a trial fails (0: none): where a smooth random field (3 cosines,
  /// frequencies within ±1 per axis, drawn from its own seed stream so the features do not change)
  /// lies below its `fail_fraction` quantile. A failed trial still has a feature (the landscape's
  /// there), as a jump that does not clear still has an up-angle: for searches that must learn
  /// where trials fail.
  double fail_fraction = 0.0;
};

class LandscapeModel {
 public:
  explicit LandscapeModel(const LandscapeOptions& options);
  /// Strategy feature at x (x in [0,1]^dim), 2 values in [0,1].
  std::vector<double> feature(const std::vector<double>& x) const;
  /// Plateau families: the squashed trend in (0,1) per feature dimension, before quantisation.
  std::vector<double> trend(const std::vector<double>& x) const;
  /// A smooth objective to maximise (peak 0 at a seeded optimum), for optimisers like CMA-ES.
  double objective(const std::vector<double>& x) const;
  /// Whether a trial at x succeeds (always, when fail_fraction is 0).
  bool succeeds(const std::vector<double>& x) const;
  int dim() const { return options_.dim; }
  static constexpr int kFeatureDim = 2;
  static std::vector<std::string> families() { return {"basins", "plateaus", "plateaus_rough", "voronoi"}; }

 private:
  struct Cosine {
    std::vector<double> frequency;
    double phase, amplitude;
  };
  LandscapeOptions options_;
  std::vector<std::vector<double>> centres_;     // basins or Voronoi sites
  std::vector<double> weights_;                  // basin radii or Voronoi weights
  std::vector<std::vector<double>> values_;      // feature value per basin / cell / level
  std::vector<double> base_value_;               // "basins": the feature outside every basin
  std::vector<std::vector<Cosine>> trends_;      // "plateaus": per feature dimension
  std::vector<std::vector<double>> thresholds_;  // "plateaus": level boundaries per dimension
  std::vector<double> optimum_;
  std::vector<Cosine> failure_field_;  // fail_fraction > 0: fails where its value < failure_cut_
  double failure_cut_ = 0.0;
  static double cosine_sum(const std::vector<Cosine>& terms, const std::vector<double>& x);
};

}  // namespace podium::tasks::landscape
