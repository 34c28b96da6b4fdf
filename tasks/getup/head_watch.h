#pragma once
/// How the head top moved over one episode, against a height (e.g. 1.2 m): when it first passed
/// it, how often it fell back below it, its highest point and how long it has stayed above. A
/// get-up that stands passes once and stays (0 drops, a peak near the standing head top,
/// humanoid21: 1.56 m, and the head above for the episode's last seconds); a leap loop — rise,
/// fly, fall, rise again — passes and drops again and again with peaks far above standing
/// (every `quick` π_weak measured did that, 2–4 drops per 250 steps: tasks/getup/RESULTS.md),
/// and its head is above the height for under a second at a time, so `stood` tells the two apart
/// where the head's height at the episode's end alone samples the leap's phase.
#include <algorithm>
#include <vector>

namespace podium::tasks::getup {

struct HeadWatch {
  double height_m = 1.2;
  int first_step = -1;  ///< control step of the first pass above height_m; −1: never
  int drops = 0;        ///< passes back below height_m after being above it
  double peak_m = 0.0;  ///< highest head top seen
  int held = 0;         ///< control steps the head top has been above height_m without a break, to the last one seen

  void observe(int step, double head_m) {
    peak_m = std::max(peak_m, head_m);
    if (head_m > height_m) {
      if (first_step < 0) first_step = step;
      ++held;
    } else {
      if (above()) ++drops;
      held = 0;
    }
  }
  bool risen() const { return first_step >= 0; }
  bool above() const { return held > 0; }  ///< at the last step seen
  /// Up at the last step seen and for at least `steps` control steps before it without a break.
  bool stood(int steps) const { return held >= steps; }
};

/// Over the episodes whose head rose: how many, and their mean first-pass step, drops and peak
/// (all 0 when none rose); and how many stood for the last `stand_steps`.
struct HeadSummary {
  int risen = 0, stood = 0;
  double first_step = 0.0, drops = 0.0, peak_m = 0.0;
};

inline HeadSummary summarise_heads(const std::vector<HeadWatch>& heads, int stand_steps) {
  HeadSummary s;
  for (const HeadWatch& h : heads) {
    if (!h.risen()) continue;
    if (h.stood(stand_steps)) ++s.stood;
    ++s.risen;
    s.first_step += h.first_step, s.drops += h.drops, s.peak_m += h.peak_m;
  }
  if (s.risen > 0) s.first_step /= s.risen, s.drops /= s.risen, s.peak_m /= s.risen;
  return s;
}

/// Of the episodes that began on the back (`on_back`, one per episode: the torso's front axis
/// pointing up at the fall's end), how many there were, rose and stood: a get-up from the back
/// needs a sit-up or a roll, from the front a push-up, and a policy may know only one (the shipped
/// π_weak rises from none of its unseen falls on the back).
struct BackSummary {
  int falls = 0, risen = 0, stood = 0;
};

inline BackSummary summarise_back(const std::vector<HeadWatch>& heads, const std::vector<char>& on_back, int stand_steps) {
  BackSummary s;
  for (std::size_t i = 0; i < heads.size() && i < on_back.size(); ++i) {
    if (!on_back[i]) continue;
    ++s.falls;
    s.risen += heads[i].risen();
    s.stood += heads[i].risen() && heads[i].stood(stand_steps);
  }
  return s;
}

/// The episode a replay should show: the first that stood for the last `stand_steps`, else the
/// first whose head rose, else the first (a viewer sees the policy's best behaviour, not fall 0's
/// whatever it was; the summary's counts say how typical it is).
inline std::size_t shown_episode(const std::vector<HeadWatch>& heads, int stand_steps) {
  for (std::size_t i = 0; i < heads.size(); ++i)
    if (heads[i].risen() && heads[i].stood(stand_steps)) return i;
  for (std::size_t i = 0; i < heads.size(); ++i)
    if (heads[i].risen()) return i;
  return 0;
}

}  // namespace podium::tasks::getup
