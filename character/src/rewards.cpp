#include "podium/character/rewards.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "podium/base/error.h"

namespace podium::character {

namespace {

struct SigmoidName {
  Sigmoid kind;
  const char* name;
};
constexpr SigmoidName kNames[] = {{Sigmoid::gaussian, "gaussian"},   {Sigmoid::hyperbolic, "hyperbolic"},
                                  {Sigmoid::long_tail, "long_tail"}, {Sigmoid::reciprocal, "reciprocal"},
                                  {Sigmoid::cosine, "cosine"},       {Sigmoid::linear, "linear"},
                                  {Sigmoid::quadratic, "quadratic"}, {Sigmoid::tanh_squared, "tanh_squared"}};

bool reaches_zero(Sigmoid kind) { return kind == Sigmoid::cosine || kind == Sigmoid::linear || kind == Sigmoid::quadratic; }

}  // namespace

Sigmoid parse_sigmoid(const std::string& name, const std::string& where) {
  std::string allowed;
  for (const auto& n : kNames) {
    if (name == n.name) return n.kind;
    allowed += (allowed.empty() ? "" : ", ") + std::string(n.name);
  }
  throw base::UserError(where + ": \"" + name + "\" is not one of " + allowed);
}

const char* sigmoid_name(Sigmoid kind) {
  for (const auto& n : kNames)
    if (n.kind == kind) return n.name;
  return "?";
}

static void check_value_at_margin(double v, Sigmoid kind) {
  const bool ok = reaches_zero(kind) ? (v >= 0.0 && v < 1.0) : (v > 0.0 && v < 1.0);
  if (!ok)
    throw base::UserError(std::string("tolerance: value_at_margin ") + std::to_string(v) + " must be in " +
                          (reaches_zero(kind) ? "[0, 1)" : "(0, 1)") + " for the " + sigmoid_name(kind) + " sigmoid");
}

// Each kind is scaled so that its value at |d| = 1 is v (dm_control rewards.py `_sigmoids`).
double sigmoid(double d, double v, Sigmoid kind) {
  check_value_at_margin(v, kind);
  switch (kind) {
    case Sigmoid::gaussian: {
      const double s = std::sqrt(-2.0 * std::log(v));
      return std::exp(-0.5 * (d * s) * (d * s));
    }
    case Sigmoid::hyperbolic:
      return 1.0 / std::cosh(d * std::acosh(1.0 / v));
    case Sigmoid::long_tail: {
      const double s = std::sqrt(1.0 / v - 1.0);
      return 1.0 / ((d * s) * (d * s) + 1.0);
    }
    case Sigmoid::reciprocal:
      return 1.0 / (std::abs(d) * (1.0 / v - 1.0) + 1.0);
    case Sigmoid::cosine: {
      const double x = d * std::acos(2.0 * v - 1.0) / std::numbers::pi;
      return std::abs(x) < 1.0 ? 0.5 * (1.0 + std::cos(std::numbers::pi * x)) : 0.0;
    }
    case Sigmoid::linear: {
      const double x = d * (1.0 - v);
      return std::abs(x) < 1.0 ? 1.0 - std::abs(x) : 0.0;
    }
    case Sigmoid::quadratic: {
      const double x = d * std::sqrt(1.0 - v);
      return std::abs(x) < 1.0 ? 1.0 - x * x : 0.0;
    }
    case Sigmoid::tanh_squared: {
      const double t = std::tanh(d * std::atanh(std::sqrt(1.0 - v)));
      return 1.0 - t * t;
    }
  }
  return 0.0;
}

double tolerance(double x, const Tolerance& t) {
  if (t.lower > t.upper)
    throw base::UserError("tolerance: lower bound " + std::to_string(t.lower) + " > upper bound " + std::to_string(t.upper));
  if (t.margin < 0.0) throw base::UserError("tolerance: margin " + std::to_string(t.margin) + " is negative");
  if (t.margin > 0.0) check_value_at_margin(t.value_at_margin, t.sigmoid);  // a bad config fails on its first use
  if (x >= t.lower && x <= t.upper) return 1.0;
  if (t.margin == 0.0) return 0.0;
  const double distance = x < t.lower ? t.lower - x : x - t.upper;
  return sigmoid(distance / t.margin, t.value_at_margin, t.sigmoid);
}

double exp_kernel(double squared_error, double k) { return std::exp(-k * squared_error); }

double naturalness_reward_from_norm(double offset_l1, double c_offset) {
  if (!(c_offset > 0)) throw base::UserError("naturalness_reward: c_offset " + std::to_string(c_offset) + " is not > 0");
  const double r = offset_l1 / c_offset;
  return 1.0 - std::min(r * r, 1.0);
}

double naturalness_reward(std::span<const double> offsets, double c_offset) {
  double l1 = 0.0;
  for (double o : offsets) l1 += std::abs(o);
  return naturalness_reward_from_norm(l1, c_offset);
}

}  // namespace podium::character
