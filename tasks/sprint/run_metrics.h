#pragma once
/// The Acceleration + Top Speed stage's per-episode measures (sprint seed §3.2), as pure functions
/// of sampled sequences (one sample per control step), so each is tested on scripted sequences.
#include <optional>
#include <vector>

namespace podium::tasks::sprint {

/// The rise distance: the root's x at the first sample from which the trunk's lean from vertical
/// stays below `threshold_rad` to the end ("for good"); nullopt when the last sample leans at or
/// above it (or there are none). `x_m` and `lean_rad` are of equal length.
std::optional<double> rise_distance(const std::vector<double>& x_m, const std::vector<double>& lean_rad, double threshold_rad);

/// Feet on the ground at one sample.
struct FootContacts {
  bool left = false, right = false;
};
/// Whether every stride that begins at x ≥ `from_x_m` has a flight phase: a stride runs from one
/// touchdown (a foot down that was up at the sample before) to the next, and needs a sample
/// between them (from the first touchdown's, the next's excluded) with neither foot down. False
/// when no whole stride begins there (the window is too short to tell).
bool flight_in_every_stride(const std::vector<double>& x_m, const std::vector<FootContacts>& contacts, double from_x_m);

/// Mean speed over [from_x_m, to_x_m] of a sampled run (`t_s` increasing, `x_m` the root's x):
/// (to − from) over the time between the first crossings of each, linear between samples; when the
/// run ends before `to_x_m` and `to_end` is set, over [from, its last x] (a finish judged by the
/// torso's front ends the episode before the root reaches the line); nullopt when it never reaches
/// `from_x_m` or covers no distance past it.
std::optional<double> segment_speed(const std::vector<double>& t_s, const std::vector<double>& x_m, double from_x_m,
                                    double to_x_m, bool to_end = false);

}  // namespace podium::tasks::sprint
