#pragma once
/// Evaluation of a policy over fixed starts (get-up seed App. D: "evaluated ... over 10
/// episodes" from fixed starts; the get-up evaluation's 20 unseen falls): success rate, mean return, the
/// task's per-episode measures, and chosen rollouts recorded as `trajectory` artifacts.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <span>
#include <string>
#include <vector>

#include "podium/character/character_env.h"

namespace podium::character {

/// The policy under test: observation ↦ action (e.g. a learner's deterministic act()).
using PolicyFn = std::function<void(std::span<const double> observation, std::span<double> action)>;

struct EpisodeMeasure {
  std::string name;                                   ///< e.g. "final_head_height_m"
  std::function<double(const CharacterEnv&)> at_end;  ///< read when the episode ends
};

struct EvaluationConfig {
  std::vector<std::uint64_t> start_seeds;  ///< one episode per seed: env.seed(s) then reset()
  std::vector<EpisodeMeasure> measures;
  /// Success of an episode, read at its end (e.g. head above 1.2 m); none: no success rate.
  std::function<bool(const CharacterEnv&)> success;
  /// Called after the reset and after every step with the start's index (per-step statistics:
  /// when the head first passes a height, which bodies carry weight).
  std::function<void(std::size_t start, const CharacterEnv&)> each_step;
  std::vector<std::size_t> record;   ///< indices into start_seeds whose rollouts are written
  std::filesystem::path record_dir;  ///< where: trajectory_<index>.jsonl
  /// Frames per second a recording needs at least (a smooth replay of a short motion, e.g. a jump
  /// at 10–30 Hz control); 0: one frame per control step. Frames are the World's states every k
  /// simulation steps, k the largest divisor of the control period that gives ≥ record_min_hz (every
  /// simulation step if none does), so the control steps' frames are among them; nothing else the
  /// evaluation computes changes.
  double record_min_hz = 0.0;
};

struct EvaluationReport {
  std::vector<double> returns;                          ///< per start
  std::vector<char> successes;                          ///< per start (empty without `success`)
  std::map<std::string, std::vector<double>> measures;  ///< name → per start
  std::vector<std::filesystem::path> trajectories;      ///< of the recorded starts, in start order
  double mean_return = 0.0;
  double success_rate = 0.0;  ///< 0 without `success`
  /// The mean over the starts of a configured measure (throws std::out_of_range for another name).
  double mean(const std::string& measure) const;
  base::Json to_json() const;
};

/// Runs one episode per start seed (the env's generator is re-seeded, so starts are fixed and
/// independent of what ran before). Recorded rollouts are sim::write_trajectory files, one frame
/// per control step (or denser: record_min_hz) from the start state on.
EvaluationReport evaluate(CharacterEnv& env, const PolicyFn& policy, const EvaluationConfig& config);

}  // namespace podium::character
