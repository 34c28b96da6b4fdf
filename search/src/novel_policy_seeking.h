#pragma once
// Novel-policy seeking (thesis §3.5.2, eq. 3.12), as a campaign stage over an earlier stage's
// results: for each input (one initial state, e.g. one distinct strategy of Stage 1) it runs
// `trials_per_input` trials in sequence at that input's parameters. Each trial's context carries
// the features of the policies already found for that input (the input's own when its stage has
// the same features, then each finished trial's), so the task can multiply its reward by
//   r_novelty(f) = clip(min_j ‖f − f_j‖ / d_threshold, 0.01, 1),
// and a warm-start checkpoint (the input's artifact named `warm_start_artifact`, or null).
// Context: {"novelty": {"features": [[...], ...], "d_threshold": d}, "warm_start": path | null};
// Proposal::input names the input, so a stage handing one input per trial hands that one.
// Inputs run in parallel with each other; within one input the next trial waits for the previous
// one. A failed trial uses up its iteration (it found no feature to add).
#include <map>
#include <set>

#include "podium/search/search.h"

namespace podium::search {

struct NovelPolicyParams {
  int trials_per_input = 5;                    ///< K: the thesis's 5 iterations per initial state
  double d_threshold = 1.5707963267948966;     ///< eq. 3.12's d_threshold (thesis: π/2)
  std::string warm_start_artifact = "policy";  ///< which input artifact to warm-start from
  static NovelPolicyParams from_json(const Json& config, const std::string& path);
};

class NovelPolicySeeking final : public Search {
 public:
  NovelPolicySeeking(const SearchSetup& setup, const std::string& json_path);
  std::string name() const override { return "novel_policy"; }
  std::vector<Proposal> ask(std::size_t n) override;
  void tell(const std::vector<Observation>& observations) override;
  Json save() const override;
  void load(const Json& state) override;

 private:
  struct Input {
    std::vector<double> x;
    Json warm_start;  // artifact path or null
    std::uint64_t source_trial = 0;
    std::vector<std::vector<double>> found;  // features of the policies found so far (saved)
    int asked = 0;                           // trials proposed so far (saved)
    bool busy = false;                       // a trial is running (saved)
  };
  Space space_;
  std::vector<Feature> features_;
  NovelPolicyParams params_;
  std::vector<Input> inputs_;
  std::uint64_t next_id_ = 0;
  std::map<std::uint64_t, std::size_t> pending_;  // id → input index
};

}  // namespace podium::search
