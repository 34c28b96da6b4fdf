#pragma once
// Bayesian Diversity Search (thesis §3.5.1, Algorithm 1), batched.
//
// One GP per feature dimension (gaussian_process.h) over the parameter box scaled to [0,1]^d,
// fitted on the successful trials; features scaled to [0,1] by their declared range, prior mean
// 0.5 (the middle of the range, §3.6.1). After `initial_samples` random proposals (spread out by
// default) and exploration steps until `explore_until` points, rounds of n_exp exploration steps,
// x = argmax Σ_j σ_j(x) (eqs. 3.9–3.10, NLopt L-BFGS from the best of random candidates), and
// n_opt diversity steps, x = argmax E[min_i ‖f(x) − f_i‖] (eq. 3.7, Monte Carlo with common
// random numbers over the posterior, NLopt DIRECT-L), with the per-feature metric of strategies.h
// (angles wrap).
// Batches (ask(n) with n > 1, or proposals still running): pending points enter the GPs as
// "believers" with their posterior mean as value (σ collapses there; their predicted feature joins
// the f_i of eq. 3.7), so a batch spreads out instead of repeating one point. Failed trials stay
// out of the fitted model but are believers too, so the search does not propose them again.
#include <map>

#include "gaussian_process.h"
#include "podium/base/rng.h"
#include "podium/search/search.h"

namespace podium::search {

/// BDS options (spec: search.config). Defaults are the thesis's where it gives one, plus a
/// schedule in front of Algorithm 1's rounds (maximin initial design, exploration until 10
/// points), which measured best on the issue-5 landscapes (bench/search/README.md). The other
/// acquisition variants, `snap`, plateau believers, between-candidates and `ucb_beta` were measured
/// not to help there and stay selectable for tasks whose features behave differently.
struct BdsParams {
  int initial_samples = 4;       ///< random proposals before the GP is used (Algorithm 1 line 2)
  /// How the initial samples are drawn: "random" (uniform) or "maximin" (the farthest from all
  /// earlier proposals of `explore_candidates` uniform points: random, but spread out).
  std::string initial_design = "maximin";
  int n_exp = 3;                 ///< exploration steps per round (thesis: 3)
  int n_opt = 3;                 ///< diversity steps per round (thesis: 3)
  /// Exploration schedule: while fewer than this many points are told or pending, every GP step
  /// explores (max σ); the N_exp/N_opt rounds start after. A GP fitted to few plateau
  /// observations predicts features poorly, so early diversity steps aim worse than max σ.
  int explore_until = 10;
  int mc_samples = 64;           ///< Monte-Carlo draws for eq. 3.7
  int explore_candidates = 256;  ///< random points scored before L-BFGS
  int explore_starts = 5;        ///< L-BFGS starts (the best candidates)
  int direct_evals = 800;        ///< DIRECT-L evaluations per diversity step
  int fit_starts = 2;            ///< random hyperparameter starts besides the previous optimum
  /// Diversity acquisition: "expected_distance" (eq. 3.7, E[min_i ‖f − f_i‖]), "capped_distance"
  /// (E[min(min_i ‖f − f_i‖, τ)]), "new_strategy" (P(min_i ‖f − f_i‖ > τ)), τ = strategy_threshold, or
  /// "plateau_new_strategy": P(new strategy) under a predictive that knows features are flat in
  /// regions: feature j at x is one of the observed values, voted by the GP's kernel weights
  /// k_j(x, x_i) (Nadaraya–Watson), with the share of prior variance the GP has explained at x,
  /// 1 − σ_j²(x)/(s_j² + η_j²); the rest is an unseen value. So a point between two observed
  /// plateaus is predicted to be on one of them (not on the in-between mean value eq. 3.7 rewards),
  /// a point between (a0, a1) and (b0, b1) may be the unseen mix (a0, b1), and far from data every
  /// point is new (exploration by the GP's own length scales).
  std::string acquisition = "expected_distance";
  /// Thesis eq. 3.8: the diversity acquisition plus β·Σ_j σ_j(x) (σ in feature units), so diversity
  /// steps keep some of the exploration's spread. 0 is the thesis's choice (pure eq. 3.7).
  double ucb_beta = 0.0;
  /// GP length-scale bounds, in units of each parameter's range. Regularises the fit on the few,
  /// piecewise-constant observations BDS starts from (maximum likelihood otherwise picks ℓ → 100 for
  /// a dimension after 10 points); measured effect in bench/search/README.md.
  double length_scale_min = 0.1;
  double length_scale_max = 1.0;
  double noise_min = 1e-3;         ///< lower bound of the GP noise variance η² (features scaled to [0,1])
  double strategy_threshold = 0.05;  ///< τ, in feature units (the stage's distinct-strategy threshold)
  /// Plateau snapping: a posterior sample of feature j within τ of a value observed for feature j
  /// counts as that value (observed values within τ are one plateau), so a point between two
  /// plateaus is predicted to be on one of them, not on an in-between value that may not exist.
  bool snap = false;
  /// How far (feature units) a sample may be from an observed value to snap to it; 0 means τ.
  /// Plateaus are wider than τ in feature value when levels are coarse, as on tasks/landscape.
  double snap_tolerance = 0.0;
  /// Flat-region recognition: two observations among each other's `plateau_neighbours` nearest (in
  /// the unit box), within `plateau_radius` and with the same value of feature j, imply a plateau of
  /// feature j between them: that feature's GP is conditioned on a virtual observation of the value
  /// at their midpoint (not fitted on), so σ collapses there and no step aims at it. 0 turns it off.
  int plateau_neighbours = 0;
  double plateau_radius = 0.3;
  /// Candidate generation for diversity steps: features are continuous in x, so new strategies lie
  /// between observations of different strategies. Besides DIRECT-L's optimum, the acquisition is
  /// scored at 1/3, 1/2 and 2/3 of the way from each observation to each of its `between_neighbours`
  /// nearest observations of a different strategy (feature distance > τ), and the best point wins.
  int between_neighbours = 0;
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
  std::vector<std::pair<Eigen::VectorXd, double>> plateau_points(std::size_t feature) const;
  Eigen::VectorXd explore(const std::vector<GaussianProcess>& gps);
  Eigen::VectorXd diversify(const std::vector<GaussianProcess>& gps, const std::vector<std::vector<double>>& targets);
  std::vector<Eigen::VectorXd> between_candidates() const;
  std::vector<double> to_params(const Eigen::VectorXd& u) const;
  Eigen::VectorXd to_unit(const std::vector<double>& x) const;

  Space space_;
  std::vector<Feature> features_;
  BdsParams params_;
  GpBounds bounds_;
  base::Rng rng_;
  std::uint64_t next_id_ = 0;
  std::uint64_t steps_ = 0;            // GP-guided proposals made (selects explore vs diversity)
  std::size_t fitted_on_ = 0;          // successful observations the hyperparameters were fitted on
  std::vector<Eigen::VectorXd> theta_; // per feature GP hyperparameters
  std::map<std::uint64_t, Eigen::VectorXd> pending_;
  std::vector<Told> told_;
};

}  // namespace podium::search
