#pragma once
/// The Evaluate stage as one trial (seed §8): π_slow and its π_weak, from falls whose
/// seeds no training saw, at several speeds κ and fast (π_weak itself), and §8.3's paused motion.
/// Per speed: the success rate (standing with the head top above rise_height_m at the end), the
/// time to rise (first head top above it, from the fall's end), the COM tracking error over the
/// rise, and the motion of one fall as a trajectory artifact: at every speed the same fall, π_weak's
/// best at its own strength (the first that stood, else the first that rose, else the first). The
/// strategy features of π_weak's fast get-ups (strategy_features.h) are the trial's features.
#include "slower.h"
#include "strategy_features.h"

namespace podium::tasks::getup {

struct EvaluateConfig {
  int falls = 20;                ///< per speed (RESULTS.md's bars count 20)
  std::uint64_t falls_seed = 2;  ///< ≠ the tests' eval_seed; training draws its own streams
  std::vector<double> kappas = {0.25, 0.5, 0.75};
  double pause_at = 0.5;  ///< §8.3: the held frame, as a fraction of τ_fast
  int pause_steps = 40;   ///< control steps τ_fast holds it (before retiming)
  double pause_kappa = 0.5;
  std::vector<double> strengths;  ///< further strengths β for π_weak's fast runs
};

EvaluateConfig read_evaluate(base::ConfigReader& r);

/// One speed's results over the falls.
struct SpeedResult {
  std::string name;       ///< "fast", "fast_b0.9", "k0.25", ..., "pause"
  double kappa = 0.0;     ///< 0 for fast
  double strength = 0.0;  ///< β of a fast run (π_weak's own for "fast")
  double success_rate = 0.0;
  double rise_time_s = 0.0;  ///< mean over the falls whose head rose (NaN-free: 0 when none)
  int risen = 0;             ///< falls whose head rose at all
  int stood = 0;             ///< falls whose head top stayed above rise_height_m for the last stand_steps (not a leap's flight)
  int on_back = 0;           ///< falls that ended on the back (the chest's front axis pointing up)
  int risen_on_back = 0, stood_on_back = 0;  ///< of those: risen, stood (the rest of risen/stood are from the front or side)
  double drops = 0.0;                        ///< mean, over those, of the head's falls back below rise_height_m (standing: 0)
  double peak_head_m = 0.0;                  ///< mean, over those, of the highest head top (standing humanoid21: 1.56 m)
  double com_error_m = 0.0;                  ///< mean over the falls (0 for fast), each over the part of the rise it tracked
  double end_com_gap_m = 0.0;                ///< mean h'_com − h_com at the last rise step reached (0 for fast)
  double tracked_fraction = 0.0;             ///< mean share of the rise tracked before the 0.5 m deviation ended it (0 for fast)
  double fast_rise_time_s = 0.0;             ///< τ_fast's duration over the same falls (slow speeds)
  std::filesystem::path trajectory;
  base::Json to_json() const;
};

struct EvaluateOutcome {
  std::vector<SpeedResult> speeds;  ///< fast, each κ, pause
  StrategyFeatures features;        ///< of π_weak's fast get-ups
  int shown_fall = 0;               ///< the fall every speed's trajectory records (head_watch.h's shown_episode)
  base::Json to_json() const;
  const SpeedResult& at(const std::string& name) const;
};

/// π_slow (`slow_policy`; empty: fast runs only) with its teacher `weak`; work_dir receives rollouts/.
EvaluateOutcome run_evaluate(const Settings& s, const SlowerConfig& slower, const EvaluateConfig& c,
                             const std::filesystem::path& slow_policy, const WeakPolicy& weak,
                             const std::filesystem::path& work_dir, const std::atomic<bool>* cancel);

/// τ_fast with frame ⌊fraction·T⌋ held (velocities zero) for `steps` more frames (§8.3).
FastRollout paused(FastRollout fast, double fraction, int steps);

}  // namespace podium::tasks::getup
