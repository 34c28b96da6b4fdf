#pragma once
/// The one definition of "distinct strategies" (docs/architecture.md "Concepts"), shared by the
/// searches, the store's strategy ids, the dashboard and the benchmarks.
///
/// Rule: occupied cells of a fixed grid. Each feature's declared range [low, high] is cut into
/// n = max(1, round((high − low) / τ)) equal cells (an angular feature: its full turn 2π into
/// max(1, round(2π / τ)) cells from `low`, wrapping), so a cell is about τ wide; a trial's strategy
/// is the cell its feature vector falls in (values outside the range join the end cell), and the
/// number of distinct strategies among trials is the number of cells their successful trials
/// occupy. Why this rule and not leader clustering (order-dependent: the same trials gave 2 or 3
/// strategies over orderings) or the largest set of trials pairwise farther apart than τ (order-free
/// but NP-hard beyond one feature, and a trial's id would move when later trials arrive):
/// - order-free by construction, and exact at any number of trials and features in O(n);
/// - a trial's id is its own cell, so the id the store gives a trial when it finishes is final
///   (no regrouping) and the store's count (distinct ids) is this count;
/// - the ceiling is explicit: the cells a reachable feature range meets (strategy_ceiling);
/// - its cost, a cluster straddling a cell edge counting twice, is paid equally by every search
///   compared on the same grid; counts at two thresholds (τ and 2τ, grids of different edges)
///   show how much it matters.
/// Failed trials (the task's success rule says no, see trial_success) have no strategy.
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "podium/base/json.h"
#include "podium/search/space.h"

namespace podium::search {

/// Distance between two feature vectors: √(Σ_i d_i²), where d_i = |a_i − b_i| for a euclidean
/// feature and the wrapped angle difference in [0, π] for an angular one (radians), so that
/// −π and π are the same orientation.
double feature_distance(const std::vector<Feature>& features, const std::vector<double>& a, const std::vector<double>& b);

/// Cells of each feature's grid at `threshold` (see the rule above). Throws UserError when the
/// threshold is not > 0.
std::vector<std::int64_t> strategy_cells_per_feature(const std::vector<Feature>& features, double threshold);

/// The strategy id of one feature vector: its grid cell, linearised (feature 0 varies slowest).
/// No features: 0 (one strategy, whatever the threshold). Throws UserError when the vector's size
/// differs from `features` or the threshold is not > 0.
std::int64_t strategy_id(const std::vector<Feature>& features, const std::vector<double>& vector, double threshold);

/// strategy_id of every vector, in order.
std::vector<std::int64_t> strategy_ids(const std::vector<Feature>& features, const std::vector<std::vector<double>>& vectors,
                                       double threshold);

/// Number of distinct strategies among `vectors` (the cells they occupy; 0 if empty). With
/// `success`, only vectors whose flag is true count (sizes must match).
int count_strategies(const std::vector<Feature>& features, const std::vector<std::vector<double>>& vectors, double threshold,
                     const std::vector<bool>* success = nullptr);

/// The ceiling: how many strategies the box [low, high] of feature values can hold (the cells it
/// meets). `low`/`high` are per feature, e.g. the reachable range a pool of trials measured.
int strategy_ceiling(const std::vector<Feature>& features, double threshold, const std::vector<double>& low,
                     const std::vector<double>& high);

/// A task's outcome of parameters x: the feature vector when the trial succeeds, nothing when it
/// fails (e.g. a lookup in a recorded pool).
using Outcome = std::function<std::optional<std::vector<double>>(const std::vector<double>& x)>;

/// Random search's expected number of distinct successful strategies after `samples` uniform
/// draws over `space`, by Monte Carlo over `draws` repetitions (seeded): the baseline a search
/// must beat, beside the ceiling.
double expected_random_count(const std::vector<Feature>& features, double threshold, const Space& space, const Outcome& outcome,
                             int samples, int draws, std::uint64_t seed);

/// Whether a finished trial succeeded by its task's rule: the description's "success", an object
/// {"info": JSON pointer into the result info, "min": number (default 0.5)}, holds when the value
/// there is true or a number ≥ min. No rule (null): every finished trial succeeds. Throws
/// UserError naming the pointer when the rule is malformed.
bool trial_success(const base::Json& rule, const base::Json& info);

}  // namespace podium::search
