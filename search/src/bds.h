#pragma once
// Bayesian Diversity Search (thesis §3.5.1, Algorithm 1), batched.
//
// One GP per feature dimension (gaussian_process.h) over the parameter box scaled to [0,1]^d,
// fitted on the successful trials; features scaled to [0,1] by their declared range, prior mean
// 0.5 (the middle of the range, §3.6.1). After `initial_samples` random proposals (spread out by
// default) and exploration steps, x = argmax Σ_j σ_j(x) (eqs. 3.9–3.10, NLopt L-BFGS from the best
// of random candidates), until `explore_until` points, diversity steps optimised by NLopt DIRECT-L.
// The thesis alternates fixed rounds of N_exp exploration and N_opt diversity steps (Algorithm 1
// line 4); here the schedule corrects itself instead: after `stall` diversity steps in a row whose
// results brought no new strategy, exploration steps follow until one finds a new strategy (at
// most `stall_explore`), then diversity steps resume. On plateau landscapes unseen level
// combinations keep paying off, so diversity steps continue; on Voronoi-like landscapes they stop
// paying off once the few cells are found, and the search falls back to exploration, which is
// what finds the small cells left. The diversity acquisition departs from the
// thesis by default: eq. 3.7's E[min_i ‖f(x) − f_i‖] rewards predictions between two observed
// plateau values, which a GP smoothing a staircase makes everywhere on a boundary; "new
// combination" asks instead how likely x's features, each read as the nearest value that feature
// has taken so far, form a combination no trial has shown (experiments/search/LOG.md measures both).
// Eq. 3.7 stays selectable (Monte Carlo with common random numbers over the posterior). Both use
// the per-feature metric of strategies.h (angles wrap).
// Batches (ask(n) with n > 1, or proposals still running): pending points enter the GPs as
// "believers" with their posterior mean as value (σ collapses there; their predicted feature joins
// the observed ones as a strategy already claimed), so a batch spreads out instead of repeating one
// point. Failed trials stay out of the fitted model but are believers too, so the search does not
// propose them again.
#include <map>

#include "gaussian_process.h"
#include "podium/base/rng.h"
#include "podium/search/search.h"

namespace podium::search {

/// BDS options (spec: search.config). Defaults are the thesis's where it gives one, except the
/// diversity acquisition ("new_combination", see above) and the schedule: a maximin initial design,
/// exploration until 10 points, then diversity steps with a fall-back to exploration when they
/// stall (thesis: fixed rounds of 3 and 3), which measured best on the plateau landscapes
/// (experiments/search/LOG.md). Other acquisitions, short-range plateau snapping, plateau believers
/// and between-candidates measured no better there and were removed (one way to do each thing);
/// that README says where they live in history.
struct BdsParams {
  int initial_samples = 4;       ///< random proposals before the GP is used (Algorithm 1 line 2)
  /// How the initial samples are drawn: "random" (uniform) or "maximin" (the farthest from all
  /// earlier proposals of `explore_candidates` uniform points: random, but spread out).
  std::string initial_design = "maximin";
  /// Diversity-step acquisition. "new_combination": 1 − P(x repeats an observed strategy), where
  /// each feature's posterior N(μ_j(x), σ_j²(x)) is split into the cells of the values that feature
  /// has taken (every value reads as its nearest observed one; distinct values are levels) and an
  /// observed strategy is its tuple of levels: P = Σ_strategies Π_j P(f_j(x) in its level's cell),
  /// in closed form. On plateau features it counts the level combinations not yet seen, not the
  /// distance to them. "expected_distance": the thesis's eq. 3.7.
  std::string acquisition = "new_combination";
  /// Exploration schedule: while fewer than this many points are told or pending, every GP step
  /// explores (max σ); diversity steps start after. A GP fitted to few plateau
  /// observations predicts features poorly, so early diversity steps aim worse than max σ.
  int explore_until = 10;
  /// Self-correcting schedule (see above): after `stall` consecutive diversity steps whose results
  /// brought no new strategy, up to `stall_explore` exploration steps, ending early when one finds
  /// a new strategy. "New" is the acquisition's own definition: a feature vector no earlier
  /// successful trial had, i.e. an unseen level combination (no distance threshold: on features
  /// that never repeat a value every result is new and the fall-back never fires). Results count
  /// in tell order, pending ones once told; a failed trial brings no new strategy. `stall` 0 never
  /// falls back (diversity steps only).
  int stall = 4;
  int stall_explore = 1;
  int mc_samples = 64;           ///< Monte-Carlo draws for eq. 3.7 (acquisition "expected_distance")
  int explore_candidates = 256;  ///< random points scored before L-BFGS
  int explore_starts = 5;        ///< L-BFGS starts (the best candidates)
  int direct_evals = 800;        ///< DIRECT-L evaluations per diversity step
  int fit_starts = 2;            ///< random hyperparameter starts besides the previous optimum
  /// Thesis eq. 3.8: the diversity acquisition plus β·Σ_j σ_j(x) (σ in feature units), so diversity
  /// steps keep some of the exploration's spread. 0 is the thesis's choice (pure eq. 3.7).
  double ucb_beta = 0.0;
  /// GP length-scale bounds, in units of each parameter's range. The thesis learns eq. 3.17's λ
  /// freely (§3.6.1); the bounds are ours. They regularise the fit on the few, piecewise-constant
  /// observations BDS starts from (maximum likelihood otherwise picks ℓ → 100 for a dimension after
  /// 10 points). The upper bound 0.5 (half the box) found +0.3 strategies at 20 evaluations over
  /// 1.0 on the plateau landscapes (experiments/search/LOG.md; why was not diagnosed); a smaller cap, a
  /// lower-bound change, a log-normal prior on ℓ (MAP) or length scales shared by the feature GPs
  /// gave no more.
  double length_scale_min = 0.1;
  double length_scale_max = 0.5;
  double noise_min = 1e-3;         ///< lower bound of the GP noise variance η² (features scaled to [0,1])
  static BdsParams from_json(const Json& config, const std::string& path);
};

class BayesianDiversitySearch final : public Search {
 public:
  BayesianDiversitySearch(const SearchSetup& setup, const std::string& json_path);
  std::string name() const override { return "bds"; }
  std::vector<Proposal> ask(std::size_t n) override;
  void tell(const std::vector<Observation>& observations) override;
  Json save() const override;
  void load(const Json& state) override;

 private:
  struct Pending {
    Eigen::VectorXd u;  // parameters scaled to [0,1]^d
    std::string step;   // "initial", "explore" or "diversity"
  };
  struct Told {
    std::uint64_t id;
    Eigen::VectorXd u;               // parameters scaled to [0,1]^d
    bool ok;
    std::vector<double> features;   // raw feature values (empty when failed)
  };
  Eigen::VectorXd propose(std::string& step);
  Eigen::VectorXd initial_point();
  void fit_if_needed();
  std::vector<GaussianProcess> conditioned_gps(std::vector<std::vector<double>>& believer_features) const;
  Eigen::VectorXd explore(const std::vector<GaussianProcess>& gps);
  Eigen::VectorXd diversify(const std::vector<GaussianProcess>& gps, const std::vector<std::vector<double>>& targets);
  std::vector<double> to_params(const Eigen::VectorXd& u) const;
  Eigen::VectorXd to_unit(const std::vector<double>& x) const;

  Space space_;
  std::vector<Feature> features_;
  BdsParams params_;
  GpBounds bounds_;
  base::Rng rng_;
  std::uint64_t next_id_ = 0;
  std::size_t fitted_on_ = 0;          // successful observations the hyperparameters were fitted on
  std::vector<Eigen::VectorXd> theta_; // per feature GP hyperparameters
  int stalled_ = 0;                    // consecutive told diversity steps without a new strategy
  int fallback_left_ = 0;              // exploration steps left since the diversity steps stalled
  std::map<std::uint64_t, Pending> pending_;
  std::vector<Told> told_;
};

}  // namespace podium::search
