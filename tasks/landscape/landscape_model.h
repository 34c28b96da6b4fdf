#pragma once
// A seeded analytic "strategy landscape": maps the box [0,1]^d to a strategy feature vector with
// large flat regions, so diversity searches have something to find and the test suite has a task
// that costs microseconds. Hand-written: no library offers such synthetic landscapes.
//
// Families (all >= 1-D, feature of 2 dimensions in [0,1]):
//  - "basins":   one base feature over most of the box, plus a few small Gaussian-shaped basins of
//                distinct feature values (rare strategies).
//  - "plateaus": a smooth random trend per feature dimension (sum of random cosines), quantised
//                into levels of unequal width: strategies are plateaus, and the feature has
//                structure a surrogate can learn (as take-off velocities shape a jump).
//  - "voronoi":  weighted-Voronoi regions of constant random feature: no structure beyond space.
#include <cstdint>
#include <string>
#include <vector>

namespace podium::tasks::landscape {

struct LandscapeOptions {
  std::string family = "basins";
  int dim = 3;
  std::uint64_t landscape_seed = 1;
  int regions = 6;       // basins, quantisation levels per feature, or Voronoi cells
};

class LandscapeModel {
 public:
  explicit LandscapeModel(const LandscapeOptions& options);
  /// Strategy feature at x (x in [0,1]^dim), 2 values in [0,1].
  std::vector<double> feature(const std::vector<double>& x) const;
  /// A smooth objective to maximise (peak 0 at a seeded optimum), for optimisers like CMA-ES.
  double objective(const std::vector<double>& x) const;
  int dim() const { return options_.dim; }
  static constexpr int kFeatureDim = 2;
  static std::vector<std::string> families() { return {"basins", "plateaus", "voronoi"}; }

 private:
  struct Cosine { std::vector<double> frequency; double phase, amplitude; };
  LandscapeOptions options_;
  std::vector<std::vector<double>> centres_;   // basins or Voronoi sites
  std::vector<double> weights_;                // basin radii or Voronoi weights
  std::vector<std::vector<double>> values_;    // feature value per basin / cell / level
  std::vector<double> base_value_;             // "basins": the feature outside every basin
  std::vector<std::vector<Cosine>> trends_;    // "plateaus": per feature dimension
  std::vector<std::vector<double>> thresholds_;  // "plateaus": level boundaries per dimension
  std::vector<double> optimum_;
};

}  // namespace podium::tasks::landscape
