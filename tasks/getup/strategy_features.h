#pragma once
/// A get-up's strategy as four numbers (the seed's App. G compares get-ups by video), read from a policy's rollouts over fixed
/// starts and averaged over them. The seed compares strategies by video and by t-SNE of
/// hand-picked state features (App. G); these summarise what a person watching tells apart:
/// which way the chest faces while rising (a sit-up from the back or a push-up from the front),
/// which side the body turns over, and which body parts carry the weight on the way up.
///
/// "The rise": from the first control step after the fall until the head top first passes
/// `rise_height_m` (the whole episode when it never does).
#include <array>
#include <string>
#include <vector>

#include "podium/base/json.h"
#include "podium/character/character_env.h"

namespace podium::tasks::getup {

struct StrategyFeatures {
  static constexpr std::size_t size = 4;
  /// Names, units and ranges as the task describes them (plugins/task.h "features").
  static base::Json describe();
  /// chest_up_at_half_height: the z component of the torso's front axis when the head top first
  ///   passes half the rise height (+1 chest to the sky: rising from the back; −1 chest to the
  ///   ground: rising from the front; the episode's last value if it never gets there);
  /// side_lean: the mean z component of the torso's left axis over the rise (+: the left side up,
  ///   turning over the right side; −: over the left);
  /// hand_support: the fraction of the rise with a hand or forearm on the ground;
  /// knee_support: the fraction of the rise with a shin on the ground (kneeling).
  std::array<double, size> values{};
  std::vector<double> as_vector() const { return {values.begin(), values.end()}; }
};

/// Accumulates one episode's features step by step (call observe after the reset and after every
/// step), then features() gives its values.
class StrategyRecorder {
 public:
  StrategyRecorder(const sim::CharacterModel& model, double head_top_m, double rise_height_m);
  void observe(const character::CharacterEnv& env);
  StrategyFeatures features() const;

 private:
  std::vector<int> hands_, shins_;
  double head_top_m_, rise_height_m_;
  bool risen_ = false, half_seen_ = false;
  double chest_up_at_half_ = 0.0, last_chest_up_ = 0.0;
  double side_sum_ = 0.0, hand_steps_ = 0.0, knee_steps_ = 0.0, steps_ = 0.0;
};

/// The mean of several episodes' features.
StrategyFeatures mean_features(const std::vector<StrategyFeatures>& episodes);

}  // namespace podium::tasks::getup
