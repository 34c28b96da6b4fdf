#pragma once
// CMA-ES as an ask/tell search (Hansen, "The CMA Evolution Strategy: A Tutorial", 2016; used for
// the sprint's dip finish, sprint seed §3.3): full covariance, weighted recombination of the best
// μ = ⌊λ/2⌋ of λ samples, cumulative step-size adaptation (CSA), rank-one and rank-μ covariance
// updates. Works in the parameter box scaled to [0,1]^d; a sample outside the box is redrawn (up
// to 100 times, then clipped), as python-cmaes does. Hand-written: Debian ships no C++ CMA-ES.
//
// A generation's λ samples are drawn when it starts; ask(n) hands out the ones not yet asked
// (fewer, or none, while the generation waits for results) and the update runs once all λ are
// told. A failed trial ranks last.
//
// Stop (Hansen 2016, App. B "TolX"): after a generation's update, when every coordinate's step
// size σ·√C_ii in the unit box is under `min_step` (a fraction of each parameter's range; 1% by
// default, 0 never), the search has converged: ask() proposes nothing more, so the stage ends
// before its trial budget. The final mean (mean()) and covariance are the result.
#include <Eigen/Core>
#include <map>

#include "podium/base/rng.h"
#include "podium/search/search.h"

namespace podium::search {

struct CmaesParams {
  int population = 0;      ///< λ; 0 = 4 + ⌊3 ln d⌋ (Hansen's default)
  double sigma0 = 0.3;     ///< initial step size as a fraction of each parameter's range
  std::vector<double> x0;  ///< initial mean in parameter units; empty = the centre of the box
  bool maximize = true;    ///< objectives[0] is maximised ("direction": "maximize"), or minimised
  /// Stop once every coordinate's step size σ·√C_ii is under this fraction of its parameter's
  /// range (after a generation's update); 0 never stops before the budget.
  double min_step = 0.01;
  static CmaesParams from_json(const Json& config, const Space& space, const std::string& path);
};

class Cmaes final : public Search {
 public:
  Cmaes(const SearchSetup& setup, const std::string& json_path);
  std::string name() const override { return "cmaes"; }
  std::vector<Proposal> ask(std::size_t n) override;
  void tell(const std::vector<Observation>& observations) override;
  Json save() const override;
  void load(const Json& state) override;
  /// The current mean in parameter units (the recommended point).
  std::vector<double> mean() const;
  /// Each coordinate's step size σ·√C_ii as a fraction of its parameter's range.
  std::vector<double> step_sizes() const;
  /// Whether the step-size stop has fired (ask() then proposes nothing).
  bool stopped() const { return stopped_; }
  /// The state's "result" (save()): mean, covariance and step sizes in parameter units, the
  /// generations done and the stop — the search's answer (the sprint's dip strategy, §3.3).
  Json result() const;

 private:
  void start_generation();  // draws the λ samples from N(m, σ² C)
  void update();            // Hansen 2016, eqs. (39)–(47)
  std::vector<double> to_params(const Eigen::VectorXd& u) const;

  Space space_;
  CmaesParams params_;
  int lambda_ = 0, mu_ = 0;
  Eigen::VectorXd weights_;
  double mu_eff_ = 0, c_sigma_ = 0, d_sigma_ = 0, c_c_ = 0, c_1_ = 0, c_mu_ = 0, chi_n_ = 0;
  // State (saved): distribution, paths, generation, this generation's samples and results.
  base::Rng rng_;
  Eigen::VectorXd mean_, p_sigma_, p_c_;
  Eigen::MatrixXd cov_;
  double sigma_ = 0;
  std::uint64_t generation_ = 0, next_id_ = 0, first_id_ = 0;  // first_id_: id of sample 0 of this generation
  std::vector<Eigen::VectorXd> samples_;                       // unit-box points of this generation
  std::size_t asked_ = 0;
  bool stopped_ = false;                     // the step-size stop fired: no more generations
  std::map<std::uint64_t, double> fitness_;  // told ids of this generation → fitness to minimise
};

}  // namespace podium::search
