#include "podium/learn/classic_control.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "podium/base/error.h"

namespace podium::learn {
namespace {

constexpr double kPi = std::numbers::pi;

double wrap_angle(double x) { return std::fmod(std::fmod(x + kPi, 2 * kPi) + 2 * kPi, 2 * kPi) - kPi; }

void check_action(std::span<const double> action, std::size_t size, const char* env) {
  if (action.size() != size)
    throw base::UserError(std::string("learn: ") + env + ".step: action has " + std::to_string(action.size()) +
                          " entries, expected " + std::to_string(size));
}

}  // namespace

// ---- Pendulum (Gym Pendulum-v1 constants) ----
namespace {
constexpr double kMaxSpeed = 8.0, kMaxTorque = 2.0, kDt = 0.05, kG = 10.0, kM = 1.0, kL = 1.0;
}

BoxSpace Pendulum::observation_space() const { return {{-1.0, -1.0, -kMaxSpeed}, {1.0, 1.0, kMaxSpeed}}; }
BoxSpace Pendulum::action_space() const { return {{-kMaxTorque}, {kMaxTorque}}; }

void Pendulum::observe(std::vector<double>& observation) const {
  observation.assign({std::cos(theta_rad_), std::sin(theta_rad_), theta_dot_rad_s_});
}

void Pendulum::reset(std::vector<double>& observation) {
  theta_rad_ = rng_.uniform(-kPi, kPi);
  theta_dot_rad_s_ = rng_.uniform(-1.0, 1.0);
  t_ = 0;
  observe(observation);
}

void Pendulum::step(std::span<const double> action, StepResult& out) {
  check_action(action, 1, "Pendulum");
  const double u = std::clamp(action[0], -kMaxTorque, kMaxTorque);
  const double th = wrap_angle(theta_rad_);
  out.reward = -(th * th + 0.1 * theta_dot_rad_s_ * theta_dot_rad_s_ + 0.001 * u * u);
  theta_dot_rad_s_ += (3 * kG / (2 * kL) * std::sin(theta_rad_) + 3.0 / (kM * kL * kL) * u) * kDt;
  theta_dot_rad_s_ = std::clamp(theta_dot_rad_s_, -kMaxSpeed, kMaxSpeed);
  theta_rad_ += theta_dot_rad_s_ * kDt;
  ++t_;
  out.terminated = false;
  out.truncated = t_ >= kEpisodeSteps;
  observe(out.observation);
}

std::optional<base::Json> Pendulum::save_state() const {
  return base::Json{{"theta_rad", theta_rad_}, {"theta_dot_rad_s", theta_dot_rad_s_}, {"t", t_}, {"rng", rng_.save()}};
}

void Pendulum::load_state(const base::Json& state) {
  theta_rad_ = state.at("theta_rad").get<double>();
  theta_dot_rad_s_ = state.at("theta_dot_rad_s").get<double>();
  t_ = state.at("t").get<int>();
  rng_.load(state.at("rng").get<std::string>());
}

// ---- CartPole (Gym CartPole-v1 constants, continuous force) ----
namespace {
constexpr double kGravity = 9.8, kMassCart = 1.0, kMassPole = 0.1, kHalfLength = 0.5, kForceMag = 10.0, kTau = 0.02,
                 kThetaLimit = 12 * 2 * kPi / 360, kXLimit = 2.4;
}

BoxSpace CartPole::observation_space() const {
  const double inf = std::numeric_limits<double>::infinity();
  return {{-2 * kXLimit, -inf, -2 * kThetaLimit, -inf}, {2 * kXLimit, inf, 2 * kThetaLimit, inf}};
}
BoxSpace CartPole::action_space() const { return {{-1.0}, {1.0}}; }

void CartPole::reset(std::vector<double>& observation) {
  for (double& s : state_) s = rng_.uniform(-0.05, 0.05);
  t_ = 0;
  observation.assign(state_, state_ + 4);
}

void CartPole::step(std::span<const double> action, StepResult& out) {
  check_action(action, 1, "CartPole");
  const double force = kForceMag * std::clamp(action[0], -1.0, 1.0);
  auto& [x, x_dot, theta, theta_dot] = state_;
  const double total_mass = kMassCart + kMassPole, pole_ml = kMassPole * kHalfLength;
  const double c = std::cos(theta), s = std::sin(theta);
  // Barto et al. 1983 with the corrected sign of Florian 2007, as in Gym.
  const double temp = (force + pole_ml * theta_dot * theta_dot * s) / total_mass;
  const double theta_acc = (kGravity * s - c * temp) / (kHalfLength * (4.0 / 3.0 - kMassPole * c * c / total_mass));
  const double x_acc = temp - pole_ml * theta_acc * c / total_mass;
  x += kTau * x_dot;
  x_dot += kTau * x_acc;
  theta += kTau * theta_dot;
  theta_dot += kTau * theta_acc;
  ++t_;
  out.reward = 1.0;
  out.terminated = std::abs(x) > kXLimit || std::abs(theta) > kThetaLimit;
  out.truncated = !out.terminated && t_ >= kEpisodeSteps;
  out.observation.assign(state_, state_ + 4);
}

std::optional<base::Json> CartPole::save_state() const {
  return base::Json{{"state", std::vector<double>(state_, state_ + 4)}, {"t", t_}, {"rng", rng_.save()}};
}

void CartPole::load_state(const base::Json& state) {
  const auto s = state.at("state").get<std::vector<double>>();
  PODIUM_CHECK(s.size() == 4, "CartPole state has 4 entries");
  std::copy(s.begin(), s.end(), state_);
  t_ = state.at("t").get<int>();
  rng_.load(state.at("rng").get<std::string>());
}

}  // namespace podium::learn
