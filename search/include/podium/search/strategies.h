#pragma once
/// The one definition of "distinct strategies" (docs/architecture.md "Concepts": a strategy is a cluster of
/// trials whose features are within a distance threshold), shared by the searches, the store and
/// the dashboard.
#include <vector>

#include "podium/search/space.h"

namespace podium::search {

/// Distance between two feature vectors: √(Σ_i d_i²), where d_i = |a_i − b_i| for a euclidean
/// feature and the wrapped angle difference in [0, π] for an angular one (radians), so that
/// −π and π are the same orientation.
double feature_distance(const std::vector<Feature>& features, const std::vector<double>& a,
                        const std::vector<double>& b);

/// Groups feature vectors into distinct strategies by leader clustering: in the given order
/// (trial order), each vector joins the first strategy whose leader (its first member) lies within
/// `threshold` (feature_distance ≤ threshold), or else founds a new strategy. Deterministic for a
/// given order. Returns the strategy index of each vector, numbered 0, 1, ... as founded.
/// Throws UserError when a vector's size differs from `features` or the threshold is negative.
std::vector<int> group_strategies(const std::vector<Feature>& features,
                                  const std::vector<std::vector<double>>& vectors, double threshold);

/// Number of distinct strategies among `vectors` (1 + the largest group_strategies index; 0 if empty).
int count_strategies(const std::vector<Feature>& features, const std::vector<std::vector<double>>& vectors,
                     double threshold);

}  // namespace podium::search
