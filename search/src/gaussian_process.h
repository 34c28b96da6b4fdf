#pragma once
// Gaussian-process regression of one scalar output (thesis §3.5.1 eq. 3.6, §3.6.1 eq. 3.17):
//   k(x, x') = s² (1 + √5 r + 5/3 r²) exp(−√5 r),   r² = Σ_d (x_d − x'_d)² / ℓ_d²   (Matérn 5/2, ARD)
//   μ(x) = m + k(X, x)ᵀ (K + η² I)⁻¹ (y − m),       σ²(x) = s² + η² − k(X, x)ᵀ (K + η² I)⁻¹ k(X, x)
// with a constant prior mean m (the middle of the feature's range). Hyperparameters θ =
// [log s², log ℓ_1..ℓ_d, log η²] (scikit-learn's order for C·Matern + White) maximise the log
// marginal likelihood, with analytic gradients, by NLopt L-BFGS from several starts.
// Hand-written on Eigen: no Debian C++ library offers GP regression.
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>

#include "podium/base/rng.h"

namespace podium::search {

/// Box on θ for fitting, in log space.
struct GpBounds {
  double log_signal_low = std::log(1e-3), log_signal_high = std::log(1e2);
  double log_length_low = std::log(1e-2), log_length_high = std::log(1e2);
  double log_noise_low = std::log(1e-6), log_noise_high = std::log(1e0);
};

class GaussianProcess {
 public:
  GaussianProcess(int dim, double prior_mean);
  int dim() const { return dim_; }
  int size() const { return static_cast<int>(y_.size()); }
  /// Default θ: s² = 1, ℓ = 0.5 (inputs live in the unit box), η² = 1e-4.
  Eigen::VectorXd default_theta() const;
  /// Sets data (n × dim) and θ, and factorises K + η² I. Throws nothing; a non-positive-definite
  /// matrix (impossible with η² ≥ 1e-6 unless points repeat exactly many times) is a PODIUM_CHECK.
  void set(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, const Eigen::VectorXd& theta);
  const Eigen::VectorXd& theta() const { return theta_; }
  const Eigen::MatrixXd& x() const { return x_; }
  const Eigen::VectorXd& y() const { return y_; }

  /// log p(y | X, θ) and, if `grad` is given, its gradient with respect to θ.
  static double log_marginal_likelihood(const Eigen::MatrixXd& x, const Eigen::VectorXd& y, double prior_mean,
                                        const Eigen::VectorXd& theta, Eigen::VectorXd* grad);
  /// Maximises the log marginal likelihood from `theta()` and `extra_starts` random starts inside
  /// `bounds` (drawn from `rng`), then set()s the best θ. Returns its log marginal likelihood.
  double fit(base::Rng& rng, int extra_starts, const GpBounds& bounds, int max_evals = 200);

  /// Posterior mean and variance (observation noise included, as in eq. 3.6) at x; with
  /// `dmean`/`dvar` also their gradients with respect to x.
  void predict(const Eigen::VectorXd& x, double& mean, double& var, Eigen::VectorXd* dmean = nullptr,
               Eigen::VectorXd* dvar = nullptr) const;

 private:
  int dim_;
  double prior_mean_;
  Eigen::MatrixXd x_;
  Eigen::VectorXd y_, theta_, alpha_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
};

}  // namespace podium::search
