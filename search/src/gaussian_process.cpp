#include "gaussian_process.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlopt.hpp>
#include <numbers>

#include "podium/base/error.h"

namespace podium::search {

using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {
const double kSqrt5 = std::sqrt(5.0);

// Matérn 5/2 kernel matrix (without noise) and, optionally, the factor
// s²·5/3·(1 + √5 r)·exp(−√5 r) that turns (Δ_d/ℓ_d)² into ∂k/∂log ℓ_d.
void kernel_matrix(const MatrixXd& x, const VectorXd& theta, MatrixXd& k, MatrixXd* dfactor) {
  const int n = static_cast<int>(x.rows());
  const double s2 = std::exp(theta[0]);
  const VectorXd inv_len = (-theta.segment(1, x.cols()).array()).exp();
  const MatrixXd scaled = x * inv_len.asDiagonal();
  k.resize(n, n);
  if (dfactor) dfactor->resize(n, n);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b <= a; ++b) {
      const double r = (scaled.row(a) - scaled.row(b)).norm();
      const double e = std::exp(-kSqrt5 * r);
      k(a, b) = k(b, a) = s2 * (1.0 + kSqrt5 * r + 5.0 / 3.0 * r * r) * e;
      if (dfactor) (*dfactor)(a, b) = (*dfactor)(b, a) = s2 * 5.0 / 3.0 * (1.0 + kSqrt5 * r) * e;
    }
}
}  // namespace

GaussianProcess::GaussianProcess(int dim, double prior_mean) : dim_(dim), prior_mean_(prior_mean) {
  theta_ = default_theta();
  x_.resize(0, dim);
}

VectorXd GaussianProcess::default_theta() const {
  VectorXd t(dim_ + 2);
  t[0] = 0.0;
  t.segment(1, dim_).setConstant(std::log(0.5));
  t[dim_ + 1] = std::log(1e-4);
  return t;
}

void GaussianProcess::set(const MatrixXd& x, const VectorXd& y, const VectorXd& theta) {
  PODIUM_CHECK(x.cols() == dim_ && x.rows() == y.size() && theta.size() == dim_ + 2, "gp: shape mismatch");
  x_ = x;
  y_ = y;
  theta_ = theta;
  MatrixXd k;
  kernel_matrix(x_, theta_, k, nullptr);
  k.diagonal().array() += std::exp(theta_[dim_ + 1]);
  llt_.compute(k);
  PODIUM_CHECK(llt_.info() == Eigen::Success, "gp: kernel matrix is not positive definite");
  alpha_ = llt_.solve((y_.array() - prior_mean_).matrix());
}

double GaussianProcess::log_marginal_likelihood(const MatrixXd& x, const VectorXd& y, double prior_mean, const VectorXd& theta,
                                                VectorXd* grad) {
  const int n = static_cast<int>(x.rows());
  const int d = static_cast<int>(x.cols());
  MatrixXd k, dfactor;
  kernel_matrix(x, theta, k, grad ? &dfactor : nullptr);
  const double noise = std::exp(theta[d + 1]);
  MatrixXd kn = k;
  kn.diagonal().array() += noise;
  Eigen::LLT<MatrixXd> llt(kn);
  if (llt.info() != Eigen::Success) return -std::numeric_limits<double>::infinity();
  const VectorXd r = (y.array() - prior_mean).matrix();
  const VectorXd alpha = llt.solve(r);
  const MatrixXd& l = llt.matrixLLT();
  // Rasmussen & Williams eq. 5.8: −½ rᵀα − Σ log L_ii − n/2 log 2π.
  const double lml = -0.5 * r.dot(alpha) - l.diagonal().array().log().sum() - 0.5 * n * std::log(2.0 * std::numbers::pi);
  if (grad) {
    // R&W eq. 5.9: ∂/∂θ_j = ½ tr((ααᵀ − K⁻¹) ∂K/∂θ_j).
    const MatrixXd w = alpha * alpha.transpose() - llt.solve(MatrixXd::Identity(n, n));
    grad->setZero(d + 2);
    (*grad)[0] = 0.5 * (w.array() * k.array()).sum();
    (*grad)[d + 1] = 0.5 * noise * w.trace();
    const VectorXd inv_len2 = (-2.0 * theta.segment(1, d).array()).exp();
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < a; ++b) {
        const double c = w(a, b) * dfactor(a, b);  // counted twice (a,b) and (b,a): ½·2 = 1
        for (int j = 0; j < d; ++j) {
          const double delta = x(a, j) - x(b, j);
          (*grad)[1 + j] += c * delta * delta * inv_len2[j];
        }
      }
  }
  return lml;
}

double GaussianProcess::fit(base::Rng& rng, int extra_starts, const GpBounds& bounds, int max_evals) {
  const int p = dim_ + 2;
  std::vector<double> low(p), high(p);
  low[0] = bounds.log_signal_low;
  high[0] = bounds.log_signal_high;
  for (int j = 0; j < dim_; ++j) {
    low[1 + j] = bounds.log_length_low;
    high[1 + j] = bounds.log_length_high;
  }
  low[p - 1] = bounds.log_noise_low;
  high[p - 1] = bounds.log_noise_high;

  struct Context {
    const GaussianProcess* gp;
    VectorXd best;
    double best_value = -std::numeric_limits<double>::infinity();
  } ctx{this, theta_, -std::numeric_limits<double>::infinity()};
  auto objective = [](const std::vector<double>& t, std::vector<double>& g, void* data) {
    auto* c = static_cast<Context*>(data);
    const VectorXd theta = Eigen::Map<const VectorXd>(t.data(), static_cast<Eigen::Index>(t.size()));
    VectorXd grad;
    const double v = log_marginal_likelihood(c->gp->x_, c->gp->y_, c->gp->prior_mean_, theta, g.empty() ? nullptr : &grad);
    if (!std::isfinite(v)) {
      std::fill(g.begin(), g.end(), 0.0);
      return -1e300;
    }
    if (!g.empty())
      for (std::size_t i = 0; i < g.size(); ++i) g[i] = grad[static_cast<Eigen::Index>(i)];
    if (v > c->best_value) {
      c->best_value = v;
      c->best = theta;
    }
    return v;
  };

  std::vector<std::vector<double>> starts;
  std::vector<double> current(theta_.data(), theta_.data() + p);
  for (int j = 0; j < p; ++j) current[j] = std::clamp(current[j], low[j], high[j]);
  starts.push_back(current);
  for (int s = 0; s < extra_starts; ++s) {
    std::vector<double> t(p);
    for (int j = 0; j < p; ++j) t[j] = rng.uniform(low[j], high[j]);
    starts.push_back(t);
  }
  for (auto& t : starts) {
    nlopt::opt opt(nlopt::LD_LBFGS, static_cast<unsigned>(p));
    opt.set_lower_bounds(low);
    opt.set_upper_bounds(high);
    opt.set_max_objective(objective, &ctx);
    opt.set_maxeval(max_evals);
    opt.set_ftol_rel(1e-10);
    opt.set_xtol_rel(1e-8);
    double value = 0.0;
    try {
      opt.optimize(t, value);
    } catch (const std::exception&) {
      // L-BFGS may stop on round-off near the optimum; the best point seen is kept in ctx.
    }
  }
  set(x_, y_, ctx.best);
  return ctx.best_value;
}

void GaussianProcess::predict(const VectorXd& x, double& mean, double& var, VectorXd* dmean, VectorXd* dvar) const {
  const int n = size();
  const double s2 = std::exp(theta_[0]);
  const double noise = std::exp(theta_[dim_ + 1]);
  if (n == 0) {
    mean = prior_mean_;
    var = s2 + noise;
    if (dmean) dmean->setZero(dim_);
    if (dvar) dvar->setZero(dim_);
    return;
  }
  const VectorXd inv_len2 = (-2.0 * theta_.segment(1, dim_).array()).exp();
  VectorXd kx(n);
  MatrixXd dk;  // ∂k(x, x_i)/∂x, n × dim
  if (dmean || dvar) dk.resize(n, dim_);
  for (int i = 0; i < n; ++i) {
    const VectorXd delta = x - x_.row(i).transpose();
    const double r = std::sqrt((delta.array().square() * inv_len2.array()).sum());
    const double e = std::exp(-kSqrt5 * r);
    kx[i] = s2 * (1.0 + kSqrt5 * r + 5.0 / 3.0 * r * r) * e;
    if (dk.size())
      dk.row(i) = (-s2 * 5.0 / 3.0 * (1.0 + kSqrt5 * r) * e) * (delta.array() * inv_len2.array()).matrix().transpose();
  }
  mean = prior_mean_ + kx.dot(alpha_);
  const VectorXd v = llt_.matrixL().solve(kx);
  var = std::max(s2 + noise - v.squaredNorm(), 1e-12);
  if (dmean) *dmean = dk.transpose() * alpha_;
  if (dvar) *dvar = -2.0 * dk.transpose() * llt_.matrixU().solve(v);
}

}  // namespace podium::search
