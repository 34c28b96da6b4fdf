#pragma once
/// Style curves (curve get-up seed §4.1, §4.3, §5.5): per feature (h, θ_x, θ_z; style_features.h)
/// a cardinal cubic B-spline p(s), s ∈ [0, 1], of 9 control points, over a get-up of duration T.
///
/// Our reading of "cardinal cubic B-spline": a cubic B-spline on uniform knots (cardinal) whose
/// end knots are repeated four times (clamped, an open knot vector
/// [0,0,0,0, 1/6, …, 5/6, 1,1,1,1]), so p(0) and p(1) are the first and last control points and
/// the curve is C² between; the 7 inner control points pull the curve without lying on it. Equal
/// control points give that constant (partition of unity).
#include <Eigen/Core>
#include <filesystem>
#include <string>

#include "podium/base/config.h"
#include "podium/base/json.h"
#include "style_features.h"

namespace podium::tasks::getup_curves {

/// Control points per feature curve (§4.1: "nine control points are sufficient").
inline constexpr int kControlPoints = 9;
/// One row per feature (h m, θ_x rad, θ_z rad), one column per control point.
using ControlPoints = Eigen::Matrix<double, 3, kControlPoints>;

/// The 9 B-spline basis values at s (clamped to [0, 1]); they sum to 1. p(s) = C · basis(s).
Eigen::Matrix<double, kControlPoints, 1> bspline_basis(double s);
/// Eq. 1: s = min((t − t0)/T, 1), and 0 before t0.
double curve_parameter(double t_s, double t0_s, double duration_s);

/// Where an episode on the curve begins: a frame of a clip (flat ground), or a ragdoll drop
/// landing supine or prone (§5.2).
struct CurveStart {
  enum class Kind { clip, drop };
  Kind kind = Kind::drop;
  std::string clip;    ///< Kind::clip: the DeepMimic-format motion file, as written (not resolved here)
  int frame = 0;       ///< Kind::clip: its frame
  bool supine = true;  ///< Kind::drop: on the back (true) or the front
};

/// A style curve: what a get-up follows (§4, §5.5).
struct StyleCurve {
  std::string name;
  double duration_s = 1.0;  ///< T of eq. 1
  ControlPoints points = ControlPoints::Zero();
  CurveStart start;
  std::string source;  ///< where it came from ("extracted from …", "authored")

  /// p(s) for the three features.
  StyleFeatures at(double s) const;
  /// The targets at time t of a get-up begun at t0 (eq. 1).
  StyleFeatures target(double t_s, double t0_s = 0.0) const { return at(curve_parameter(t_s, t0_s, duration_s)); }
};

/// Reads a curve from a config object: {"name", "duration_s", "control_points": {"h_m": [9],
/// "theta_x_deg": [9], "theta_z_deg": [9]}, "start": {"clip", "frame"} | {"drop": "supine"|"prone"},
/// "source"}. Angles are written in degrees ([0, 180]), heights in metres ([0, 3]); base::ConfigError
/// names the JSON path and the value of a bad entry.
StyleCurve read_style_curve(base::ConfigReader& r);
/// The same object for a curve (read_style_curve's inverse up to round-off in the degrees).
base::Json style_curve_json(const StyleCurve& curve);
/// A curve file; errors begin with the file's path.
StyleCurve load_style_curve(const std::filesystem::path& path);
void save_style_curve(const std::filesystem::path& path, const StyleCurve& curve);

}  // namespace podium::tasks::getup_curves
