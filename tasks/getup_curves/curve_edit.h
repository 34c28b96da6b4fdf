#pragma once
/// Edits of a style curve (curve get-up seed §4.3: the user edits the curves to author a style):
/// shift the rise in time, scale the duration T, move one control point. Each returns a new
/// curve and leaves its argument alone; each throws base::UserError naming the curve, the edit
/// and the value when the result would not be a valid curve file.
#include <string>

#include "style_curve.h"

namespace podium::tasks::getup_curves {

/// The rise time (s): the first t in [0, T] at which p_h(t/T) reaches half of p_h(1), the height
/// it stands at (the quick bar's "first passes 50% of standing height" read on the target).
/// Throws when p_h(0) is already there (nothing rises).
double rise_time_s(const StyleCurve& curve);

/// The curve with its rise `shift_s` seconds later (earlier when negative), T, the first and the
/// last control points kept: every feature is re-timed by one monotone warp of [0, T] onto itself
/// that takes the new rise time t_r + shift_s to t_r (a monotone cubic Hermite through
/// (0, 0), (t_r + shift_s, t_r), (T, T), Fritsch–Butland slopes), and the 7 inner control points
/// are then the least-squares fit of the warped curve at 400 instants (clamped to the file's
/// ranges). A shift of 0 returns the curve (to round-off). The new rise must lie inside (0, T).
StyleCurve shift_rise(const StyleCurve& curve, double shift_s);

/// The same control points over factor · T (the same shape, slower or faster).
StyleCurve scale_duration(const StyleCurve& curve, double factor);

/// Control point `index` (0–8) of `feature` ("h", "theta_x" or "theta_z") moved by `delta` in the
/// file's units (m for h, degrees for the angles); the result must stay in the file's range.
StyleCurve move_control_point(const StyleCurve& curve, const std::string& feature, int index, double delta);

}  // namespace podium::tasks::getup_curves
