#pragma once
/// The sprint environment (sprint seed §2; the parts in track.h, steps.h, sprint_rewards.h,
/// mirror.h, drag.h): humanoid34 on stable PD at 30 Hz on the preset's straight track, with two
/// inclined starting blocks behind the start line as sim props.
///
/// Per episode (§2 "Initial State"): a domain-randomisation draw (sprint_preset.h: wind along the
/// track, runway μ) — μ through the World's friction, the wind as drag on every body
/// (SprintDrag::apply after the start and after every control step) — recorded with the episode
/// (draw(), episode_record(), the info entries wind_mps and friction). Neither is observed.
///
/// Observation (§2 "State"), facing-invariant but for the track block:
///   per body, in the heading frame: position relative to the root, rotation (two matrix
///   columns), linear and angular velocity (character::LinkStates: 15 per body);
///   the COM relative to the root in the heading frame (3), its height above the ground and its
///   velocity in the heading frame (character::CenterOfMass: 4) — c_t, position and velocity;
///   the track: the root's lateral offset from the lane centre, sin and cos of its heading
///   relative to +x (3; ours: the lane rule and r_d need where the runner is and faces, which a
///   heading-frame state cannot tell);
///   z_t = steps / N_norm (StepCounter, last).
///
/// Action (§2 "Action"): SPD targets through character::TargetActions (stable PD by MABA): an angle
/// per revolute joint and an exponential map (3 values) per spherical joint, within the joint
/// limits (28 values on humanoid34). The seed and the issue ask for a unit quaternion per
/// spherical joint (36 values, normalised before use); the exponential map is the character
/// layer's existing target map and spans the same rotations without the normalisation.
///
/// Reward per control step (§2, §3.2): r_base = r_f + r_s + r_d, plus r_mass, r_diag and r_mirror
/// with the preset's weights (0 switches one off), and r_primitive (primitive.h) at the control
/// step a stride completes when a sport primitive is given and its weight is not 0; info names
/// each term (sprint_env_info_names).
///
/// The episode ends (terminated) on a fall (fallen_body), on leaving the lane (body_outside_lane:
/// root or a foot) or at the finish (FinishLine, its time interpolated within the simulation
/// step), and is truncated at the preset's time limit. It starts standing with the root on the
/// start line, in a given pose, or at one of a set of hand-over states (handover_state(): a World
/// snapshot with its draw and step count, e.g. the Start phase's first landings for stage 2).
///
/// The Start mode (§3.1; SprintEnvSettings::start_references not empty): each episode starts at
/// the first frame of a reference drawn uniformly from the set ("periodically alter a new
/// reference"), on that reference's blocks (the World's props are moved when they differ), at the
/// frame's pose and velocity with the reference clock at 0. The reward adds λ_i·r_I, DeepMimic's
/// imitation terms (character/imitation.h) against that reference with the preset's weights and
/// kernels; the episode also ends on a large deviation from it (EarlyTermination: the COM, r_p;
/// the falls are the sprint's rule above) and at the first landing — the StepCounter's first
/// counted touchdown, on the ground — whose hand-over state (handover_state(), with the episode's
/// draw) landing_state() keeps for stage 2. The observation adds, before z, the reference's phase
/// (its clock over its duration, at most 1) and a one-hot of the reference drawn (the policy cannot
/// tell the arm action from the state).
#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "drag.h"
#include "mirror.h"
#include "podium/base/json.h"
#include "podium/character/character_env.h"
#include "podium/character/imitation.h"
#include "podium/character/motion.h"
#include "podium/character/starts.h"
#include "primitive.h"
#include "sprint_preset.h"
#include "steps.h"
#include "track.h"

namespace podium::tasks::sprint {

/// One starting block: a fixed box whose top face, inclined by `angle_rad` to the ground, faces
/// the track (rising towards −x), resting on the ground.
struct BlockSpec {
  std::string name;
  double x_m = -0.6;            ///< the box's centre along the track (behind the start line: < 0)
  double y_m = 0.0;             ///< its centre across the track
  double angle_rad = 0.785398;  ///< the face's inclination to the ground
  double length_m = 0.2;        ///< the face's length (up the incline)
  double width_m = 0.12;        ///< across the track
  double thickness_m = 0.05;    ///< normal to the face
};
/// The default pair, for a left foot in front: front block 0.55 m behind the line at 45°, rear
/// block 0.85 m behind at 60°, 0.1 m either side of the lane centre (athletics' usual settings;
/// the seed gives none).
std::vector<BlockSpec> default_blocks();
/// The blocks as sim props (BoxProp, friction multiplier 1).
std::vector<sim::BoxProp> starting_blocks(const std::vector<BlockSpec>& blocks);

/// A reference of the Start phase (crouch_start.h builds ours): its name, the blocks it starts
/// from (front block first, as default_blocks()) and its clip (on the env's model, at its
/// control rate, starting in the blocks).
struct StartReference {
  std::string name;
  std::vector<BlockSpec> blocks;
  std::shared_ptr<const character::Clip> clip;
};

struct SprintEnvSettings {
  SprintPreset preset;  ///< track, N_norm, reward weights, drag, DR ranges, time limit
  std::string model = "humanoid34";
  /// Simulation rate; 600 Hz until a lower one is measured to give the same outcomes.
  double sim_hz = 600.0;
  double control_hz = 30.0;  ///< divides sim_hz
  std::vector<BlockSpec> blocks = default_blocks();
  /// The standing start's placement (root on the start line, facing +x).
  character::Placement standing;
  /// A given start state instead of standing (q: nq; qd: nv, empty for at rest).
  Eigen::VectorXd start_q, start_qd;
  /// When not empty, each episode starts at one of these, uniformly (handover_state()'s JSON).
  std::vector<base::Json> handover_states;
  /// When set, every episode takes this draw (evaluation at set conditions); otherwise a
  /// hand-over state's recorded draw, else a fresh draw from the preset's ranges.
  std::optional<EpisodeDraw> fixed_draw;
  /// When not empty, the Start mode: each episode imitates one of these (the preset's `start`).
  std::vector<StartReference> start_references;
  /// The sport primitive r_primitive scores strides with (none: no r_primitive); the env keeps
  /// each stride for take_strides() (the stage's metric and Φ2's training).
  std::shared_ptr<const SportPrimitive> primitive;
  /// Keep each ended episode's distance (the root's x at its last step minus at its start), read
  /// with take_episode_distances(): training copies log them, as the learner reports only returns.
  bool log_distances = false;
};

/// Reads a JSON array of hand-over states; errors name the file.
std::vector<base::Json> load_handover_states(const std::string& path);
/// Writes them as load_handover_states reads them (exact doubles); errors name the file.
void save_handover_states(const std::string& path, const std::vector<base::Json>& states);

/// StepResult::info of SprintEnv, in order: forward, survival, lateral (r_f, r_s, r_d, weighted),
/// mass, diagonal, mirror, primitive (weighted), steps, fell, left_lane, finished (0/1), finish_time_s (on
/// the World's clock, 0 before the finish), wind_mps, friction (the episode's draw); in the Start
/// mode also imitation (λ_i·r_I), landed, deviated (0/1) and reference (the index drawn).
std::vector<std::string> sprint_env_info_names(bool start_mode = false);

class SprintEnv final : public character::CharacterEnv {
 public:
  /// no_landing: the Start's reference ended (plus the preset's extra_time_s) before a landing.
  enum class Outcome { running, fell, left_lane, finished, landed, deviated, no_landing };

  /// Throws base::UserError for a bad setting (a model without the sprint's bodies, a bad start
  /// state, a hand-over state of another model).
  explicit SprintEnv(const SprintEnvSettings& settings);
  // The World's substep observer holds `this`.
  SprintEnv(const SprintEnv&) = delete;
  SprintEnv& operator=(const SprintEnv&) = delete;

  void reset(std::vector<double>& observation) override;
  /// CharacterEnv's state plus the draw, step counter, finish line, mirror history, the root's
  /// last and starting x and the outcome: loaded into an env of the same settings, it continues bitwise.
  std::optional<base::Json> save_state() const override;
  void load_state(const base::Json& state) override;

  /// The current state as a hand-over state: {"world": World snapshot, "draw", "step_counter"}.
  base::Json handover_state() const;
  /// This episode's draw, outcome, steps and finish time (null before the finish), as JSON.
  base::Json episode_record() const;

  const SprintEnvSettings& settings() const { return settings_; }
  const EpisodeDraw& draw() const { return draw_; }
  const StepCounter& step_counter() const { return counter_; }
  const FinishLine& finish_line() const { return finish_; }
  const SprintBodies& bodies() const { return bodies_; }
  const SprintDrag& drag() const { return drag_; }
  Outcome outcome() const { return outcome_; }

  /// Start mode: whether it is on, the reference drawn this episode (−1 before a reset), its
  /// imitation reference, and the tracking errors and r_I of the current state at the reference
  /// clock (what the reward uses).
  bool start_mode() const { return !settings_.start_references.empty(); }
  int reference_index() const { return reference_; }
  const character::ImitationReference& imitation() const;
  character::TrackingErrors tracking_errors() const;
  character::ImitationTerms imitation_terms() const;
  /// The hand-over state at this episode's first landing (Start mode), else nullopt.
  const std::optional<base::Json>& landing_state() const { return landing_; }

  /// The distances of the episodes ended since the last call (log_distances), m, in order; an
  /// episode ends here when the next one resets.
  std::vector<double> take_episode_distances();
  /// The strides completed since the last call (with a sport primitive), K·F values each.
  std::vector<std::vector<double>> take_strides();

 private:
  struct HandoverStart;
  struct ReferenceSetStart;
  struct Terms;
  static character::CharacterEnvParts make_parts(const SprintEnvSettings& settings);
  void begin_episode();
  void on_step(learn::StepResult& out);
  Terms phase_terms(const sim::Observation& features);
  void apply_drag();
  double start_terms(const sim::Observation& features, bool counted, bool& landed, bool& deviated);
  bool start_overran() const;

  SprintEnvSettings settings_;
  SprintBodies bodies_;
  GroundAllowance allowance_;
  std::vector<int> lane_bodies_;
  FinishLine finish_;
  StepCounter counter_;
  Mirror mirror_;
  StepAlignedPoses poses_;
  SprintDrag drag_;
  Eigen::Vector3d upright_com_;  // the COM relative to the root in the heading frame, standing
  EpisodeDraw draw_;
  const base::Json* handover_ = nullptr;  // the hand-over state this episode started at
  double prev_root_x_ = 0.0;
  double start_root_x_ = 0.0;  // the root's x at this episode's start
  std::vector<double> distances_;
  Outcome outcome_ = Outcome::running;
  std::size_t z_index_ = 0;  // z's entry in the observation
  // Start mode
  std::vector<std::shared_ptr<const character::ImitationReference>> imitations_;
  character::EarlyTermination early_;
  int reference_ = -1;
  std::optional<base::Json> landing_;
  // Sport primitive
  std::unique_ptr<character::PoseBridge> bridge_;
  std::optional<StrideRecorder> strides_;
  std::vector<std::vector<double>> completed_;
};

const char* to_string(SprintEnv::Outcome outcome);

}  // namespace podium::tasks::sprint
