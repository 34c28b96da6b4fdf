#pragma once
/// The ask/tell contract every search algorithm implements (docs/architecture.md "Search algorithms").
///
/// - ask(n) returns up to n new proposals, each with a stage-unique id (0, 1, 2, ...) that the
///   orchestrator uses as the trial index. It may return fewer than n (or none) when the
///   algorithm must wait for results or has nothing left to propose.
/// - tell() takes finished observations by id; an id never asked, or told twice, is a UserError.
///   Failed trials are told with ok = false so the algorithm can keep them out of its model
///   without stalling.
/// - save()/load() round-trip the whole state, RNG included: load(save()) followed by ask()
///   proposes exactly what the original would have. The orchestrator stores save() after every
///   ask and every tell, in the same transaction as the trials they concern.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "podium/base/json.h"
#include "podium/search/space.h"

namespace podium::search {

using base::Json;

struct Proposal {
  std::uint64_t id = 0;           ///< stage-unique, dense from 0; becomes the trial index
  std::vector<double> x;          ///< parameters, inside the space's bounds
  Json context = Json::object();  ///< extra input for the task (e.g. features to be novel against)
  Json info = Json::object();     ///< why this point was proposed (e.g. {"step": "explore"})
  /// Which of SearchSetup::inputs the proposal is for (novel-policy seeking); a stage whose
  /// trials each get one input hands this one to the trial. Unset: the orchestrator's default.
  std::optional<std::size_t> input;
};

struct Observation {
  std::uint64_t id = 0;
  bool ok = false;                 ///< false: the trial failed; objectives/features are empty
  std::vector<double> objectives;  ///< as returned by the task; objectives[0] is the primary one
  std::vector<double> features;    ///< strategy feature vector, sized as the task declares
  /// The task's success rule (search/strategies.h trial_success): a finished trial that missed the
  /// task's goal (a jump that did not clear) is ok with features but no strategy.
  bool success = true;
  /// Where the trial ran when that is not its proposal (a task that looks results up at the
  /// nearest recorded point, tasks/pool): parameters inside the space's bounds, in its order. A
  /// search that models results over the parameters (BDS) models them here; empty: the proposal.
  std::vector<double> x = {};
};

/// Observation::x from a trial's result info: its "evaluated_params" (one number per parameter, in
/// the space's order), which a task that looks results up reports (tasks/pool); else empty.
std::vector<double> evaluated_params(const Json& info);

class Search {
 public:
  virtual ~Search() = default;
  virtual std::string name() const = 0;
  virtual std::vector<Proposal> ask(std::size_t n) = 0;
  virtual void tell(const std::vector<Observation>& observations) = 0;
  virtual Json save() const = 0;
  virtual void load(const Json& state) = 0;
};

/// Everything a search is built from; all of it is stored with the stage.
struct SearchSetup {
  Space space;                    ///< parameter box the search proposes in
  std::vector<Feature> features;  ///< the task's strategy features (for diversity searches)
  Json config = Json::object();   ///< the algorithm's config from the spec
  std::uint64_t seed = 0;
  /// Feature distance within which two results are one strategy (the stage's strategy_threshold;
  /// 0: 5% of the feature box's diagonal).
  double strategy_threshold = 0.0;
  /// The trials of earlier stages handed to this stage (resolved when it starts), each
  /// {"stage", "stage_index", "trial_index", "params", "objectives", "features", "strategy",
  /// "artifacts": {name: absolute path}, "info": the trial's result info}. Every algorithm accepts them; novel-policy seeking
  /// needs at least one and seeks novel policies for each.
  Json inputs = Json::array();
};

/// Names of the algorithms make_search knows, e.g. {"random", ...}.
std::vector<std::string> algorithm_names();

/// Builds a search; throws base::UserError naming `json_path` (e.g. "stages[0].search") when the
/// algorithm is unknown or its config is invalid.
std::unique_ptr<Search> make_search(const std::string& algorithm, const SearchSetup& setup,
                                    const std::string& json_path = "search");

/// The submit-time check of a stage's search, before its inputs exist (they are resolved when
/// the stage starts; `setup.inputs` is ignored): the algorithm name and its config, and for an
/// algorithm that needs inputs, that the stage declares some (`has_inputs`). Throws
/// base::UserError naming `json_path`, as make_search does.
void check_search(const std::string& algorithm, const SearchSetup& setup, bool has_inputs,
                  const std::string& json_path = "search");

}  // namespace podium::search
