#pragma once
/// The Dip Finish (sprint seed §3.3): two numbers on top of the frozen Acceleration + Top Speed
/// policy — d_dip, the root's distance to the finish line at which the dip fires (the seed's
/// "dipping moment", one to five metres from the line), and θ_dip, the tilt (0° to 90°). From the
/// first control step at which the root is within d_dip of the line, θ_dip is added to both hips'
/// flexion targets (and, as an option, to the chest's forward pitch) on top of the policy's
/// deterministic action: the trunk pitches forward at the hips and reaches the plane sooner.
///
/// A candidate (d_dip, θ_dip) is judged by its mean time over a fixed set of episodes, each
/// replayed from a snapshot taken before the line in stage-2 runs (hand-over states with their
/// DR draws; a snapshot without a draw takes one from a fixed seed, the same for every candidate:
/// common random numbers). An episode's time runs from its snapshot to the finish (FinishLine:
/// the torso's front, interpolated within the simulation step); an episode that does not finish
/// (a fall, leaving the lane, the time limit) scores the preset's fixed penalty.
#include <Eigen/Core>
#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "podium/base/config.h"
#include "podium/character/evaluator.h"
#include "sprint_env.h"

namespace podium::tasks::sprint {

/// One dip: d_dip and θ_dip (§3.3; the seed's initial guess is 5 m, 30°).
struct DipParams {
  double distance_m = 5.0;  ///< d_dip: fires at the first control step with the root this close to the line
  double angle_deg = 30.0;  ///< θ_dip
};

/// The dip's change to a TargetActions action (a pose: an angle per hinge, an exponential map per
/// ball joint, in the model's link order).
class DipActions {
 public:
  /// Throws base::UserError naming the model when it has no ball joints left_hip and right_hip
  /// (or chest, with `chest`) under the root.
  DipActions(const sim::ModelPtr& model, bool chest);
  /// Turns both hips' targets by θ in flexion (about the pelvis's lateral axis, thigh forward) and,
  /// with the chest option, the chest's by θ in forward pitch: the rotation composed before the
  /// target's, in the parent's frame. θ = 0 leaves the action untouched (bitwise).
  void apply(double angle_rad, std::span<double> action) const;
  bool chest() const { return !chest_.empty(); }

 private:
  std::vector<std::size_t> hips_, chest_;  // each ball joint's first entry in the pose
};

/// The firing rule (§3.3), the one the dip stage and the race apply: the dip fires at the first
/// control step at which the root is within d_dip of the line and stays on to the episode's end.
class DipTrigger {
 public:
  /// `actions` must outlive the trigger; `length_m` is the track's.
  DipTrigger(const DipParams& dip, const DipActions& actions, double length_m);
  /// Before control step `step`: with the root at `root_x_m`, fires if due and, once fired,
  /// changes the policy's `action`.
  void apply(int step, double root_x_m, std::span<double> action);
  int fired_step() const { return fired_step_; }                 ///< −1: not (yet) fired
  double fired_distance_m() const { return fired_distance_m_; }  ///< the root's distance to the line then
  double fired_x_m() const { return fired_x_m_; }                ///< the root's x then

 private:
  DipParams dip_;
  const DipActions* actions_;
  double length_m_, angle_rad_;
  int fired_step_ = -1;
  double fired_distance_m_ = 0.0, fired_x_m_ = 0.0;
};

/// One episode of the dip from a snapshot.
struct DipEpisode {
  std::string outcome;            ///< SprintEnv::Outcome's name at the end
  bool finished = false;          ///< the torso reached the plane without a fall or leaving the lane
  double start_time_s = 0.0;      ///< the World's clock at the snapshot (the race's, as snapshots keep it)
  double finish_time_s = 0.0;     ///< on the World's clock (finishers; else 0)
  double time_s = 0.0;            ///< from the snapshot to the finish, or the penalty
  int fired_step = -1;            ///< the control step (from the snapshot) at which the dip fired; −1: never
  double fired_distance_m = 0.0;  ///< the root's distance to the line then
  int control_steps = 0;
  EpisodeDraw draw;
  base::Json to_json() const;
};

/// Called after the reset (step −1, empty action) and after every step with the action applied.
using DipStepFn = std::function<void(int step, const SprintEnv& env, std::span<const double> action)>;

/// Runs one episode of `env` (whose settings hold the snapshot as its one hand-over state) from
/// generator seed `seed`: the policy's action each control step, the dip applied from the step it
/// fires (none without `dip`). `fall_penalty_s` is an unfinished episode's time.
DipEpisode run_dip_episode(SprintEnv& env, std::uint64_t seed, const character::PolicyFn& policy, const DipActions& actions,
                           const std::optional<DipParams>& dip, double fall_penalty_s, const DipStepFn& each_step = {});

struct DipSettings {
  std::string track = "smoke";  ///< the presets.json entry (track, DR, time limit, dip.fall_penalty_s)
  double sim_hz = 600.0;
  int episodes = 4;             ///< the snapshots used (the first ones), at most as many as given
  bool chest = false;           ///< also pitch the chest (DipActions)
  std::uint64_t seed = 20'240;  ///< the episodes' generator seeds derive from it (the same for every candidate)
};

/// Reads the stage's own keys (dip_episodes, dip_chest); track, sim_hz and seed are the shared
/// keys' (read_start_train_settings: track, sim_hz, eval_seed).
void read_dip_settings(base::ConfigReader& r, DipSettings& s);

/// The mean of a set of dip episodes.
struct DipSummary {
  double mean_time_s = 0.0;  ///< the fitness: mean time from the snapshot (penalties included)
  double finish_rate = 0.0;
  double mean_finish_time_s = 0.0;  ///< finishers' mean finish time on the race's clock (0: none)
  double fired_rate = 0.0;          ///< episodes in which the dip fired
  static DipSummary of(const std::vector<DipEpisode>& episodes);
  base::Json to_json() const;
};

/// A fixed set of dip episodes: one env per snapshot, each episode from the same seed whatever
/// the candidate (common random numbers).
class DipEvaluator {
 public:
  /// Throws base::UserError when there are no snapshots.
  DipEvaluator(const DipSettings& settings, const std::vector<base::Json>& snapshots);
  /// Every episode, in snapshot order, with `dip` (none: the policy alone). A set `cancel` stops
  /// it between episodes (std::runtime_error).
  std::vector<DipEpisode> run(const character::PolicyFn& policy, const std::optional<DipParams>& dip,
                              const std::atomic<bool>* cancel = nullptr);
  std::size_t size() const { return envs_.size(); }
  /// The first snapshot's env (its observation and action spaces are every env's).
  const SprintEnv& env() const { return *envs_.front(); }
  double fall_penalty_s() const { return penalty_s_; }

 private:
  DipSettings s_;
  std::vector<std::unique_ptr<SprintEnv>> envs_;
  std::unique_ptr<DipActions> actions_;
  double penalty_s_ = 0.0;
};

}  // namespace podium::tasks::sprint
