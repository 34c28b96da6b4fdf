#pragma once
/// The race report (sprint seed §3, the three phases in sequence): over N DR episodes, the Start
/// policy from the blocks, the stage-2 (accelerate) policy from the first landing, an optional dip
/// on top of it (§3.3) to the line, a fall or a lane exit; per episode the finish time, 10 m splits,
/// speed profile, top speed, steps, step length and frequency per segment, trunk lean per step, the
/// rise distance, left/right asymmetry, the DR draw and the motion; the paired wind check.
///
/// The measures are pure functions of sampled sequences (one sample per control step), tested on
/// scripted ones; run_race drives the environments.
#include <atomic>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "dip.h"
#include "podium/base/config.h"
#include "podium/base/json.h"
#include "podium/character/evaluator.h"
#include "podium/sim/model.h"
#include "sprint_env.h"
#include "sprint_preset.h"
#include "steps.h"
#include "user_start.h"

namespace podium::tasks::sprint {

// ---- Measures on sampled sequences -----------------------------------------------------------

/// Cumulative split times at x = split_m, 2·split_m, … below `length_m`: the first time the
/// torso's front `front_x_m` reaches each mark, linear between samples (times `t_s`); stops at the
/// first mark not reached. A given finish time is appended as the last split.
std::vector<double> split_times(const std::vector<double>& t_s, const std::vector<double>& front_x_m, double split_m,
                                double length_m, std::optional<double> finish_s);

/// A counted step (steps.h): when (s) and where (the landing foot's centroid x) it touched down,
/// with which foot, and the index of the sample at which it counted.
struct Touchdown {
  double t_s = 0.0, x_m = 0.0;
  Foot foot = Foot::left;
  std::size_t sample = 0;
};

/// The steps whose touchdown lies in [from_m, to_m): a step is the interval from one counted
/// touchdown to the next (so the first touchdown, out of the blocks, starts the first step).
struct SegmentSteps {
  double from_m = 0.0, to_m = 0.0;
  int steps = 0;
  double length_m = 0.0;      ///< mean step length (0 when no step)
  double frequency_hz = 0.0;  ///< steps over their summed durations (0 when no step)
};
/// Per segment of `segment_m` from 0 to `length_m` (the last one shorter when it does not divide).
std::vector<SegmentSteps> steps_by_segment(const std::vector<Touchdown>& touchdowns, double segment_m, double length_m);

/// Left/right asymmetry of the steps (step i: touchdown i−1 to i, by the foot of touchdown i):
/// each side's mean length and duration, and the symmetry index |L − R| / ((L + R)/2) of each
/// (0: symmetric; Robinson et al. 1987). Indices are 0 without a step on both sides.
struct StepAsymmetry {
  int left_steps = 0, right_steps = 0;
  double left_length_m = 0.0, right_length_m = 0.0, length_index = 0.0;
  double left_time_s = 0.0, right_time_s = 0.0, time_index = 0.0;
  base::Json to_json() const;
};
StepAsymmetry step_asymmetry(const std::vector<Touchdown>& touchdowns);

/// The trunk's mean lean over each step: samples from touchdown i's (included) to touchdown
/// i+1's (excluded), the last step to the end of the samples.
std::vector<double> lean_per_step(const std::vector<Touchdown>& touchdowns, const std::vector<double>& lean_rad);

/// Mean speed over each bin of `bin_m` from 0 to `length_m` (run_metrics' segment_speed of the
/// root's x); nullopt for a bin the run did not cover.
std::vector<std::optional<double>> speed_profile(const std::vector<double>& t_s, const std::vector<double>& x_m, double bin_m,
                                                 double length_m);
/// The highest mean speed over a window of `window_m` (starts every `step_m` from 0) and the
/// window's centre; nullopt when the run covers no whole window.
struct SpeedPeak {
  double speed_mps = 0.0, at_m = 0.0;
};
std::optional<SpeedPeak> top_speed(const std::vector<double>& t_s, const std::vector<double>& x_m, double window_m,
                                   double step_m);

// ---- The race --------------------------------------------------------------------------------

struct RaceSettings {
  std::string track = "smoke";  ///< the presets.json entry
  double sim_hz = 600.0;
  int episodes = 0;             ///< 0: the preset's race.episodes
  std::uint64_t seed = 52'409;  ///< the episodes' seeds and draws derive from it (not the training's)
  /// The dip (§3.3; dip.h's DipTrigger and DipActions, the dip stage's): none by default. With one,
  /// every episode also runs without it (the dip check, paired).
  std::optional<DipParams> dip;
  bool wind_check = true;           ///< the paired headwind/tailwind runs
  double wind_check_mps = 2.0;      ///< their wind: −this and +this, μ as drawn
  double split_m = 10.0;            ///< splits and the step segments
  double profile_bin_m = 1.0;       ///< the speed profile's bins
  double top_speed_window_m = 5.0;  ///< the top speed's window
  double rise_lean_deg = 20.0;      ///< the rise: the trunk's lean below this for good
  int record = 1;                   ///< motions written: the first this many DR episodes
  /// The Start's user clips (its references besides the crouch starts): the Start policy observes
  /// which reference it runs, so the race draws from the same set it trained on.
  std::vector<StartClipSpec> start_clips;
};
/// Reads the race's keys (`race_…`); track, sim_hz and the rise threshold are the shared keys.
void read_race_settings(base::ConfigReader& r, RaceSettings& s);

/// One race episode's figures (JSON: its to_json()).
struct RaceEpisode {
  int index = 0;
  std::uint64_t seed = 0;
  EpisodeDraw draw;
  std::string reference;  ///< the crouch start drawn
  std::string outcome;    ///< finished, fell, left_lane, time_limit, or no_landing (the Start phase ended without one)
  std::optional<double> finish_time_s, landing_time_s;
  double distance_m = 0.0;  ///< the root's x at the end minus at the start
  std::vector<double> splits_s;
  std::vector<std::optional<double>> speed_profile_mps;
  std::optional<SpeedPeak> top_speed;
  int steps = 0;                                        ///< counted steps to the end (to the line for a finisher)
  double step_length_m = 0.0, step_frequency_hz = 0.0;  ///< over the whole run (0 without a step)
  std::vector<SegmentSteps> segments;
  std::vector<double> lean_per_step_rad;
  double first_segment_lean_rad = 0.0;  ///< the mean trunk lean while the root is in the first segment
  std::optional<double> rise_distance_m;
  StepAsymmetry asymmetry;
  std::optional<double> dip_x_m;  ///< the root's x when the dip fired
  base::Json to_json() const;
};

/// The policies a race runs (TorchScript or checkpoint files, learn::FrozenPolicy).
struct RacePolicies {
  std::filesystem::path start, accelerate;
};
/// The same as functions (observation ↦ action), e.g. scripted ones in tests.
struct RacePolicyFns {
  character::PolicyFn start, accelerate;
};

/// The two phases' environments: the Start mode on the preset's crouch starts (no early
/// termination on a deviation from the reference: a training device), and stage 2 (plain mode).
struct RaceEnvSettings {
  SprintEnvSettings start, accelerate;
};
RaceEnvSettings race_env_settings(const RaceSettings& settings);

/// What a race wrote and found.
struct RaceReport {
  RaceSettings settings;
  double length_m = 0.0, time_limit_s = 0.0;  ///< the track, the race's time limit (a DNF counts at it)
  std::vector<RaceEpisode> episodes;
  std::vector<RaceEpisode> headwind, tailwind;  ///< the wind check, episode by episode (empty without it)
  std::vector<RaceEpisode> no_dip;              ///< the dip check: each episode without the dip (empty without one)
  base::Json summary() const;                   ///< the figures over the episodes and the two checks
  std::string text_table() const;               ///< the plain-text report a researcher reads
  base::Json result_table() const;              ///< one row per episode (plugins::result_table)
  base::Json to_json() const;                   ///< settings, summary, every episode (and the checks')
  std::vector<std::filesystem::path> motions;   ///< the recorded episodes' trajectory files
};

/// Runs the race in `work_dir` (motions under work_dir/rollouts/race). `progress` gets the
/// fraction done after each episode; a set `cancel` stops it (std::runtime_error). Throws
/// base::UserError when a policy does not fit the environment.
RaceReport run_race(const RaceSettings& settings, const RacePolicies& policies, const std::filesystem::path& work_dir,
                    const std::atomic<bool>* cancel = nullptr, const std::function<void(double)>& progress = {});
/// The same with policy functions (no fit check).
RaceReport run_race(const RaceSettings& settings, const RacePolicyFns& policies, const std::filesystem::path& work_dir,
                    const std::atomic<bool>* cancel = nullptr, const std::function<void(double)>& progress = {});

}  // namespace podium::tasks::sprint
