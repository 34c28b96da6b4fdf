#include "cmaes.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "eigen_helpers.h"
#include "podium/base/config.h"
#include "podium/base/error.h"

namespace podium::search {

using Eigen::MatrixXd;
using Eigen::VectorXd;

CmaesParams CmaesParams::from_json(const Json& config, const Space& space, const std::string& path) {
  base::ConfigReader r(config, path);
  CmaesParams p;
  p.population = r.integer("population", p.population, {0, 100000});
  if (p.population == 1) r.fail("population", "is not 0 (the default size) or >= 2");
  p.sigma0 = r.number("sigma0", p.sigma0, {1e-12, 10.0});
  p.maximize = r.choice("direction", "maximize", {"maximize", "minimize"}) == "maximize";
  p.min_step = r.number("min_step", p.min_step, {0.0, 1.0},
                        "stop once every coordinate's step size σ·√C_ii is under this fraction of its parameter's range "
                        "(0: run to the trial budget)");
  // x0: {parameter name: value} for every parameter of the space, or absent (the box centre).
  if (r.has("x0"))
    p.x0 = r.object("x0", base::required, [&](base::ConfigReader& x0) {
      std::vector<double> x;
      for (const auto& q : space.params) x.push_back(x0.number(q.name, base::required, {q.low, q.high}));
      return x;
    });
  r.finish();
  return p;
}

Cmaes::Cmaes(const SearchSetup& setup, const std::string& json_path)
    : space_(setup.space), params_(CmaesParams::from_json(setup.config, setup.space, json_path + ".config")), rng_(setup.seed) {
  const int n = static_cast<int>(space_.dim());
  if (n == 0) throw base::UserError(json_path + ": cmaes needs a parameter space with at least one parameter");
  // Hansen 2016, Table 1 (default strategy parameters), positive weights only.
  lambda_ = params_.population > 0 ? params_.population : 4 + static_cast<int>(std::floor(3.0 * std::log(n)));
  mu_ = lambda_ / 2;
  weights_.resize(mu_);
  for (int i = 0; i < mu_; ++i) weights_[i] = std::log((lambda_ + 1) / 2.0) - std::log(i + 1.0);
  weights_ /= weights_.sum();
  mu_eff_ = 1.0 / weights_.squaredNorm();
  c_sigma_ = (mu_eff_ + 2.0) / (n + mu_eff_ + 5.0);
  d_sigma_ = 1.0 + 2.0 * std::max(0.0, std::sqrt((mu_eff_ - 1.0) / (n + 1.0)) - 1.0) + c_sigma_;
  c_c_ = (4.0 + mu_eff_ / n) / (n + 4.0 + 2.0 * mu_eff_ / n);
  c_1_ = 2.0 / ((n + 1.3) * (n + 1.3) + mu_eff_);
  c_mu_ = std::min(1.0 - c_1_, 2.0 * (mu_eff_ - 2.0 + 1.0 / mu_eff_) / ((n + 2.0) * (n + 2.0) + mu_eff_));
  chi_n_ = std::sqrt(n) * (1.0 - 1.0 / (4.0 * n) + 1.0 / (21.0 * n * n));

  mean_.setConstant(n, 0.5);
  for (std::size_t i = 0; i < params_.x0.size(); ++i)
    mean_[static_cast<Eigen::Index>(i)] = (params_.x0[i] - space_.params[i].low) / (space_.params[i].high - space_.params[i].low);
  p_sigma_.setZero(n);
  p_c_.setZero(n);
  cov_.setIdentity(n, n);
  sigma_ = params_.sigma0;
  start_generation();
}

void Cmaes::start_generation() {
  const Eigen::Index n = mean_.size();
  Eigen::SelfAdjointEigenSolver<MatrixXd> eig(cov_);
  const MatrixXd bd = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
  samples_.clear();
  for (int k = 0; k < lambda_; ++k) {
    VectorXd u;
    for (int attempt = 0; attempt < 100; ++attempt) {
      VectorXd z(n);
      for (Eigen::Index i = 0; i < n; ++i) z[i] = rng_.normal();
      u = mean_ + sigma_ * bd * z;
      if ((u.array() >= 0.0).all() && (u.array() <= 1.0).all()) break;
    }
    samples_.push_back(u.cwiseMax(0.0).cwiseMin(1.0));
  }
  first_id_ = next_id_;
  asked_ = 0;
  fitness_.clear();
}

std::vector<double> Cmaes::to_params(const VectorXd& u) const { return unit_to_params(space_, u); }

std::vector<double> Cmaes::mean() const { return to_params(mean_); }

std::vector<double> Cmaes::step_sizes() const {
  std::vector<double> out;
  for (Eigen::Index i = 0; i < cov_.rows(); ++i) out.push_back(sigma_ * std::sqrt(std::max(0.0, cov_(i, i))));
  return out;
}

std::vector<Proposal> Cmaes::ask(std::size_t n) {
  std::vector<Proposal> out;
  while (out.size() < n && asked_ < samples_.size()) {
    Proposal p;
    p.id = next_id_++;
    p.x = to_params(samples_[asked_++]);
    p.info = {{"generation", generation_}};
    out.push_back(std::move(p));
  }
  return out;
}

void Cmaes::tell(const std::vector<Observation>& observations) {
  for (const auto& o : observations) {
    if (o.id < first_id_ || o.id >= first_id_ + asked_ || fitness_.count(o.id))
      throw base::UserError(name() + ": tell() got id " + std::to_string(o.id) +
                            ", which is not a pending proposal (never asked or already told)");
    if (o.ok && o.objectives.empty())
      throw base::UserError(name() + ": trial " + std::to_string(o.id) + " reported no objective; cmaes needs objectives[0]");
    double f = std::numeric_limits<double>::infinity();  // failed trials rank last
    if (o.ok && std::isfinite(o.objectives[0])) f = params_.maximize ? -o.objectives[0] : o.objectives[0];
    fitness_[o.id] = f;
  }
  if (fitness_.size() == samples_.size()) {
    update();
    ++generation_;
    const std::vector<double> steps = step_sizes();
    stopped_ = params_.min_step > 0.0 && *std::max_element(steps.begin(), steps.end()) < params_.min_step;
    if (stopped_) {  // converged: nothing more to ask
      samples_.clear();
      first_id_ = next_id_;
      asked_ = 0;
      fitness_.clear();
    } else {
      start_generation();
    }
  }
}

void Cmaes::update() {
  const Eigen::Index n = mean_.size();
  std::vector<int> order(lambda_);
  for (int k = 0; k < lambda_; ++k) order[k] = k;
  // Ties (e.g. failures) keep sample order, so the update is deterministic.
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return fitness_.at(first_id_ + a) < fitness_.at(first_id_ + b); });
  MatrixXd y(n, mu_);  // selected steps (x_i:λ − m) / σ, eq. (39)
  for (int i = 0; i < mu_; ++i) y.col(i) = (samples_[order[i]] - mean_) / sigma_;
  const VectorXd y_w = y * weights_;
  mean_ += sigma_ * y_w;  // eq. (41), c_m = 1

  Eigen::SelfAdjointEigenSolver<MatrixXd> eig(cov_);
  const VectorXd inv_sqrt = eig.eigenvalues().cwiseMax(1e-300).cwiseSqrt().cwiseInverse();
  const MatrixXd c_inv_sqrt = eig.eigenvectors() * inv_sqrt.asDiagonal() * eig.eigenvectors().transpose();
  p_sigma_ = (1.0 - c_sigma_) * p_sigma_ + std::sqrt(c_sigma_ * (2.0 - c_sigma_) * mu_eff_) * c_inv_sqrt * y_w;  // eq. (43)
  const double norm = p_sigma_.norm();
  const double correction = std::sqrt(1.0 - std::pow(1.0 - c_sigma_, 2.0 * static_cast<double>(generation_ + 1)));
  const bool h_sigma = norm / correction < (1.4 + 2.0 / (static_cast<double>(n) + 1.0)) * chi_n_;
  p_c_ = (1.0 - c_c_) * p_c_ + (h_sigma ? std::sqrt(c_c_ * (2.0 - c_c_) * mu_eff_) : 0.0) * y_w;  // eq. (45)
  const double delta_h = h_sigma ? 0.0 : c_c_ * (2.0 - c_c_);
  cov_ = (1.0 + c_1_ * delta_h - c_1_ - c_mu_) * cov_ + c_1_ * p_c_ * p_c_.transpose() +
         c_mu_ * y * weights_.asDiagonal() * y.transpose();  // eq. (47)
  cov_ = 0.5 * (cov_ + cov_.transpose());
  sigma_ *= std::exp(c_sigma_ / d_sigma_ * (norm / chi_n_ - 1.0));  // eq. (44)
}

Json Cmaes::save() const {
  Json cov = Json::array(), samples = Json::array(), fitness = Json::array();
  for (Eigen::Index i = 0; i < cov_.rows(); ++i) cov.push_back(vector_json(cov_.row(i).transpose()));
  for (const auto& s : samples_) samples.push_back(vector_json(s));
  // Failed trials' +inf is not JSON: store null.
  for (const auto& [id, f] : fitness_) fitness.push_back({id, std::isfinite(f) ? Json(f) : Json(nullptr)});
  return {{"rng", rng_.save()},
          {"mean", vector_json(mean_)},
          {"p_sigma", vector_json(p_sigma_)},
          {"p_c", vector_json(p_c_)},
          {"cov", cov},
          {"sigma", sigma_},
          {"generation", generation_},
          {"next_id", next_id_},
          {"first_id", first_id_},
          {"samples", samples},
          {"asked", asked_},
          {"fitness", fitness},
          {"stopped", stopped_},
          {"step_sizes", step_sizes()},
          {"result", result()}};
}

// What the search has found so far, in the parameters' units (the store's summary shows it; load()
// ignores it): the distribution's mean and covariance σ²·C scaled by each parameter's range, its
// per-parameter step sizes, the generations done, whether the step-size stop fired.
Json Cmaes::result() const {
  const std::size_t n = space_.dim();
  Json mean = Json::object(), steps = Json::object(), cov = Json::array();
  const std::vector<double> m = this->mean(), s = step_sizes();
  for (std::size_t i = 0; i < n; ++i) {
    const double range_i = space_.params[i].high - space_.params[i].low;
    mean[space_.params[i].name] = m[i];
    steps[space_.params[i].name] = s[i] * range_i;
    Json row = Json::array();
    for (std::size_t j = 0; j < n; ++j)
      row.push_back(sigma_ * sigma_ * cov_(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) * range_i *
                    (space_.params[j].high - space_.params[j].low));
    cov.push_back(row);
  }
  return {{"algorithm", "cmaes"},       {"mean", mean},       {"covariance", cov}, {"step_sizes", steps},
          {"generations", generation_}, {"stopped", stopped_}};
}

void Cmaes::load(const Json& state) {
  rng_.load(state.at("rng").get<std::string>());
  mean_ = vector_from(state.at("mean"));
  p_sigma_ = vector_from(state.at("p_sigma"));
  p_c_ = vector_from(state.at("p_c"));
  const auto& cov = state.at("cov");
  cov_.resize(mean_.size(), mean_.size());
  for (Eigen::Index i = 0; i < cov_.rows(); ++i) cov_.row(i) = vector_from(cov.at(static_cast<std::size_t>(i))).transpose();
  sigma_ = state.at("sigma").get<double>();
  generation_ = state.at("generation").get<std::uint64_t>();
  next_id_ = state.at("next_id").get<std::uint64_t>();
  first_id_ = state.at("first_id").get<std::uint64_t>();
  samples_.clear();
  for (const auto& s : state.at("samples")) samples_.push_back(vector_from(s));
  asked_ = state.at("asked").get<std::size_t>();
  stopped_ = state.value("stopped", false);  // states saved before the stop existed ran on
  fitness_.clear();
  for (const auto& f : state.at("fitness"))
    fitness_[f.at(0).get<std::uint64_t>()] = f.at(1).is_null() ? std::numeric_limits<double>::infinity() : f.at(1).get<double>();
  PODIUM_CHECK(mean_.size() == static_cast<Eigen::Index>(space_.dim()), "cmaes: saved state has a different dimension");
}

}  // namespace podium::search
