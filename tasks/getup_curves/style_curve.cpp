#include "style_curve.h"

#include <algorithm>
#include <numbers>
#include <unsupported/Eigen/Splines>

namespace podium::tasks::getup_curves {

namespace {

using Spline = Eigen::Spline<double, 1, 3>;
constexpr int kDegree = 3;
constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// The clamped uniform knot vector of §4.1's cubic B-spline (style_curve.h): 9 + 3 + 1 knots.
const Spline::KnotVectorType& knots() {
  static const Spline::KnotVectorType k = [] {
    constexpr int spans = kControlPoints - kDegree;
    Spline::KnotVectorType v(kControlPoints + kDegree + 1);
    for (int i = 0; i < v.size(); ++i) v(i) = std::clamp(static_cast<double>(i - kDegree) / spans, 0.0, 1.0);
    return v;
  }();
  return k;
}

// Keys of the control-point rows in a curve file, with their unit and range.
struct RowKey {
  const char* key;
  double scale;  // file value = scale · stored value
  base::Interval range;
  const char* doc;
};
const std::array<RowKey, 3>& row_keys() {
  static const std::array<RowKey, 3> rows{{
      {"h_m", 1.0, {.min = 0.0, .max = 3.0}, "neck-base height above the ground at the 9 control points (m)"},
      {"theta_x_deg", kDegPerRad, {.min = 0.0, .max = 180.0}, "side vector's angle to up at the 9 control points (°)"},
      {"theta_z_deg", kDegPerRad, {.min = 0.0, .max = 180.0}, "front vector's angle to up at the 9 control points (°)"},
  }};
  return rows;
}

ControlPoints read_points(base::ConfigReader& c) {
  ControlPoints points;
  for (int f = 0; f < 3; ++f) {
    const RowKey& row = row_keys()[static_cast<std::size_t>(f)];
    const std::vector<double> values = c.numbers(row.key, std::vector<double>(kControlPoints, 0.0), row.range, row.doc);
    if (values.size() != static_cast<std::size_t>(kControlPoints))
      c.fail(row.key, "has " + std::to_string(values.size()) + " entries; a curve has " + std::to_string(kControlPoints));
    for (int k = 0; k < kControlPoints; ++k) points(f, k) = values[static_cast<std::size_t>(k)] / row.scale;
  }
  return points;
}

CurveStart read_start(base::ConfigReader& c) {
  CurveStart start;
  const std::string drop = c.choice("drop", "none", {"none", "supine", "prone"}, "a ragdoll drop landing on the back or front");
  start.clip = c.string("clip", "", "a clip start: the DeepMimic-format motion file");
  start.frame = c.integer<int>("frame", 0, {.min = 0}, "a clip start: the frame the episode begins in");
  if (drop == "none" && start.clip.empty())
    c.fail("clip", R"(is missing: a start is either {"clip", "frame"} or {"drop": "supine" | "prone"})");
  if (drop != "none" && !start.clip.empty()) c.fail("clip", R"(beside "drop": a start is either a clip frame or a drop)");
  if (drop != "none" && c.has("frame")) c.fail("frame", "belongs to a clip start, not a drop");
  start.kind = drop == "none" ? CurveStart::Kind::clip : CurveStart::Kind::drop;
  start.supine = drop != "prone";
  return start;
}

}  // namespace

Eigen::Matrix<double, kControlPoints, 1> bspline_basis(double s) {
  s = std::clamp(s, 0.0, 1.0);
  const Eigen::DenseIndex span = Spline::Span(s, kDegree, knots());
  const Spline::BasisVectorType nonzero = Spline::BasisFunctions(s, kDegree, knots());
  Eigen::Matrix<double, kControlPoints, 1> basis = Eigen::Matrix<double, kControlPoints, 1>::Zero();
  for (int j = 0; j <= kDegree; ++j) basis(span - kDegree + j) = nonzero(j);
  return basis;
}

// Curve get-up seed eq. 1; times before the start hold the curve's first value.
double curve_parameter(double t_s, double t0_s, double duration_s) { return std::clamp((t_s - t0_s) / duration_s, 0.0, 1.0); }

StyleFeatures StyleCurve::at(double s) const { return points * bspline_basis(s); }

StyleCurve read_style_curve(base::ConfigReader& r) {
  StyleCurve curve;
  curve.name = r.string("name", base::required, "the curve's name");
  curve.duration_s = r.number("duration_s", base::required, {.min = 0.0, .max = 60.0, .exclusive_min = true},
                              "T of the seed's eq. 1: the get-up's duration (s)");
  curve.points = r.object("control_points", base::required, read_points, "the B-spline's control points per feature");
  curve.start = r.object("start", base::required, read_start, "where an episode on this curve begins");
  curve.source = r.string("source", "", "where the curve came from");
  return curve;
}

base::Json style_curve_json(const StyleCurve& curve) {
  base::Json points = base::Json::object();
  for (int f = 0; f < 3; ++f) {
    const RowKey& row = row_keys()[static_cast<std::size_t>(f)];
    std::vector<double> values(kControlPoints);
    for (int k = 0; k < kControlPoints; ++k) values[static_cast<std::size_t>(k)] = curve.points(f, k) * row.scale;
    points[row.key] = values;
  }
  base::Json start = curve.start.kind == CurveStart::Kind::clip
                         ? base::Json{{"clip", curve.start.clip}, {"frame", curve.start.frame}}
                         : base::Json{{"drop", curve.start.supine ? "supine" : "prone"}};
  return {{"name", curve.name},
          {"duration_s", curve.duration_s},
          {"control_points", points},
          {"start", start},
          {"source", curve.source}};
}

StyleCurve load_style_curve(const std::filesystem::path& path) {
  const base::Json json = base::read_json_file(path);
  return base::ConfigReader::parse(json, path.string(), read_style_curve);
}

void save_style_curve(const std::filesystem::path& path, const StyleCurve& curve) {
  base::write_json_file_atomic(path, style_curve_json(curve));
}

}  // namespace podium::tasks::getup_curves
