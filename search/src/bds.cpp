#include "bds.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlopt.hpp>
#include <numbers>
#include <set>

#include "eigen_helpers.h"
#include "podium/base/config.h"
#include "podium/base/error.h"
#include "podium/search/strategies.h"

namespace podium::search {

using Eigen::MatrixXd;
using Eigen::VectorXd;

BdsParams BdsParams::from_json(const Json& config, const std::string& path) {
  base::ConfigReader r(config, path);
  BdsParams p;
  p.initial_samples = r.integer("initial_samples", p.initial_samples, {1, 100000});
  p.schedule = r.choice("schedule", p.schedule, {"adaptive", "thesis"});
  if (p.schedule == "thesis") p.initial_design = "random";  // Algorithm 1 line 2
  p.initial_design = r.choice("initial_design", p.initial_design, {"random", "maximin"});
  p.n_explore = r.integer("n_explore", p.n_explore, {0, 1000000});
  p.n_diversity = r.integer("n_diversity", p.n_diversity, {0, 1000000});
  if (p.n_explore + p.n_diversity == 0)
    throw base::UserError(path + ".n_diversity: n_explore and n_diversity are both 0; a round needs at least one step");
  p.acquisition = r.choice("acquisition", p.acquisition, {"auto", "new_combination", "expected_distance"});
  p.explore_until = r.integer("explore_until", p.explore_until, {0, 1000000});
  p.stall = r.integer("stall", p.stall, {0, 1000000});
  p.stall_explore = r.integer("stall_explore", p.stall_explore, {1, 1000000});
  p.mc_samples = r.integer("mc_samples", p.mc_samples, {1, 100000});
  p.explore_candidates = r.integer("explore_candidates", p.explore_candidates, {1, 1000000});
  p.explore_starts = r.integer("explore_starts", p.explore_starts, {1, 1000});
  p.direct_evals = r.integer("direct_evals", p.direct_evals, {10, 10000000});
  p.fit_starts = r.integer("fit_starts", p.fit_starts, {0, 1000});
  p.fit_min_points = r.integer("fit_min_points", p.fit_min_points, {0, 1000000});
  p.ucb_beta = r.number("ucb_beta", p.ucb_beta, {0.0, 1e6});
  p.length_scale_min = r.number("length_scale_min", p.length_scale_min, {1e-6, 1e6});
  p.length_scale_max = r.number("length_scale_max", p.length_scale_max, {p.length_scale_min, 1e6});
  p.noise_min = r.number("noise_min", p.noise_min, {1e-9, 0.5});
  p.failures = r.choice("failures", p.failures, {"model", "ignore"});
  p.explore_success_weight = r.boolean("explore_success_weight", p.explore_success_weight);
  r.finish();
  return p;
}

BayesianDiversitySearch::BayesianDiversitySearch(const SearchSetup& setup, const std::string& json_path)
    : space_(setup.space),
      features_(setup.features),
      params_(BdsParams::from_json(setup.config, json_path + ".config")),
      rng_(setup.seed) {
  if (space_.dim() == 0) throw base::UserError(json_path + ": bds needs a parameter space with at least one parameter");
  if (features_.empty()) throw base::UserError(json_path + ": bds needs the task to declare at least one feature");
  for (const auto& f : features_)
    if (!(f.low < f.high))
      throw base::UserError(json_path + ": feature \"" + f.name + "\" has an empty range [" + std::to_string(f.low) + ", " +
                            std::to_string(f.high) + "]; bds scales features by it");
  acquisition_ = params_.acquisition;
  if (acquisition_ == "auto")
    acquisition_ = std::all_of(features_.begin(), features_.end(), [](const Feature& f) { return f.quantised; })
                       ? "new_combination"
                       : "expected_distance";
  threshold_ = setup.strategy_threshold;
  if (!(threshold_ > 0.0)) {  // the orchestrator's default (campaigns.cpp): 5% of the feature box's diagonal
    double diagonal = 0.0;
    for (const auto& f : features_) diagonal += (f.high - f.low) * (f.high - f.low);
    threshold_ = 0.05 * std::sqrt(diagonal);
  }
  bounds_.log_length_low = std::log(params_.length_scale_min);
  bounds_.log_length_high = std::log(params_.length_scale_max);
  bounds_.log_noise_low = std::log(params_.noise_min);
  const GaussianProcess prototype(static_cast<int>(space_.dim()), 0.5);
  theta_.assign(features_.size(), prototype.default_theta());
  theta_success_ = prototype.default_theta();
}

std::vector<double> BayesianDiversitySearch::to_params(const VectorXd& u) const { return unit_to_params(space_, u); }

VectorXd BayesianDiversitySearch::to_unit(const std::vector<double>& x) const {
  VectorXd u(static_cast<Eigen::Index>(x.size()));
  for (std::size_t i = 0; i < x.size(); ++i)
    u[static_cast<Eigen::Index>(i)] = (x[i] - space_.params[i].low) / (space_.params[i].high - space_.params[i].low);
  return u;
}

std::vector<Proposal> BayesianDiversitySearch::ask(std::size_t n) {
  std::vector<Proposal> out;
  for (std::size_t k = 0; k < n; ++k) {
    Proposal p;
    std::string step;
    const VectorXd u = propose(step);
    p.id = next_id_++;
    p.x = to_params(u);
    p.info = {{"step", step}};
    pending_[p.id] = {to_unit(p.x), step};
    out.push_back(std::move(p));
  }
  return out;
}

VectorXd BayesianDiversitySearch::propose(std::string& step) {
  // The GPs need a modelled trial (with failures "model": a success); until then, the initial design.
  const bool any_data = std::any_of(told_.begin(), told_.end(), [&](const Told& t) { return modelled(t); });
  if (next_id_ < static_cast<std::uint64_t>(params_.initial_samples) || !any_data) {
    step = "initial";
    return initial_point();
  }
  fit_if_needed();
  std::vector<std::vector<double>> believer_features;
  const auto gps = conditioned_gps(believer_features);
  const std::uint64_t t = gp_steps_++;
  if (params_.schedule == "thesis") {
    // Algorithm 1 line 4: t % (N_exp + N_opt) < N_exp explores.
    if (t % static_cast<std::uint64_t>(params_.n_explore + params_.n_diversity) < static_cast<std::uint64_t>(params_.n_explore)) {
      step = "explore";
      return explore(gps);
    }
  } else if (told_.size() + pending_.size() < static_cast<std::size_t>(params_.explore_until) || fallback_left_ > 0) {
    if (told_.size() + pending_.size() >= static_cast<std::size_t>(params_.explore_until)) --fallback_left_;
    step = "explore";
    return explore(gps);
  }
  step = "diversity";
  return diversify(gps, diversity_targets(believer_features));
}

// The features a diversity step must keep away from (eq. 3.7's f_i): the modelled trials' (with
// failures "model" the strategies found; with "ignore" every finished trial's) and the pending
// believers' predictions.
std::vector<std::vector<double>> BayesianDiversitySearch::diversity_targets(
    const std::vector<std::vector<double>>& believer_features) const {
  std::vector<std::vector<double>> targets = believer_features;
  for (const auto& t : told_)
    if (modelled(t)) targets.push_back(t.features);
  return targets;
}

// The success model is used once a told trial has failed (failures "model"); before, p ≡ 1.
bool BayesianDiversitySearch::success_modelled() const {
  return params_.failures == "model" && std::any_of(told_.begin(), told_.end(), [](const Told& t) { return !t.success; });
}

// "Failed samples" in bds.h: a GP on every told trial's 0/1 success label, prior mean their rate.
std::optional<GaussianProcess> BayesianDiversitySearch::success_model() const {
  if (!success_modelled()) return std::nullopt;
  const int d = static_cast<int>(space_.dim());
  MatrixXd x(static_cast<Eigen::Index>(told_.size()), d);
  VectorXd y(x.rows());
  for (std::size_t i = 0; i < told_.size(); ++i) {
    x.row(static_cast<Eigen::Index>(i)) = told_[i].u.transpose();
    y[static_cast<Eigen::Index>(i)] = told_[i].success ? 1.0 : 0.0;
  }
  GaussianProcess gp(d, y.mean());
  gp.set(x, y, theta_success_);
  return gp;
}

VectorXd BayesianDiversitySearch::initial_point() {
  const int d = static_cast<int>(space_.dim());
  const int candidates = params_.initial_design == "maximin" ? params_.explore_candidates : 1;
  VectorXd best;
  double best_distance = -1.0;
  for (int c = 0; c < candidates; ++c) {
    VectorXd u(d);
    for (int i = 0; i < d; ++i) u[i] = rng_.uniform();
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& t : told_) nearest = std::min(nearest, (u - t.u).norm());
    for (const auto& [id, p] : pending_) nearest = std::min(nearest, (u - p.u).norm());
    if (nearest > best_distance) {
      best_distance = nearest;
      best = u;
    }
  }
  return best;
}

void BayesianDiversitySearch::fit_if_needed() {
  const std::size_t min_points = params_.fit_min_points > 0 ? static_cast<std::size_t>(params_.fit_min_points) : space_.dim() + 3;
  if (success_modelled() && told_.size() != success_fitted_on_ && told_.size() >= min_points) {
    auto gp = *success_model();
    gp.fit(rng_, params_.fit_starts, bounds_);
    theta_success_ = gp.theta();
    success_fitted_on_ = told_.size();
  }
  std::vector<const Told*> ok;
  for (const auto& t : told_)
    if (modelled(t)) ok.push_back(&t);
  if (ok.size() == fitted_on_ || ok.size() < min_points) return;
  const int d = static_cast<int>(space_.dim());
  MatrixXd x(static_cast<Eigen::Index>(ok.size()), d);
  for (std::size_t i = 0; i < ok.size(); ++i) x.row(static_cast<Eigen::Index>(i)) = ok[i]->u.transpose();
  for (std::size_t j = 0; j < features_.size(); ++j) {
    VectorXd y(x.rows());
    for (std::size_t i = 0; i < ok.size(); ++i)
      y[static_cast<Eigen::Index>(i)] = (ok[i]->features[j] - features_[j].low) / (features_[j].high - features_[j].low);
    GaussianProcess gp(d, 0.5);
    gp.set(x, y, theta_[j]);
    gp.fit(rng_, params_.fit_starts, bounds_);
    theta_[j] = gp.theta();
  }
  fitted_on_ = ok.size();
}

std::vector<GaussianProcess> BayesianDiversitySearch::conditioned_gps(std::vector<std::vector<double>>& believer_features) const {
  const int d = static_cast<int>(space_.dim());
  std::vector<VectorXd> xs, believers;
  for (const auto& t : told_) (modelled(t) ? xs : believers).push_back(t.u);
  const std::size_t failed = believers.size();
  for (const auto& [id, p] : pending_) believers.push_back(p.u);
  believer_features.assign(believers.size() - failed, std::vector<double>(features_.size()));

  std::vector<GaussianProcess> gps;
  for (std::size_t j = 0; j < features_.size(); ++j) {
    const double range = features_[j].high - features_[j].low;
    const auto n_known = static_cast<Eigen::Index>(xs.size());
    const auto n_all = n_known + static_cast<Eigen::Index>(believers.size());
    MatrixXd x(n_all, d);
    VectorXd y(n_all);
    Eigen::Index i = 0;
    for (const auto& t : told_)
      if (modelled(t)) {
        x.row(i) = t.u.transpose();
        y[i++] = (t.features[j] - features_[j].low) / range;
      }
    for (const auto& u : believers) x.row(i++) = u.transpose();
    GaussianProcess base(d, 0.5);
    base.set(x.topRows(n_known), y.head(n_known), theta_[j]);
    for (std::size_t b = 0; b < believers.size(); ++b) {
      double mean = 0.0, var = 0.0;
      base.predict(believers[b], mean, var);
      y[n_known + static_cast<Eigen::Index>(b)] = mean;
      if (b >= failed) believer_features[b - failed][j] = features_[j].low + mean * range;
    }
    GaussianProcess gp(d, 0.5);
    gp.set(x, y, theta_[j]);
    gps.push_back(std::move(gp));
  }
  return gps;
}

namespace {
constexpr double kMinSuccessProbability = 0.01;  // keeps the acquisition informative where p is ~0 everywhere

// p(u) of "Failed samples" (bds.h): the success model's posterior mean clipped to [0.01, 1] (1
// without a model), with its gradient (0 where clipped).
double success_probability(const GaussianProcess* success, const VectorXd& u, VectorXd* grad) {
  if (grad) grad->setZero(u.size());
  if (!success) return 1.0;
  double mean = 0.0, var = 0.0;
  VectorXd dmean;
  success->predict(u, mean, var, grad ? &dmean : nullptr);
  if (grad && mean > kMinSuccessProbability && mean < 1.0) *grad = dmean;
  return std::clamp(mean, kMinSuccessProbability, 1.0);
}

struct ExploreContext {
  const std::vector<GaussianProcess>* gps;
  const GaussianProcess* success;  // weighs the step (explore_success_weight), or null
};

// Eq. 3.9 summed over feature dimensions: Σ_j σ_j(u), times p(u) when weighted, with its gradient
// for L-BFGS.
double total_sigma(const ExploreContext& c, const VectorXd& u, VectorXd* grad) {
  double total = 0.0;
  if (grad) grad->setZero(u.size());
  for (const auto& gp : *c.gps) {
    double mean = 0.0, var = 0.0;
    VectorXd dvar;
    gp.predict(u, mean, var, nullptr, grad ? &dvar : nullptr);
    const double sigma = std::sqrt(var);
    total += sigma;
    if (grad) *grad += dvar / (2.0 * sigma);
  }
  if (!c.success) return total;
  VectorXd dp;
  const double p = success_probability(c.success, u, grad ? &dp : nullptr);
  if (grad) *grad = p * *grad + total * dp;
  return p * total;
}
}  // namespace

VectorXd BayesianDiversitySearch::explore(const std::vector<GaussianProcess>& gps) {
  const int d = static_cast<int>(space_.dim());
  const auto success = params_.explore_success_weight ? success_model() : std::nullopt;
  ExploreContext ctx{&gps, success ? &*success : nullptr};
  std::vector<std::pair<double, VectorXd>> candidates;
  for (int c = 0; c < params_.explore_candidates; ++c) {
    VectorXd u(d);
    for (int i = 0; i < d; ++i) u[i] = rng_.uniform();
    candidates.emplace_back(total_sigma(ctx, u, nullptr), u);
  }
  std::stable_sort(candidates.begin(), candidates.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  candidates.resize(std::min<std::size_t>(candidates.size(), static_cast<std::size_t>(params_.explore_starts)));

  VectorXd best = candidates.front().second;
  double best_value = candidates.front().first;
  auto objective = [](const std::vector<double>& x, std::vector<double>& g, void* data) {
    const auto* c = static_cast<const ExploreContext*>(data);
    const VectorXd u = Eigen::Map<const VectorXd>(x.data(), static_cast<Eigen::Index>(x.size()));
    VectorXd grad;
    const double v = total_sigma(*c, u, g.empty() ? nullptr : &grad);
    for (std::size_t i = 0; i < g.size(); ++i) g[i] = grad[static_cast<Eigen::Index>(i)];
    return v;
  };
  for (const auto& [value, start] : candidates) {
    nlopt::opt opt(nlopt::LD_LBFGS, static_cast<unsigned>(d));
    opt.set_lower_bounds(std::vector<double>(d, 0.0));
    opt.set_upper_bounds(std::vector<double>(d, 1.0));
    opt.set_max_objective(objective, &ctx);
    opt.set_maxeval(100);
    opt.set_xtol_rel(1e-6);
    std::vector<double> x(start.data(), start.data() + d);
    double v = value;
    try {
      opt.optimize(x, v);
    } catch (const std::exception&) {
      // Round-off stops keep the last iterate; it is re-scored below.
    }
    const VectorXd u = Eigen::Map<const VectorXd>(x.data(), d).cwiseMax(0.0).cwiseMin(1.0);
    const double score = total_sigma(ctx, u, nullptr);
    if (score > best_value) {
      best_value = score;
      best = u;
    }
  }
  return best;
}

namespace {
// Levels of one feature: the distinct values it has taken, each owning the cell of values nearest
// to it (on the circle for angular features).
struct Levels {
  std::vector<double> low, high;  // cell bounds, in feature units (−∞/+∞ at the ends of a Euclidean feature)
};

struct DiversityContext {
  const std::vector<GaussianProcess>* gps;
  const std::vector<Feature>* features;
  double ucb_beta;
  // eq. 3.7 (both acquisitions: "new_combination" breaks its ties with it):
  const std::vector<std::vector<double>>* targets;
  const MatrixXd* eps;                       // mc_samples × features: common random numbers for every x
  double tie_scale = 0.0;                    // "new_combination": eq. 3.7's weight (10⁻³ / the feature box's diagonal)
  const GaussianProcess* success = nullptr;  // failures "model" after a failure: weighs by p(u)
  // "new_combination":
  std::vector<Levels> levels = {};                    // per feature
  std::vector<std::vector<std::size_t>> tuples = {};  // distinct observed strategies as level indices
};

double wrap_angle(double a) {
  a = std::fmod(a, 2.0 * std::numbers::pi);
  return a < 0.0 ? a + 2.0 * std::numbers::pi : a;
}

Levels make_levels(const Feature& f, std::vector<double> values) {
  const bool angular = f.metric == FeatureMetric::angular;
  if (angular)
    for (auto& v : values) v = wrap_angle(v);
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
  Levels l;
  const std::size_t m = values.size();
  const double inf = std::numeric_limits<double>::infinity(), period = 2.0 * std::numbers::pi;
  for (std::size_t a = 0; a < m; ++a) {
    if (angular && m == 1) {
      l.low.push_back(values[a] - 0.5 * period);
      l.high.push_back(values[a] + 0.5 * period);
      continue;
    }
    const double prev = a > 0 ? values[a - 1] : angular ? values[m - 1] - period : -inf;
    const double next = a + 1 < m ? values[a + 1] : angular ? values[0] + period : inf;
    l.low.push_back(std::isinf(prev) ? prev : 0.5 * (prev + values[a]));
    l.high.push_back(std::isinf(next) ? next : 0.5 * (values[a] + next));
  }
  return l;
}

// Index of the level whose cell holds v.
std::size_t level_of(const Feature& f, const Levels& l, double v) {
  const bool angular = f.metric == FeatureMetric::angular;
  if (angular) v = wrap_angle(v);
  for (std::size_t a = 0; a < l.low.size(); ++a)
    for (double shift : {0.0, 2.0 * std::numbers::pi, -2.0 * std::numbers::pi})
      if ((shift == 0.0 || angular) && v + shift >= l.low[a] && v + shift < l.high[a]) return a;
  return l.low.size() - 1;  // round-off at the seam of an angular feature's last cell
}

// P(low ≤ f < high) for f ~ N(mean, σ²); on a circle, the mass of every 2π copy of the cell.
double cell_mass(bool angular, double mean, double sigma, double low, double high) {
  const double scale = std::max(sigma, 1e-12) * std::numbers::sqrt2;
  auto cdf = [&](double z) { return 0.5 * std::erfc(-(z - mean) / scale); };
  if (!angular) return cdf(high) - cdf(low);
  const double period = 2.0 * std::numbers::pi;
  double mass = 0.0;
  for (double k = std::floor((mean - 8.0 * sigma - high) / period); k <= std::ceil((mean + 8.0 * sigma - low) / period); ++k)
    mass += cdf(high + k * period) - cdf(low + k * period);
  return mass;
}

// The diversity acquisition at u (see BdsParams::acquisition), plus eq. 3.8's β·Σ_j σ_j(u).
double diversity_acquisition(const DiversityContext& c, const VectorXd& u) {
  const std::size_t nf = c.features->size();
  std::vector<double> mean(nf), sigma(nf);
  double spread = 0.0;
  for (std::size_t j = 0; j < nf; ++j) {
    const auto& f = (*c.features)[j];
    double m = 0.0, var = 0.0;
    (*c.gps)[j].predict(u, m, var);
    mean[j] = f.low + m * (f.high - f.low);
    sigma[j] = std::sqrt(var) * (f.high - f.low);
    spread += sigma[j];
  }
  if (!c.levels.empty()) {
    std::vector<std::vector<double>> mass(nf);
    for (std::size_t j = 0; j < nf; ++j) {
      const bool angular = (*c.features)[j].metric == FeatureMetric::angular;
      for (std::size_t a = 0; a < c.levels[j].low.size(); ++a)
        mass[j].push_back(cell_mass(angular, mean[j], sigma[j], c.levels[j].low[a], c.levels[j].high[a]));
    }
    // Level cells of one feature are disjoint, so the strategies' events are too: the sum is exact.
    double repeat = 0.0;
    for (const auto& t : c.tuples) {
      double p = 1.0;
      for (std::size_t j = 0; j < nf; ++j) p *= mass[j][t[j]];
      repeat += p;
    }
    return success_probability(c.success, u, nullptr) *
           (1.0 - repeat + c.tie_scale * expected_nearest_distance(*c.features, mean, sigma, *c.targets, *c.eps) +
            c.ucb_beta * spread);
  }
  // "Failed samples" (bds.h): the expected gain p(u)·a(u); p ≡ 1 without a failure.
  return success_probability(c.success, u, nullptr) *
         (expected_nearest_distance(*c.features, mean, sigma, *c.targets, *c.eps) + c.ucb_beta * spread);
}
}  // namespace

// Thesis eq. 3.7: E_{f ~ N(μ(x), σ²(x))}[min_i ‖f − f_i‖], by Monte Carlo (§3.5.1: "numerically
// with Monte-Carlo integration"), in the strategies' own distance (angular features wrap), so
// "diverse" means what the store counts.
double expected_nearest_distance(const std::vector<Feature>& features, const std::vector<double>& mean,
                                 const std::vector<double>& sigma, const std::vector<std::vector<double>>& targets,
                                 const MatrixXd& eps) {
  const std::size_t nf = features.size();
  PODIUM_CHECK(mean.size() == nf && sigma.size() == nf && static_cast<std::size_t>(eps.cols()) == nf && eps.rows() > 0,
               "expected_nearest_distance: sizes differ");
  if (targets.empty()) return 0.0;
  double total = 0.0;
  std::vector<double> sample(nf);
  for (Eigen::Index s = 0; s < eps.rows(); ++s) {
    for (std::size_t j = 0; j < nf; ++j) sample[j] = mean[j] + sigma[j] * eps(s, static_cast<Eigen::Index>(j));
    double nearest = std::numeric_limits<double>::infinity();
    for (const auto& target : targets) nearest = std::min(nearest, feature_distance(features, sample, target));
    total += nearest;
  }
  return total / static_cast<double>(eps.rows());
}

namespace {
// Everything a diversity step's acquisition reads, for the current told trials and targets.
struct DiversityInputs {
  DiversityContext ctx;
  MatrixXd eps;
};

void fill_context(DiversityInputs& in, const std::string& acquisition, const std::vector<Feature>& features,
                  const std::vector<std::vector<double>>& observed, base::Rng& rng, int mc_samples) {
  DiversityContext& ctx = in.ctx;
  in.eps.resize(mc_samples, static_cast<Eigen::Index>(features.size()));
  for (Eigen::Index s = 0; s < in.eps.rows(); ++s)
    for (Eigen::Index j = 0; j < in.eps.cols(); ++j) in.eps(s, j) = rng.normal();
  ctx.eps = &in.eps;
  if (acquisition != "new_combination") return;
  double diagonal = 0.0;
  for (const auto& f : features) diagonal += (f.high - f.low) * (f.high - f.low);
  ctx.tie_scale = 1e-3 / std::sqrt(diagonal);
  // Levels come from real observations only; believers' predicted features are read as their
  // nearest levels, so a pending point claims an observed combination, not a new level.
  for (std::size_t j = 0; j < features.size(); ++j) {
    std::vector<double> values;
    for (const auto& o : observed) values.push_back(o[j]);
    ctx.levels.push_back(make_levels(features[j], values));
  }
  std::set<std::vector<std::size_t>> tuples;
  for (const auto& target : *ctx.targets) {
    std::vector<std::size_t> tuple;
    for (std::size_t j = 0; j < features.size(); ++j) tuple.push_back(level_of(features[j], ctx.levels[j], target[j]));
    tuples.insert(tuple);
  }
  ctx.tuples.assign(tuples.begin(), tuples.end());
}
}  // namespace

VectorXd BayesianDiversitySearch::diversify(const std::vector<GaussianProcess>& gps,
                                            const std::vector<std::vector<double>>& targets) {
  const int d = static_cast<int>(space_.dim());
  DiversityInputs in{{&gps, &features_, params_.ucb_beta, &targets, nullptr}, {}};
  std::vector<std::vector<double>> observed;
  for (const auto& t : told_)
    if (modelled(t)) observed.push_back(t.features);
  fill_context(in, acquisition_, features_, observed, rng_, params_.mc_samples);
  const auto success = success_model();
  in.ctx.success = success ? &*success : nullptr;
  auto objective = [](const std::vector<double>& x, std::vector<double>&, void* data) {
    return diversity_acquisition(*static_cast<DiversityContext*>(data),
                                 Eigen::Map<const VectorXd>(x.data(), static_cast<Eigen::Index>(x.size())));
  };
  // Algorithm 1 line 7: DIRECT (the locally biased variant), derivative-free since the Monte
  // Carlo estimate is noisy in x (§3.5.1).
  nlopt::opt opt(nlopt::GN_DIRECT_L, static_cast<unsigned>(d));
  opt.set_lower_bounds(std::vector<double>(d, 0.0));
  opt.set_upper_bounds(std::vector<double>(d, 1.0));
  opt.set_max_objective(objective, &in.ctx);
  opt.set_maxeval(params_.direct_evals);
  std::vector<double> x(d, 0.5);
  double value = 0.0;
  try {
    opt.optimize(x, value);
  } catch (const std::exception&) {
    // DIRECT's best point so far is in x even when it stops early.
  }
  return Eigen::Map<const VectorXd>(x.data(), d).cwiseMax(0.0).cwiseMin(1.0);
}

std::vector<double> BayesianDiversitySearch::diversity_values(const std::vector<VectorXd>& us) {
  PODIUM_CHECK(std::any_of(told_.begin(), told_.end(), [&](const Told& t) { return modelled(t); }),
               "bds: diversity_values needs a modelled (successful, or with failures \"ignore\" finished) trial");
  fit_if_needed();
  std::vector<std::vector<double>> believer_features;
  const auto gps = conditioned_gps(believer_features);
  const auto targets = diversity_targets(believer_features);
  DiversityInputs in{{&gps, &features_, params_.ucb_beta, &targets, nullptr}, {}};
  std::vector<std::vector<double>> observed;
  for (const auto& t : told_)
    if (modelled(t)) observed.push_back(t.features);
  fill_context(in, acquisition_, features_, observed, rng_, params_.mc_samples);
  const auto success = success_model();
  in.ctx.success = success ? &*success : nullptr;
  std::vector<double> out;
  for (const auto& u : us) out.push_back(diversity_acquisition(in.ctx, u));
  return out;
}

bool BayesianDiversitySearch::is_new_strategy(const Observation& o) const {
  if (!o.ok || !o.success) return false;
  return std::none_of(told_.begin(), told_.end(), [&](const Told& t) {
    return t.ok && t.success && feature_distance(features_, t.features, o.features) <= threshold_;
  });
}

void BayesianDiversitySearch::tell(const std::vector<Observation>& observations) {
  for (const auto& o : observations) {
    auto it = pending_.find(o.id);
    if (it == pending_.end())
      throw base::UserError(name() + ": tell() got id " + std::to_string(o.id) +
                            ", which is not a pending proposal (never asked or already told)");
    if (o.ok && o.features.size() != features_.size())
      throw base::UserError(name() + ": trial " + std::to_string(o.id) + " reported " + std::to_string(o.features.size()) +
                            " feature values but the task declares " + std::to_string(features_.size()));
    if (o.ok)
      for (double v : o.features)
        if (!std::isfinite(v))
          throw base::UserError(name() + ": trial " + std::to_string(o.id) + " reported a non-finite feature value");
    if (!o.x.empty() && o.x.size() != static_cast<std::size_t>(it->second.u.size()))
      throw base::UserError(name() + ": trial " + std::to_string(o.id) + " ran at " + std::to_string(o.x.size()) +
                            " parameters but the space has " + std::to_string(it->second.u.size()));
    const bool new_strategy = is_new_strategy(o);
    // The self-correcting schedule (bds.h): stalled diversity steps trigger exploration, which
    // stops at its first new strategy.
    if (it->second.step == "diversity" && params_.stall > 0) {
      stalled_ = new_strategy ? 0 : stalled_ + 1;
      if (stalled_ >= params_.stall) {
        fallback_left_ = params_.stall_explore;
        stalled_ = 0;
      }
    } else if (it->second.step == "explore" && new_strategy) {
      fallback_left_ = 0;
    }
    // A result is modelled where it was measured (Observation::x), not where it was asked for.
    told_.push_back(
        {o.id, o.x.empty() ? it->second.u : to_unit(o.x), o.ok, o.ok ? o.features : std::vector<double>{}, o.ok && o.success});
    pending_.erase(it);
  }
}

Json BayesianDiversitySearch::save() const {
  Json pending = Json::array(), told = Json::array(), theta = Json::array();
  for (const auto& [id, p] : pending_) pending.push_back({{"id", id}, {"u", vector_json(p.u)}, {"step", p.step}});
  for (const auto& t : told_)
    told.push_back({{"id", t.id}, {"u", vector_json(t.u)}, {"ok", t.ok}, {"features", t.features}, {"success", t.success}});
  for (const auto& t : theta_) theta.push_back(vector_json(t));
  return {{"rng", rng_.save()},
          {"next_id", next_id_},
          {"stalled", stalled_},
          {"fallback_left", fallback_left_},
          {"fitted_on", fitted_on_},
          {"theta", theta},
          {"pending", pending},
          {"told", told},
          {"gp_steps", gp_steps_},
          {"theta_success", vector_json(theta_success_)},
          {"success_fitted_on", success_fitted_on_}};
}

void BayesianDiversitySearch::load(const Json& state) {
  rng_.load(state.at("rng").get<std::string>());
  next_id_ = state.at("next_id").get<std::uint64_t>();
  stalled_ = state.at("stalled").get<int>();
  fallback_left_ = state.at("fallback_left").get<int>();
  fitted_on_ = state.at("fitted_on").get<std::size_t>();
  gp_steps_ = state.value("gp_steps", std::uint64_t{0});
  if (state.contains("theta_success")) theta_success_ = vector_from(state["theta_success"]);
  success_fitted_on_ = state.value("success_fitted_on", std::size_t{0});
  theta_.clear();
  for (const auto& t : state.at("theta")) theta_.push_back(vector_from(t));
  PODIUM_CHECK(theta_.size() == features_.size(), "bds: saved state has a different number of features");
  pending_.clear();
  for (const auto& p : state.at("pending"))
    pending_[p.at("id").get<std::uint64_t>()] = {vector_from(p.at("u")), p.at("step").get<std::string>()};
  told_.clear();
  for (const auto& t : state.at("told"))
    told_.push_back({t.at("id").get<std::uint64_t>(), vector_from(t.at("u")), t.at("ok").get<bool>(),
                     t.at("features").get<std::vector<double>>(), t.value("success", t.at("ok").get<bool>())});
}

}  // namespace podium::search
