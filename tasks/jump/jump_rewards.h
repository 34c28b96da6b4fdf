#pragma once
/// The jumps' sparse reward (thesis §3.6.1, eqs. 3.2, 3.15, 3.16), given once at the end:
///   r = r_complete · r_ω · r_safety · r_naturalness [· r_novelty in Stage 2]
/// with r_complete ∈ {0, 1} (success), r_ω = exp(−0.02·ω̄) (ω̄ the episode's mean root angular
/// speed, rad/s), r_safety = 0.7 after a head-first landing (jump_rules.h) else 1, r_naturalness
/// eq. 3.4 on the episode's mean L1 offset norm (§3.4.2), r_novelty eq. 3.12.
#include <numbers>
#include <span>
#include <vector>

namespace podium::tasks::jump {

/// r_ω = exp(−0.02·ω̄).
double omega_reward(double mean_root_speed_rad_s);
/// 0.7 for a head-first landing, else 1.
double safety_reward(bool head_first);
/// Eq. 3.12: clip(min_i ‖f − f_i‖ / d_threshold, 0.01, 1) over the features f_i of the policies
/// already found (Euclidean); 1 when there are none. Throws base::UserError when a known
/// feature's size differs from f's or d_threshold ≤ 0.
double novelty_reward(std::span<const double> feature, const std::vector<std::vector<double>>& known,
                      double d_threshold = std::numbers::pi / 2);

/// Per-control-step sums over an episode for r_ω and r_naturalness.
struct EpisodeSums {
  int steps = 0;
  double root_speed_sum = 0.0;  ///< Σ ‖ω_root‖ after each step, rad/s
  double offset_l1_sum = 0.0;   ///< Σ ‖a_offset‖₁ of each step's action, rad
  void add(double root_speed_rad_s, double offset_l1) { ++steps, root_speed_sum += root_speed_rad_s, offset_l1_sum += offset_l1; }
  double mean_root_speed() const { return steps ? root_speed_sum / steps : 0.0; }
  double mean_offset_l1() const { return steps ? offset_l1_sum / steps : 0.0; }
};

struct RewardTerms {
  double complete = 0.0, omega = 1.0, safety = 1.0, naturalness = 1.0, novelty = 1.0;
  double total() const { return complete * omega * safety * naturalness * novelty; }
};

/// The terms at an episode's end; `novelty` is r_novelty (1 in Stage 1).
RewardTerms jump_reward(bool success, bool head_first, const EpisodeSums& sums, double c_offset, double novelty = 1.0);

}  // namespace podium::tasks::jump
