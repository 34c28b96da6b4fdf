#include "jump_rewards.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "podium/base/error.h"
#include "podium/character/rewards.h"

namespace podium::tasks::jump {

double omega_reward(double mean_root_speed_rad_s) { return std::exp(-0.02 * mean_root_speed_rad_s); }

double safety_reward(bool head_first) { return head_first ? 0.7 : 1.0; }

double novelty_reward(std::span<const double> feature, const std::vector<std::vector<double>>& known, double d_threshold) {
  if (!(d_threshold > 0)) throw base::UserError("jump novelty: d_threshold " + std::to_string(d_threshold) + " is not > 0");
  if (known.empty()) return 1.0;
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < known.size(); ++i) {
    if (known[i].size() != feature.size())
      throw base::UserError("jump novelty: known feature " + std::to_string(i) + " has " + std::to_string(known[i].size()) +
                            " values, the episode's has " + std::to_string(feature.size()));
    double d2 = 0.0;
    for (std::size_t k = 0; k < feature.size(); ++k) d2 += (feature[k] - known[i][k]) * (feature[k] - known[i][k]);
    nearest = std::min(nearest, std::sqrt(d2));
  }
  return std::clamp(nearest / d_threshold, 0.01, 1.0);
}

RewardTerms jump_reward(bool success, bool head_first, const EpisodeSums& sums, double c_offset, double novelty) {
  RewardTerms t;
  t.complete = success ? 1.0 : 0.0;
  t.omega = omega_reward(sums.mean_root_speed());
  t.safety = success ? safety_reward(head_first) : 1.0;
  t.naturalness = character::naturalness_reward_from_norm(sums.mean_offset_l1(), c_offset);
  t.novelty = novelty;
  return t;
}

}  // namespace podium::tasks::jump
