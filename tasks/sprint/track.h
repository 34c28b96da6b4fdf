#pragma once
/// The sprint's track and its rules (sprint seed §2 "Reward", §3.1; athletics' finish rule): a
/// straight flat track along +x, the start line at x = 0, the finish plane at x = L, one lane of
/// width w centred on y = 0. Lengths come from the preset (sprint_preset.h), not from code.
///
/// Finish: the first instant any torso body (the model's root and its torso body — pelvis and chest
/// on humanoid34; not head, arms or legs) reaches the plane, judged on the front of the body's
/// geoms after every simulation step and interpolated linearly within that step.
/// Lane: leaving it ends the episode. Fall: any body but the feet (and the hands before the first
/// step) touching the ground.
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "podium/base/json.h"
#include "podium/sim/world.h"

namespace podium::tasks::sprint {

struct TrackSpec {
  double length_m = 100.0;       ///< L: the finish plane's x (preset: 100 paper, 30 quick, 10 smoke)
  double lane_width_m = 1.22;    ///< w: an athletics lane
  double lane_centre_y_m = 0.0;  ///< y of the lane's centre line
};

/// The largest world x of body `body`'s geoms (its front along the track), from the link poses in
/// `data` (as every World step leaves them). Throws base::UserError for a bad index or a body without geoms.
double body_front_x(const sim::CharacterModel& model, const sim::CharacterData& data, int body);

/// The time at which x(t), linear between (t0, x0) and (t1, x1), first reaches `plane`; nullopt
/// when it does not in [t0, t1]. At or past the plane already at t0: t0.
std::optional<double> crossing_time(double t0, double x0, double t1, double x1, double plane);

/// Watches the torso bodies' front after every simulation step and keeps the finish time.
class FinishLine {
 public:
  /// Torso bodies: the model's root (body 0) and its torso body (one body when they coincide).
  FinishLine(const sim::CharacterModel& model, const TrackSpec& track);
  /// Starts an episode at the World's current state (call after World::reset).
  void reset(const sim::World& world);
  /// After each simulation step (World::set_substep_observer). Once finished, nothing changes.
  void observe(const sim::World& world);
  /// The finish time on the World's clock, s; nullopt before the torso reaches the plane.
  std::optional<double> finish_time() const { return finish_; }
  /// The torsos' front x at the last observation, m.
  double front_x() const { return last_x_; }
  const std::vector<int>& torso_bodies() const { return torso_; }
  /// The line's state (last observation, finish time), for env checkpoints, and back.
  base::Json state() const;
  void load_state(const base::Json& state);

 private:
  double torso_front(const sim::World& world) const;
  const sim::CharacterModel* model_;
  TrackSpec track_;
  std::vector<int> torso_;
  double last_t_ = 0.0, last_x_ = 0.0;
  std::optional<double> finish_;
};

/// Whether a lateral position is outside the lane (|y − centre| > w/2).
bool outside_lane(const TrackSpec& track, double y_m);
/// The bodies whose centroid leaves the lane ends the episode: the root and the feet.
/// Returns the first such body outside the lane, or −1.
int body_outside_lane(const TrackSpec& track, const sim::World& world, std::span<const int> bodies);

/// Which bodies may touch the ground (by index in the model).
struct GroundAllowance {
  std::vector<int> feet;   ///< always
  std::vector<int> hands;  ///< until the first step (the crouch start's hands on the track)
};
/// The first body touching the ground that may not (a fall), or −1. Props (the blocks) do not count.
int fallen_body(const sim::Observation& observation, const GroundAllowance& allowed, bool first_step_taken);

/// The model's bodies by name, resolved once: feet, hands, thighs and upper arms, left and right.
/// Throws base::UserError naming the model and the missing body.
struct SprintBodies {
  int left_foot = -1, right_foot = -1, left_hand = -1, right_hand = -1;
  int left_thigh = -1, right_thigh = -1, left_upper_arm = -1, right_upper_arm = -1;
  static SprintBodies of(const sim::CharacterModel& model);
  GroundAllowance ground_allowance() const { return {{left_foot, right_foot}, {left_hand, right_hand}}; }
};

}  // namespace podium::tasks::sprint
