// The GP against scikit-learn and its analytic gradients against finite
// differences. scikit-learn runs as a subprocess on data drawn here, so nothing is hard-coded.
#include "gaussian_process.h"

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <filesystem>
#include <fstream>

#include "podium/base/json.h"
#include "process.h"

namespace podium::search {
namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

struct Problem {
  MatrixXd x, x_test;
  VectorXd y, theta;
  double prior_mean = 0.5;
};

Problem random_problem(std::uint64_t seed, int n, int d) {
  base::Rng rng(seed);
  Problem p;
  p.x.resize(n, d);
  p.y.resize(n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < d; ++j) p.x(i, j) = rng.uniform();
    p.y[i] = 0.5 + 0.3 * std::sin(4.0 * p.x(i, 0)) + 0.2 * p.x(i, d - 1) * p.x(i, d - 1) + rng.normal(0.0, 0.02);
  }
  p.x_test.resize(15, d);
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < d; ++j) p.x_test(i, j) = rng.uniform(-0.2, 1.2);
  p.theta.resize(d + 2);
  p.theta[0] = std::log(rng.uniform(0.05, 2.0));
  for (int j = 0; j < d; ++j) p.theta[1 + j] = std::log(rng.uniform(0.1, 1.5));
  p.theta[d + 1] = std::log(rng.uniform(1e-4, 1e-2));
  return p;
}

base::Json matrix_json(const MatrixXd& m) {
  base::Json out = base::Json::array();
  for (int i = 0; i < m.rows(); ++i) {
    std::vector<double> row(m.cols());
    for (int j = 0; j < m.cols(); ++j) row[j] = m(i, j);
    out.push_back(row);
  }
  return out;
}

// Runs tests/search/gp_reference.py; returns null when scikit-learn is unavailable.
base::Json sklearn_reference(const Problem& p, const GpBounds& b, int restarts, const std::string& tag) {
  const auto input = std::filesystem::temp_directory_path() / ("podium_gp_reference_" + tag + ".json");
  base::Json j = {{"x", matrix_json(p.x)},
                  {"y", std::vector<double>(p.y.data(), p.y.data() + p.y.size())},
                  {"prior_mean", p.prior_mean},
                  {"theta", std::vector<double>(p.theta.data(), p.theta.data() + p.theta.size())},
                  {"x_test", matrix_json(p.x_test)},
                  {"bounds",
                   {{"signal", {b.log_signal_low, b.log_signal_high}},
                    {"length", {b.log_length_low, b.log_length_high}},
                    {"noise", {b.log_noise_low, b.log_noise_high}}}},
                  {"restarts", restarts}};
  std::ofstream(input) << j.dump();
  const std::string command = std::string(PODIUM_PYTHON) + " " + PODIUM_GP_REFERENCE + " " + input.string();
  const auto [status, out] = podium::testing::shell(command);
  std::filesystem::remove(input);
  // 3: the script found no scikit-learn; 127: no python3 at all.
  if (WIFEXITED(status) && (WEXITSTATUS(status) == 3 || WEXITSTATUS(status) == 127)) return nullptr;
  EXPECT_EQ(status, 0) << command << " printed: " << out;
  return base::Json::parse(out);
}

double relative_error(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-12); }

TEST(GaussianProcess, MatchesScikitLearnPosteriorAndLikelihood) {
  for (std::uint64_t seed : {1u, 2u, 3u}) {
    const Problem p = random_problem(seed, 20 + 5 * static_cast<int>(seed), 1 + static_cast<int>(seed));
    const GpBounds bounds;
    const base::Json ref = sklearn_reference(p, bounds, 5, std::to_string(seed));
    if (ref.is_null()) GTEST_SKIP() << "python3 with scikit-learn not available (" << PODIUM_PYTHON << ")";
    GaussianProcess gp(static_cast<int>(p.x.cols()), p.prior_mean);
    gp.set(p.x, p.y, p.theta);
    const double lml = GaussianProcess::log_marginal_likelihood(p.x, p.y, p.prior_mean, p.theta, nullptr);
    EXPECT_LT(relative_error(lml, ref["lml"].get<double>()), 1e-6) << lml << " vs " << ref["lml"];
    for (int i = 0; i < p.x_test.rows(); ++i) {
      double mean = 0.0, var = 0.0;
      gp.predict(p.x_test.row(i).transpose(), mean, var);
      EXPECT_LT(relative_error(mean, ref["mean"][i].get<double>()), 1e-6) << "seed " << seed << " point " << i;
      EXPECT_LT(relative_error(std::sqrt(var), ref["std"][i].get<double>()), 1e-6) << "seed " << seed << " point " << i;
    }
    // Fitting on: our optimum is no worse than scikit-learn's (6 L-BFGS runs each).
    base::Rng rng(seed);
    const double fitted = gp.fit(rng, 5, bounds);
    std::printf("seed %d: fitted log marginal likelihood %.6f (scikit-learn %.6f)\n", static_cast<int>(seed), fitted,
                ref["fitted_lml"].get<double>());
    EXPECT_GE(fitted, ref["fitted_lml"].get<double>() - 1e-3) << "seed " << seed;
    EXPECT_NEAR(fitted, GaussianProcess::log_marginal_likelihood(p.x, p.y, p.prior_mean, gp.theta(), nullptr), 1e-12);
  }
}

TEST(GaussianProcess, LikelihoodGradientMatchesFiniteDifferences) {
  const Problem p = random_problem(7, 30, 3);
  VectorXd grad;
  GaussianProcess::log_marginal_likelihood(p.x, p.y, p.prior_mean, p.theta, &grad);
  for (int j = 0; j < p.theta.size(); ++j) {
    const double h = 1e-6;
    VectorXd plus = p.theta, minus = p.theta;
    plus[j] += h;
    minus[j] -= h;
    const double fd = (GaussianProcess::log_marginal_likelihood(p.x, p.y, p.prior_mean, plus, nullptr) -
                       GaussianProcess::log_marginal_likelihood(p.x, p.y, p.prior_mean, minus, nullptr)) /
                      (2 * h);
    EXPECT_NEAR(grad[j], fd, 1e-5 * std::max(1.0, std::abs(fd))) << "theta[" << j << "]";
  }
}

TEST(GaussianProcess, PredictionGradientsMatchFiniteDifferences) {
  const Problem p = random_problem(8, 20, 3);
  GaussianProcess gp(3, p.prior_mean);
  gp.set(p.x, p.y, p.theta);
  for (int i = 0; i < 5; ++i) {
    const VectorXd x = p.x_test.row(i).transpose();
    double mean, var;
    VectorXd dmean, dvar;
    gp.predict(x, mean, var, &dmean, &dvar);
    for (int j = 0; j < 3; ++j) {
      const double h = 1e-6;
      VectorXd plus = x, minus = x;
      plus[j] += h;
      minus[j] -= h;
      double mp, vp, mm, vm;
      gp.predict(plus, mp, vp);
      gp.predict(minus, mm, vm);
      EXPECT_NEAR(dmean[j], (mp - mm) / (2 * h), 1e-5);
      EXPECT_NEAR(dvar[j], (vp - vm) / (2 * h), 1e-5);
    }
  }
}

}  // namespace
}  // namespace podium::search
