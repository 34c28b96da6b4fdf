#include "curve_edit.h"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "podium/base/error.h"

namespace podium::tasks::getup_curves {

namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr int kFitInstants = 400;

std::string number(double v) {
  std::ostringstream out;
  out.precision(6);
  out << v;
  return out.str();
}

// A monotone cubic Hermite map of [0, T] onto itself through (t_new, t_old): piece 1 runs
// (0, 0) → (t_new, t_old), piece 2 (t_new, t_old) → (T, T). End slopes are the pieces' secants,
// the middle one their harmonic mean (Fritsch & Butland), so both pieces are monotone
// (Fritsch & Carlson's region: α² + β² ≤ 9 with α = 1, β < 2).
struct RiseWarp {
  double t_new, t_old, duration;

  double operator()(double t) const {
    const double d0 = t_old / t_new, d1 = (duration - t_old) / (duration - t_new);
    const double middle = 2.0 * d0 * d1 / (d0 + d1);
    const bool first = t <= t_new;
    const double x0 = first ? 0.0 : t_new, x1 = first ? t_new : duration;
    const double y0 = first ? 0.0 : t_old, y1 = first ? t_old : duration;
    const double m0 = first ? d0 : middle, m1 = first ? middle : d1;
    const double h = x1 - x0, u = (t - x0) / h;
    const double h00 = (1 + 2 * u) * (1 - u) * (1 - u), h10 = u * (1 - u) * (1 - u), h01 = u * u * (3 - 2 * u),
                 h11 = u * u * (u - 1);
    return h00 * y0 + h10 * h * m0 + h01 * y1 + h11 * h * m1;
  }
};

// The file's range of each feature row (style_curve.h), in the curve's units.
double row_max(int feature) { return feature == 0 ? 3.0 : std::numbers::pi; }

}  // namespace

double rise_time_s(const StyleCurve& curve) {
  const double half = 0.5 * curve.at(1.0)(0);
  const auto above = [&](double s) { return curve.at(s)(0) >= half; };
  if (above(0.0))
    throw base::UserError("curve \"" + curve.name + "\": h starts at " + number(curve.at(0.0)(0)) +
                          " m, already half its end height " + number(curve.at(1.0)(0)) + " m: nothing rises");
  // The first of 2,000 steps at which h is up, then bisection inside it.
  constexpr int kSteps = 2000;
  double lo = 0.0, hi = 1.0;
  for (int i = 1; i <= kSteps; ++i) {
    if (!above(static_cast<double>(i) / kSteps)) continue;
    lo = static_cast<double>(i - 1) / kSteps;
    hi = static_cast<double>(i) / kSteps;
    break;
  }
  for (int i = 0; i < 50; ++i) (above(0.5 * (lo + hi)) ? hi : lo) = 0.5 * (lo + hi);
  return hi * curve.duration_s;
}

StyleCurve shift_rise(const StyleCurve& curve, double shift_s) {
  const double t_old = rise_time_s(curve), duration = curve.duration_s, t_new = t_old + shift_s;
  if (!std::isfinite(shift_s) || !(t_new > 0.0 && t_new < duration))
    throw base::UserError("curve \"" + curve.name + "\": --shift-rise " + number(shift_s) + " s moves its rise from " +
                          number(t_old) + " s to " + number(t_new) + " s, outside (0, " + number(duration) + ") s");
  const RiseWarp warp{t_new, t_old, duration};
  // Least squares for the 7 inner control points with the end ones held: A_inner x = f − A_ends c_ends.
  Eigen::MatrixXd a(kFitInstants + 1, kControlPoints - 2);
  Eigen::MatrixXd f(kFitInstants + 1, 3);
  for (int i = 0; i <= kFitInstants; ++i) {
    const double t = duration * i / kFitInstants;
    const auto basis = bspline_basis(t / duration);
    a.row(i) = basis.segment(1, kControlPoints - 2).transpose();
    const StyleFeatures ends = curve.points.col(0) * basis(0) + curve.points.col(kControlPoints - 1) * basis(kControlPoints - 1);
    f.row(i) = (curve.at(warp(t) / duration) - ends).transpose();
  }
  const Eigen::MatrixXd inner = a.colPivHouseholderQr().solve(f);
  StyleCurve out = curve;
  for (int feature = 0; feature < 3; ++feature)
    for (int k = 1; k < kControlPoints - 1; ++k)
      out.points(feature, k) = std::clamp(inner(k - 1, feature), 0.0, row_max(feature));
  std::ostringstream note;
  note << "; rise " << std::abs(shift_s) << " s " << (shift_s < 0 ? "earlier" : "later") << " (" << number(t_old) << " → "
       << number(t_new) << " s)";
  if (shift_s != 0.0) out.source += note.str();
  return out;
}

StyleCurve scale_duration(const StyleCurve& curve, double factor) {
  const double duration = curve.duration_s * factor;
  if (!std::isfinite(factor) || !(factor > 0.0) || !(duration <= 60.0))
    throw base::UserError("curve \"" + curve.name + "\": --scale-T " + number(factor) + " makes T " + number(duration) +
                          " s; T must lie in (0, 60] s");
  StyleCurve out = curve;
  out.duration_s = duration;
  if (factor != 1.0) out.source += "; T × " + number(factor);
  return out;
}

StyleCurve move_control_point(const StyleCurve& curve, const std::string& feature, int index, double delta) {
  const auto& names = style_feature_names();
  const auto it = std::find(names.begin(), names.end(), feature);
  const std::string edit = "--move " + feature + ":" + std::to_string(index) + ":" + number(delta);
  if (it == names.end())
    throw base::UserError("curve \"" + curve.name + "\": " + edit + ": no feature \"" + feature + "\" (h, theta_x or theta_z)");
  if (index < 0 || index >= kControlPoints)
    throw base::UserError("curve \"" + curve.name + "\": " + edit + ": control point " + std::to_string(index) +
                          " is not in [0, " + std::to_string(kControlPoints - 1) + "]");
  const int row = static_cast<int>(it - names.begin());
  const double scale = row == 0 ? 1.0 : kDegPerRad;  // file units per curve unit
  StyleCurve out = curve;
  out.points(row, index) += delta / scale;
  const double moved = out.points(row, index) * scale, max = row_max(row) * scale;
  if (!std::isfinite(delta) || moved < 0.0 || moved > max)
    throw base::UserError("curve \"" + curve.name + "\": " + edit + ": " + feature + " control point " + std::to_string(index) +
                          " would be " + number(moved) + (row == 0 ? " m" : "°") + ", outside [0, " + number(max) + "]");
  out.source += "; " + edit;
  return out;
}

}  // namespace podium::tasks::getup_curves
