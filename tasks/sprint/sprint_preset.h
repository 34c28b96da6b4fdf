#pragma once
/// The sprint's preset data (tasks/sprint/data/presets.json): track length, N_norm, reward
/// weights and kernels, drag, the episode's time limit, and the per-episode domain-randomisation
/// ranges (sprint seed §2 "Initial State" names wind and runway friction, not their ranges: the
/// ranges are ours).
#include <string>

#include "drag.h"
#include "podium/base/config.h"
#include "podium/base/rng.h"
#include "podium/character/imitation.h"
#include "sprint_rewards.h"
#include "steps.h"
#include "track.h"

namespace podium::tasks::sprint {

struct Range {
  double lo = 0.0, hi = 0.0;
};

/// The Start phase (§3.1): the imitation term's weight λ_i and r_I's weights and kernels
/// (character/imitation.h; DeepMimic's by default), early termination, and the references' first
/// landing (crouch_start.h).
struct StartPreset {
  double imitation_weight = 10.0;  ///< λ_i: reward r_base + λ_i·r_I (presets: 10)
  character::ImitationWeights weights;
  double max_com_deviation_m = 0.5;  ///< ends the episode when the COM is this far from the reference's
  double min_pose_reward = 0.0;      ///< ends it when r_p falls to this (0: never)
  double landing_x_m = 0.5;          ///< the references' first landing, m past the line
  double extra_time_s = 0.5;         ///< a Start not landed by its reference's duration plus this has failed
};

/// The race report (race.h): how many DR episodes it runs (smoke a few, quick 20, paper 100).
struct RacePreset {
  int episodes = 20;
};

/// The Dip Finish (§3.3): an episode that does not reach the line (a fall, leaving the lane, the
/// time limit) scores this time from its snapshot; above the episode's time limit, so that every
/// finisher beats every fall.
struct DipPreset {
  double fall_penalty_s = 60.0;
};

struct SprintPreset {
  TrackSpec track;
  StepCounterConfig steps;
  RewardWeights rewards;
  DragConfig drag;
  Range wind_mps{-2.0, 2.0};   ///< wind along the track, U(lo, hi); +2.0 is the record-legal limit
  Range friction{0.8, 1.2};    ///< runway μ, U(lo, hi)
  double time_limit_s = 30.0;  ///< an episode is truncated after this long (control steps: ⌈T·f_control⌉)
  StartPreset start;
  RacePreset race;
  DipPreset dip;
};

/// One episode's domain-randomisation draw (§2 "Initial State"), recorded with the episode.
struct EpisodeDraw {
  double wind_mps = 0.0;  ///< along the track (+: tailwind)
  double friction = 1.0;  ///< runway μ
  base::Json to_json() const { return {{"wind_mps", wind_mps}, {"friction", friction}}; }
};
/// Draws wind then μ, each uniform in the preset's range.
EpisodeDraw draw_episode(const SprintPreset& preset, base::Rng& rng);

/// Reads one preset object (every key optional, defaults as above); errors name the JSON path.
SprintPreset read_sprint_preset(base::ConfigReader& reader);
/// The preset `name` ("smoke", "quick", "paper") of the shipped presets.json. Throws
/// base::UserError naming the file and the name when it has no such preset.
SprintPreset load_sprint_preset(const std::string& name);
/// The shipped presets file.
std::string sprint_presets_file();

}  // namespace podium::tasks::sprint
