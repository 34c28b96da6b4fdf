// Reward kernels on hand-made inputs; expected values worked out by hand in the comments.
#include "podium/character/rewards.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "podium/base/error.h"

namespace podium::character {
namespace {

constexpr double kTol = 1e-12;

TEST(Tolerance, OneInsideTheBoundsAndIndicatorWithoutMargin) {
  EXPECT_EQ(tolerance(0.5, {0.0, 1.0, 0.3, 0.1, Sigmoid::gaussian}), 1.0);
  EXPECT_EQ(tolerance(1.0, {0.0, 1.0, 0.3, 0.1, Sigmoid::gaussian}), 1.0);  // bounds are closed
  EXPECT_EQ(tolerance(1.2, {0.0, 1.0, 0.0, 0.1, Sigmoid::gaussian}), 0.0);  // margin 0: indicator
  EXPECT_EQ(tolerance(5.0, {1.0, kInf, 0.0, 0.1, Sigmoid::gaussian}), 1.0);
}

// Every kind is scaled to give value_at_margin at one margin outside the bounds.
TEST(Tolerance, EveryKindTakesItsValueAtTheMargin) {
  for (Sigmoid kind : {Sigmoid::gaussian, Sigmoid::hyperbolic, Sigmoid::long_tail, Sigmoid::reciprocal, Sigmoid::cosine,
                       Sigmoid::linear, Sigmoid::quadratic, Sigmoid::tanh_squared}) {
    EXPECT_NEAR(tolerance(2.0, {0.0, 1.0, 1.0, 0.3, kind}), 0.3, kTol) << sigmoid_name(kind);
    EXPECT_NEAR(tolerance(-1.0, {0.0, 1.0, 1.0, 0.3, kind}), 0.3, kTol) << sigmoid_name(kind);
  }
}

// Half a margin outside [0, 1] (x = 1.5, margin 1, d = 0.5), value_at_margin v:
TEST(Tolerance, HalfAMarginOutsideMatchesHandValues) {
  const auto at = [](Sigmoid kind, double v) { return tolerance(1.5, {0.0, 1.0, 1.0, v, kind}); };
  // gaussian: exp(−½ (d·√(−2 ln v))²) = v^(d²) = 0.1^0.25 = 0.5623413251903491
  EXPECT_NEAR(at(Sigmoid::gaussian, 0.1), 0.5623413251903491, kTol);
  // hyperbolic: 1 / cosh(d · acosh(1/v)) = 1 / cosh(0.5 · acosh 10) = 0.42640143271122083
  EXPECT_NEAR(at(Sigmoid::hyperbolic, 0.1), 0.42640143271122083, kTol);
  // long_tail: 1 / ((d·√(1/v − 1))² + 1) = 1 / (1.5² + 1) = 1/3.25
  EXPECT_NEAR(at(Sigmoid::long_tail, 0.1), 1.0 / 3.25, kTol);
  // reciprocal: 1 / (|d|·(1/v − 1) + 1) = 1 / (0.5·9 + 1) = 1/5.5
  EXPECT_NEAR(at(Sigmoid::reciprocal, 0.1), 1.0 / 5.5, kTol);
  // cosine, v = 0: scale acos(−1)/π = 1, (1 + cos(π·0.5)) / 2 = 0.5
  EXPECT_NEAR(at(Sigmoid::cosine, 0.0), 0.5, kTol);
  // linear, v = 0: 1 − 0.5 = 0.5;  quadratic, v = 0: 1 − 0.5² = 0.75
  EXPECT_NEAR(at(Sigmoid::linear, 0.0), 0.5, kTol);
  EXPECT_NEAR(at(Sigmoid::quadratic, 0.0), 0.75, kTol);
  // tanh_squared: 1 − tanh(d · atanh(√(1 − v)))² = 1 − tanh(0.5 · atanh √0.9)² = 0.4805061467040842
  EXPECT_NEAR(at(Sigmoid::tanh_squared, 0.1), 0.4805061467040842, kTol);
}

// Terms whose value at the margin is 0 (get-up seed eqs. 6 and 8) reach 0 only with cosine,
// linear and quadratic, and stay 0 beyond the margin; the other kinds refuse v = 0.
TEST(Tolerance, ValueZeroAtTheMarginOnlyForKindsThatReachZero) {
  // r_feet = f(d_feet, [0, 0.9], 0.38, 0) with a linear fall-off: at 0.9 + 0.19 it is 0.5.
  EXPECT_NEAR(tolerance(1.09, {0.0, 0.9, 0.38, 0.0, Sigmoid::linear}), 0.5, kTol);
  EXPECT_EQ(tolerance(0.9 + 0.38, {0.0, 0.9, 0.38, 0.0, Sigmoid::linear}), 0.0);
  EXPECT_EQ(tolerance(3.0, {0.0, 0.9, 0.38, 0.0, Sigmoid::quadratic}), 0.0);
  EXPECT_EQ(tolerance(3.0, {0.0, 0.9, 0.38, 0.0, Sigmoid::cosine}), 0.0);
  for (Sigmoid kind : {Sigmoid::gaussian, Sigmoid::hyperbolic, Sigmoid::long_tail, Sigmoid::reciprocal, Sigmoid::tanh_squared})
    EXPECT_THROW(tolerance(1.0, {0.0, 0.9, 0.38, 0.0, kind}), base::UserError) << sigmoid_name(kind);
  // A bad value fails on first use, even with x inside the bounds.
  EXPECT_THROW(tolerance(0.5, {0.0, 0.9, 0.38, 1.0, Sigmoid::linear}), base::UserError);
}

// Get-up seed eq. 5: r_h = f(h_head, [1.55, ∞], 0.37, 0.1).
TEST(Tolerance, HeadHeightTermOfTheGetUpSeed) {
  const Tolerance r_h{1.55, kInf, 0.37, 0.1, Sigmoid::gaussian};
  EXPECT_EQ(tolerance(1.60, r_h), 1.0);
  EXPECT_NEAR(tolerance(1.55 - 0.37, r_h), 0.1, kTol);
  EXPECT_NEAR(tolerance(1.55 - 0.37 / 2, r_h), 0.5623413251903491, kTol);  // as above: 0.1^(1/4)
}

TEST(Tolerance, RejectsBadBoundsMarginsAndNames) {
  EXPECT_THROW(tolerance(0.0, {1.0, 0.0, 0.1, 0.1, Sigmoid::gaussian}), base::UserError);
  EXPECT_THROW(tolerance(0.0, {0.0, 1.0, -0.1, 0.1, Sigmoid::gaussian}), base::UserError);
  EXPECT_EQ(parse_sigmoid("long_tail", "rewards.r_h.sigmoid"), Sigmoid::long_tail);
  try {
    parse_sigmoid("gauss", "rewards.r_h.sigmoid");
    FAIL() << "expected UserError";
  } catch (const base::UserError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("rewards.r_h.sigmoid: \"gauss\" is not one of gaussian, hyperbolic", 0), 0u)
        << e.what();
  }
}

TEST(Kernels, ExponentialAndNaturalness) {
  // get-up seed eq. 12 r_pose = exp(−¼ Σ‖Δq‖²): Σ = 4 gives e^−1.
  EXPECT_NEAR(exp_kernel(4.0, 0.25), std::exp(-1.0), kTol);
  EXPECT_EQ(exp_kernel(0.0, 3.0), 1.0);
  // thesis eq. 3.4: 1 − clip((‖a‖₁ / c)², 0, 1): ‖(0.25, −0.25)‖₁ = 0.5 → 1 − 0.25 = 0.75 with c = 1;
  // with c = 2: 1 − 0.0625; ‖(2)‖₁ / 1 = 2 → clipped → 0.
  EXPECT_NEAR(naturalness_reward(std::vector<double>{0.25, -0.25}, 1.0), 0.75, kTol);
  EXPECT_NEAR(naturalness_reward(std::vector<double>{0.25, -0.25}, 2.0), 1.0 - 0.0625, kTol);
  EXPECT_EQ(naturalness_reward(std::vector<double>{2.0}, 1.0), 0.0);
  EXPECT_EQ(naturalness_reward(std::vector<double>{0.0, 0.0}, 48.0), 1.0);
  EXPECT_THROW(naturalness_reward(std::vector<double>{0.0}, 0.0), base::UserError);
  // Sparse tasks pass the episode's mean ‖a_offset‖₁: mean 24 with c_offset 48 → 1 − ¼.
  EXPECT_NEAR(naturalness_reward_from_norm(24.0, 48.0), 0.75, kTol);
}

}  // namespace
}  // namespace podium::character
