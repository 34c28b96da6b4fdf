#pragma once
/// Reward kernels shared by the tasks: the bounded tolerance f(i, b, m, v) of the get-up seed
/// (appendix B, Fig. 11), built on dm_control's `tolerance` and its sigmoid kinds [Tassa et al.
/// 2020]; exponential tracking kernels; the thesis's naturalness reward (eq. 3.4).
#include <limits>
#include <span>
#include <string>

namespace podium::character {

/// The shape of the fall-off outside the bounds, as dm_control names them. Only cosine, linear
/// and quadratic reach 0 (at the margin and beyond); the others stay positive, so a term whose
/// value at the margin is 0 (get-up seed eqs. 6 and 8) must use one of those three.
enum class Sigmoid { gaussian, hyperbolic, long_tail, reciprocal, cosine, linear, quadratic, tanh_squared };

/// Parses a sigmoid name ("gaussian", "long_tail", ...); `where` names the JSON path in the error.
Sigmoid parse_sigmoid(const std::string& name, const std::string& where);
const char* sigmoid_name(Sigmoid kind);

/// f(i, b, m, v) of get-up seed App. B: 1 inside b = [lower, upper]; outside, the sigmoid of
/// d = distance-to-bounds / margin, which equals `value_at_margin` at d = 1. margin 0 makes it
/// the indicator of b. Bounds may be ±infinity.
struct Tolerance {
  double lower = 0.0;
  double upper = 0.0;
  double margin = 0.0;
  double value_at_margin = 0.1;  ///< dm_control's default
  Sigmoid sigmoid = Sigmoid::gaussian;
};

/// The sigmoid with value 1 at d = 0 and `value_at_1` at |d| = 1. value_at_1 must lie in (0, 1),
/// or [0, 1) for cosine, linear, quadratic; base::UserError otherwise.
double sigmoid(double d, double value_at_1, Sigmoid kind);
/// f(x, b, m, v); throws base::UserError for margin < 0, lower > upper or a bad value_at_margin.
double tolerance(double x, const Tolerance& t);

constexpr double kInf = std::numeric_limits<double>::infinity();

/// exp(−k·e), the exponential tracking kernel of DeepMimic-style rewards (get-up seed eq. 12:
/// r_pose = exp(−¼ Σ‖q_j − q̂_j‖²) is exp_kernel(Σ‖q_j − q̂_j‖², 0.25)).
double exp_kernel(double squared_error, double k);

/// Thesis eq. 3.4: r_naturalness = 1 − clip((‖a_offset‖₁ / c_offset)², 0, 1), the penalty on the
/// per-joint offsets an action adds to the P-VAE's decoded pose. c_offset > 0.
double naturalness_reward(std::span<const double> offsets, double c_offset);
/// Eq. 3.4 from an offset norm: for sparse tasks (reward only at the end) the thesis replaces
/// ‖a_offset‖₁ by its average over the episode, which the task accumulates and passes here.
double naturalness_reward_from_norm(double offset_l1, double c_offset);

}  // namespace podium::character
