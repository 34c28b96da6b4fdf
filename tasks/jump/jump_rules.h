#pragma once
/// The jumps' rules (thesis §3.6.1), judged after every control step from the World's contacts by
/// partner: success when the character lands on the block with every body at least 20 cm from the
/// wall (obstacle); failure when any body touches the wall (obstacle), any body but the take-off
/// foot touches the ground, or 2 s pass after take-off (the episode's start) without success.
///
/// "Lands": some body touches the block while every body is ≥ clearance from the wall
/// (sim::World::prop_distance, the geoms' distance). A block touch closer than that is neither,
/// and the episode goes on. Failures win over a success seen in the same step.
///
/// Head-first (r_safety, eq. 3.16; the thesis does not define it): the head is among the bodies
/// touching the block in the landing step — so a head that touches in the same control step as a
/// foot or hand counts as head-first, one that touches later does not. This is the rule of the
/// authors' repository (arpspoof/Jump, env/jumper/highjump.py).
#include <string>

#include "jump_suite.h"
#include "podium/base/json.h"
#include "podium/sim/world.h"

namespace podium::tasks::jump {

enum class Outcome { in_flight, success, touched_obstacle, touched_ground, timed_out };
const char* outcome_name(Outcome outcome);

struct RulesConfig {
  double clearance_m = 0.2;   ///< §3.6.1: 20 cm
  double time_limit_s = 2.0;  ///< §3.6.1: two seconds after take-off
};

class JumpReferee {
 public:
  /// `takeoff_foot`: the body allowed on the ground. Throws base::UserError for a bad index.
  JumpReferee(const sim::CharacterModel& model, int takeoff_foot, int obstacle_prop, int block_prop, RulesConfig rules = {});
  /// Starts an episode (in flight, no reason).
  void reset();
  /// Judges the state after a control step, `time_s` after take-off; `observation` is
  /// world.observe() of that state. Once decided, the outcome stays.
  Outcome judge(const sim::World& world, const sim::Observation& observation, double time_s);

  Outcome outcome() const { return outcome_; }
  /// Why it ended: "left_shin touched the ground", "right_hand touched the bar", ... ("" in flight).
  const std::string& reason() const { return reason_; }
  /// Whether the landing was head-first (only meaningful on success).
  bool head_first() const { return head_first_; }

  /// The decision so far, for env checkpoints.
  base::Json state() const;
  void load_state(const base::Json& state);

 private:
  const sim::CharacterModel* model_;
  int foot_, obstacle_, block_;
  RulesConfig rules_;
  Outcome outcome_ = Outcome::in_flight;
  std::string reason_;
  bool head_first_ = false;
};

}  // namespace podium::tasks::jump
