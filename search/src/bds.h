#pragma once
// Bayesian Diversity Search (thesis §3.5.1, Algorithm 1), batched.
//
// One GP per feature dimension (gaussian_process.h) over the parameter box scaled to [0,1]^d,
// fitted on the successful trials (see "Failed samples" below); features scaled to [0,1] by their declared range, prior mean 0.5
// (the middle of the range, "GP Priors and Kernels" of §3.6.1). Exploration steps take x = argmax Σ_j σ_j(x) (eqs. 3.9–3.10,
// NLopt L-BFGS from the best of random candidates); diversity steps maximise the diversity acquisition by NLopt DIRECT-L
// (Algorithm 1 line 7).
//
// Diversity acquisition (`acquisition`, default "auto"): the thesis's eq. 3.7,
// E_{f ~ N(μ(x), σ²(x))}[min_i ‖f − f_i‖] by Monte Carlo with common random numbers over the
// posterior, wherever a feature is continuous. Only where the task declares every feature
// quantised (Feature::quantised: a few exact levels, like a plateau landscape) does "auto" pick
// "new combination": how likely x's features, each read as the nearest level that feature has
// taken, form a combination no trial has shown. On levels eq. 3.7 rewards predictions between two
// observed values, which a GP smoothing a staircase makes on every boundary; on a continuous
// feature every observed value would be its own level, so "new combination" is constant where
// there is one feature (every level is a strategy) and exact-equality-new where there are more:
// that is why it is never the default there. Eq. 3.7, scaled small, breaks its ties, so it is
// never flat. Both use the per-feature metric of strategies.h (angles wrap).
//
// Schedules (`schedule`). "thesis": Algorithm 1 as written — `initial_samples` uniform random
// proposals, then rounds of N_exp = `n_explore` exploration and N_opt = `n_diversity` diversity
// steps (3 and 3, §3.6.2), one at a time. "adaptive" (the default): a maximin initial design,
// exploration until `explore_until` points, then diversity steps; after `stall` diversity steps
// in a row whose results brought no new strategy, exploration steps follow until one finds a new
// strategy (at most `stall_explore`), then diversity steps resume. A result is a new strategy when
// the task counts it a success and its feature lies farther than the stage's strategy threshold
// from every earlier success (the threshold the store's strategies use, strategies.h), so a
// noisy repeat of a known strategy is a repeat.
// Failed samples (`failures`, default "model"). Algorithm 1 has no notion of failure: every
// sample's f_{t+1} = g(x_{t+1}) joins F_t and the GP (lines 9–11), and §3.7.1 only reports that
// of 10 samples "the other four generated either repetitions or failures". Its aim is "a set of
// representatives ... such that the corresponding feature set F_n has a large diversity" of
// strategies that "complete the task" (§3.5), and a failure completes nothing. So where a task
// declares a success rule and a trial fails it, BDS reads the thesis's objective as the diversity
// of successful features: (1) the feature GPs model g on successful trials only (a jump that did
// not clear has an up-angle, but not one of a strategy), and failed points enter them as
// believers, so no step proposes them again; (2) eq. 3.7's targets f_i are the successful
// features (a failure claims no strategy); (3) eq. 3.7 is the expected distance *if* x yields a
// strategy, and a failure adds nothing to F, so a diversity step maximises p(x)·a(x), with p the
// posterior mean, clipped to [0.01, 1], of a GP fitted to the 0/1 success labels of every told
// trial (prior mean their success rate): the expected diversity gained, as constrained Bayesian
// optimisation weighs expected improvement by the probability of feasibility (Gelbart, Snoek &
// Adams 2014); (4) an exploration step likewise maximises p(x)·Σ_j σ_j(x), as a failure observes
// nothing of g on successes (`explore_success_weight`; measured on landscapes with failure regions,
// tasks/landscape/RESULTS.md). Until a trial succeeds, proposals stay the initial design. While every told trial
// succeeded this is exactly the thesis's step (p ≡ 1). "ignore" is Algorithm 1 read literally.
// Batches (ask(n) with n > 1, or proposals still running): pending points enter the GPs as
// "believers" with their posterior mean as value (σ collapses there; their predicted feature joins
// the observed ones as a strategy already claimed), so a batch spreads out instead of repeating one
// point. The thesis is sequential (one trial at a time, Algorithm 1 line 9): with one worker and
// ask(1) there are no believers. Failed trials stay out of the fitted model but are believers too
// (with "ignore", only trials that failed outright), so the search does not propose them again.
#include <map>
#include <optional>

#include "gaussian_process.h"
#include "podium/base/rng.h"
#include "podium/search/search.h"

namespace podium::search {

/// BDS options (spec: search.config). Defaults are the thesis's where it gives one (eq. 3.7 on
/// continuous features, eq. 3.9–3.10 exploration, the §3.6.1 prior), except the schedule: a maximin
/// initial design, exploration until 10 points, then diversity steps with a fall-back to
/// exploration when they stall, which measured best on the plateau landscapes
/// (experiments/search/LOG.md); `"schedule": "thesis"` is Algorithm 1's fixed rounds of 3 and 3.
/// Other acquisitions, short-range plateau snapping, plateau believers and between-candidates
/// measured no better there and were removed; that README says where they live in history.
struct BdsParams {
  int initial_samples = 4;  ///< random proposals before the GP is used (Algorithm 1 line 2)
  /// How the initial samples are drawn: "random" (uniform) or "maximin" (the farthest from all
  /// earlier proposals of `explore_candidates` uniform points: random, but spread out). Default
  /// "maximin", or "random" under the thesis schedule.
  std::string initial_design = "maximin";
  /// "adaptive" or "thesis" (see the header comment).
  std::string schedule = "adaptive";
  int n_explore = 3;    ///< thesis schedule: N_exp exploration steps per round (§3.6.2: 3)
  int n_diversity = 3;  ///< thesis schedule: N_opt diversity steps per round (§3.6.2: 3)
  /// Diversity-step acquisition: "auto" (eq. 3.7 unless every feature is declared quantised, then
  /// "new_combination"), "expected_distance" (the thesis's eq. 3.7) or "new_combination":
  /// 1 − P(x repeats an observed strategy), where each feature's posterior N(μ_j(x), σ_j²(x)) is
  /// split into the cells of the values that feature has taken (every value reads as its nearest
  /// observed one; distinct values are levels) and an observed strategy is its tuple of levels:
  /// P = Σ_strategies Π_j P(f_j(x) in its level's cell), in closed form, plus eq. 3.7 × 10⁻³ (in
  /// units of the feature box's diagonal) to break ties where no combination is new.
  std::string acquisition = "auto";
  /// Exploration schedule: while fewer than this many points are told or pending, every GP step
  /// explores (max σ); diversity steps start after. A GP fitted to few plateau
  /// observations predicts features poorly, so early diversity steps aim worse than max σ.
  int explore_until = 10;
  /// Self-correcting schedule (see above): after `stall` consecutive diversity steps whose results
  /// brought no new strategy, up to `stall_explore` exploration steps, ending early when one finds
  /// a new strategy. "New": a success farther than the strategy threshold from every earlier
  /// success (SearchSetup::strategy_threshold). Results count in tell order, pending ones once
  /// told; a failed trial brings no new strategy. `stall` 0 never falls back (diversity steps only).
  int stall = 4;
  int stall_explore = 1;
  int mc_samples = 64;           ///< Monte-Carlo draws for eq. 3.7 (acquisition "expected_distance")
  int explore_candidates = 256;  ///< random points scored before L-BFGS
  int explore_starts = 5;        ///< L-BFGS starts (the best candidates)
  int direct_evals = 800;        ///< DIRECT-L evaluations per diversity step
  int fit_starts = 2;            ///< random hyperparameter starts besides the previous optimum
  /// Observations a GP needs before its hyperparameters are fitted; 0: one more than it has
  /// hyperparameters (dim + 3). Until then it keeps the defaults (signal 1, length 0.5, noise
  /// 10⁻⁴). Maximum likelihood on fewer points is degenerate: on one success it can explain the
  /// feature as noise, σ is then flat over the box, and a success-weighted exploration step
  /// proposes that success again.
  int fit_min_points = 0;
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
  double noise_min = 1e-3;  ///< lower bound of the GP noise variance η² (features scaled to [0,1])
  /// Trials that do not succeed (the task's success rule said no, or the trial failed outright;
  /// see the header comment "Failed samples"): "model" (default) keeps them out of the feature GPs
  /// and the diversity targets (a failure is no strategy) and weighs the diversity acquisition by
  /// a GP model of the probability of success; "ignore" treats a finished failure as any sample
  /// (Algorithm 1 read literally: its feature joins the GPs and the targets).
  std::string failures = "model";
  /// With failures "model": weigh exploration steps (eq. 3.9's Σ_j σ_j) by the success
  /// probability too, so exploration stops spending samples where trials fail.
  bool explore_success_weight = true;
  static BdsParams from_json(const Json& config, const std::string& path);
};

/// Thesis eq. 3.7 by Monte Carlo: the mean over the rows ε_s of `eps` (standard normal draws, one
/// column per feature) of min_i feature_distance(μ + σ ⊙ ε_s, targets_i). Features in their own
/// units. Exposed for the closed-form test.
double expected_nearest_distance(const std::vector<Feature>& features, const std::vector<double>& mean,
                                 const std::vector<double>& sigma, const std::vector<std::vector<double>>& targets,
                                 const Eigen::MatrixXd& eps);

class BayesianDiversitySearch final : public Search {
 public:
  BayesianDiversitySearch(const SearchSetup& setup, const std::string& json_path);
  std::string name() const override { return "bds"; }
  std::vector<Proposal> ask(std::size_t n) override;
  void tell(const std::vector<Observation>& observations) override;
  Json save() const override;
  void load(const Json& state) override;
  /// The diversity acquisition the next diversity step would maximise, at points u of [0,1]^d
  /// (for tests and benchmarks; draws its Monte Carlo numbers from the search's RNG).
  std::vector<double> diversity_values(const std::vector<Eigen::VectorXd>& us);
  /// The acquisition "auto" resolved for this task's features.
  const std::string& acquisition() const { return acquisition_; }

 private:
  struct Pending {
    Eigen::VectorXd u;  // parameters scaled to [0,1]^d
    std::string step;   // "initial", "explore" or "diversity"
  };
  struct Told {
    std::uint64_t id;
    Eigen::VectorXd u;  // parameters scaled to [0,1]^d
    bool ok;
    std::vector<double> features;  // raw feature values (empty when failed)
    bool success = true;           // the task's success rule (a strategy only if true)
  };
  Eigen::VectorXd propose(std::string& step);
  Eigen::VectorXd initial_point();
  void fit_if_needed();
  std::vector<GaussianProcess> conditioned_gps(std::vector<std::vector<double>>& believer_features) const;
  Eigen::VectorXd explore(const std::vector<GaussianProcess>& gps);
  Eigen::VectorXd diversify(const std::vector<GaussianProcess>& gps, const std::vector<std::vector<double>>& targets);
  bool is_new_strategy(const Observation& o) const;
  std::vector<std::vector<double>> diversity_targets(const std::vector<std::vector<double>>& believer_features) const;
  bool modelled(const Told& t) const { return params_.failures == "model" ? t.success : t.ok; }
  bool success_modelled() const;
  std::optional<GaussianProcess> success_model() const;
  std::vector<double> to_params(const Eigen::VectorXd& u) const;
  Eigen::VectorXd to_unit(const std::vector<double>& x) const;

  Space space_;
  std::vector<Feature> features_;
  BdsParams params_;
  std::string acquisition_;  // params_.acquisition with "auto" resolved
  double threshold_ = 0.0;   // the strategy threshold, in feature units
  GpBounds bounds_;
  base::Rng rng_;
  std::uint64_t next_id_ = 0;
  std::size_t fitted_on_ = 0;           // successful observations the hyperparameters were fitted on
  std::vector<Eigen::VectorXd> theta_;  // per feature GP hyperparameters
  Eigen::VectorXd theta_success_;       // the success model's hyperparameters
  std::size_t success_fitted_on_ = 0;   // told trials the success model was fitted on
  int stalled_ = 0;                     // consecutive told diversity steps without a new strategy
  int fallback_left_ = 0;               // exploration steps left since the diversity steps stalled
  std::uint64_t gp_steps_ = 0;          // proposals after the initial ones (the thesis schedule's t)
  std::map<std::uint64_t, Pending> pending_;
  std::vector<Told> told_;
};

}  // namespace podium::search
