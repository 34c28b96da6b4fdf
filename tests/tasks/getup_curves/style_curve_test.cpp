// Style curves (curve get-up seed §4.1, eq. 1): the clamped cardinal cubic B-spline, and curve
// files read with errors at their JSON path.
#include "style_curve.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numbers>

#include "config_errors.h"
#include "podium/base/rng.h"

namespace podium::tasks::getup_curves {
namespace {

using base::Json;

StyleCurve random_curve(base::Rng& rng) {
  StyleCurve c;
  c.name = "random";
  c.duration_s = 2.5;
  for (int k = 0; k < kControlPoints; ++k)
    c.points.col(k) << rng.uniform(0.1, 1.6), rng.uniform(0.0, std::numbers::pi), rng.uniform(0.0, std::numbers::pi);
  c.start = {CurveStart::Kind::drop, "", 0, false};
  c.source = "authored";
  return c;
}

TEST(BSpline, BasisIsAPartitionOfUnityAndEqualPointsGiveAConstant) {
  StyleCurve c;
  c.points.row(0).setConstant(0.42);
  c.points.row(1).setConstant(1.1);
  c.points.row(2).setConstant(0.0);
  for (int i = 0; i <= 200; ++i) {
    const double s = i / 200.0;
    const auto basis = bspline_basis(s);
    EXPECT_NEAR(basis.sum(), 1.0, 1e-12) << s;
    EXPECT_GE(basis.minCoeff(), 0.0) << s;
    EXPECT_LE(basis.count(), 4) << s;  // cubic: at most four non-zero
    const StyleFeatures p = c.at(s);
    EXPECT_NEAR(p(0), 0.42, 1e-12);
    EXPECT_NEAR(p(1), 1.1, 1e-12);
    EXPECT_NEAR(p(2), 0.0, 1e-12);
  }
}

TEST(BSpline, HitsItsEndControlPointsAndNotTheInnerOnes) {
  base::Rng rng(3);
  for (int trial = 0; trial < 20; ++trial) {
    const StyleCurve c = random_curve(rng);
    EXPECT_LT((c.at(0.0) - c.points.col(0)).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((c.at(1.0) - c.points.col(kControlPoints - 1)).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_LT((c.at(1.0 - 1e-9) - c.points.col(kControlPoints - 1)).cwiseAbs().maxCoeff(), 1e-6);  // continuous at the end
    // The inner points are approximated: the middle one equals p(1/2) only by coincidence.
    if (trial == 0) {
      EXPECT_GT((c.at(0.5) - c.points.col(4)).cwiseAbs().maxCoeff(), 1e-3);
    }
  }
  // A line through the knots' Greville abscissae (0, 1/18, 1/6, 1/3, …) is reproduced (linear precision).
  const double greville[kControlPoints] = {0.0, 1.0 / 18, 1.0 / 6, 1.0 / 3, 0.5, 2.0 / 3, 5.0 / 6, 17.0 / 18, 1.0};
  StyleCurve line;
  for (int k = 0; k < kControlPoints; ++k) line.points.col(k) << 0.2 + greville[k], 0.5, 1.0 - 0.5 * greville[k];
  for (double s : {0.1, 0.37, 0.5, 0.81}) {
    EXPECT_NEAR(line.at(s)(0), 0.2 + s, 1e-12);
    EXPECT_NEAR(line.at(s)(2), 1.0 - 0.5 * s, 1e-12);
  }
}

TEST(BSpline, CurveParameterIsEquationOne) {
  EXPECT_DOUBLE_EQ(curve_parameter(3.0, 2.0, 4.0), 0.25);
  EXPECT_EQ(curve_parameter(7.0, 2.0, 4.0), 1.0);
  EXPECT_EQ(curve_parameter(1.0, 2.0, 4.0), 0.0);
  base::Rng rng(5);
  const StyleCurve c = random_curve(rng);
  EXPECT_EQ(c.target(10.0, 1.0), c.at(1.0));
  EXPECT_EQ(c.target(1.0 + 1.25, 1.0), c.at(0.5));
}

TEST(CurveFile, RoundTripsThroughJson) {
  base::Rng rng(7);
  StyleCurve c = random_curve(rng);
  const auto path = std::filesystem::temp_directory_path() / "podium_getup_curves_roundtrip.json";
  for (const CurveStart& start :
       {CurveStart{CurveStart::Kind::drop, "", 0, false}, CurveStart{CurveStart::Kind::drop, "", 0, true},
        CurveStart{CurveStart::Kind::clip, "motions/getup.txt", 12, true}}) {
    c.start = start;
    save_style_curve(path, c);
    const StyleCurve back = load_style_curve(path);
    EXPECT_EQ(back.name, c.name);
    EXPECT_EQ(back.source, c.source);
    EXPECT_EQ(back.duration_s, c.duration_s);
    EXPECT_LT((back.points - c.points).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_EQ(back.start.kind, start.kind);
    EXPECT_EQ(back.start.clip, start.clip);
    EXPECT_EQ(back.start.frame, start.frame);
    if (start.kind == CurveStart::Kind::drop) {
      EXPECT_EQ(back.start.supine, start.supine);
    }
  }
  std::filesystem::remove(path);
}

Json good_curve() {
  return Json{{"name", "faceup"},
              {"duration_s", 3.1},
              {"control_points",
               {{"h_m", {0.2, 0.3, 0.5, 0.8, 1.0, 1.2, 1.4, 1.45, 1.45}},
                {"theta_x_deg", {90, 90, 90, 90, 90, 90, 90, 90, 90}},
                {"theta_z_deg", {5, 20, 45, 70, 80, 85, 90, 90, 90}}}},
              {"start", {{"drop", "supine"}}}};
}

std::string error_path(const Json& config) { return podium::testing::config_error_path(config, read_style_curve); }

TEST(CurveFile, BadEntriesNameTheirJsonPath) {
  EXPECT_EQ(error_path(good_curve()), "(accepted)");
  Json c = good_curve();
  c["control_points"]["theta_x_deg"][2] = 200;
  EXPECT_EQ(error_path(c), "control_points.theta_x_deg[2]");
  c = good_curve();
  c["control_points"]["h_m"].erase(3);
  EXPECT_EQ(error_path(c), "control_points.h_m");
  c = good_curve();
  c["duration_s"] = 0;
  EXPECT_EQ(error_path(c), "duration_s");
  c = good_curve();
  c["start"] = {{"drop", "sideways"}};
  EXPECT_EQ(error_path(c), "start.drop");
  c = good_curve();
  c["start"] = {{"drop", "prone"}, {"clip", "a.txt"}};
  EXPECT_EQ(error_path(c), "start.clip");
  c = good_curve();
  c["start"] = Json::object();
  EXPECT_EQ(error_path(c), "start.clip");
  c = good_curve();
  c["start"] = {{"drop", "prone"}, {"frame", 3}};
  EXPECT_EQ(error_path(c), "start.frame");
  c = good_curve();
  c["control_points"]["theta_y_deg"] = c["control_points"]["theta_x_deg"];
  EXPECT_EQ(error_path(c), "control_points.theta_y_deg");
  c = good_curve();
  c.erase("name");
  EXPECT_EQ(error_path(c), "name");
}

TEST(CurveFile, ErrorLineNamesTheFilePathAndValue) {
  Json c = good_curve();
  c["control_points"]["h_m"][4] = -0.5;
  const auto path = std::filesystem::temp_directory_path() / "podium_getup_curves_bad.json";
  std::ofstream(path) << c.dump();
  try {
    load_style_curve(path);
    FAIL() << "expected a ConfigError";
  } catch (const base::ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path.string() + ": control_points.h_m[4]: -0.5"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  c = good_curve();
  c["control_points"]["theta_z_deg"] = {1, 2, 3};
  std::ofstream(path) << c.dump();
  try {
    load_style_curve(path);
    FAIL() << "expected a ConfigError";
  } catch (const base::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string() + ": control_points.theta_z_deg: [1,2,3] has 3 entries; a curve has 9"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace podium::tasks::getup_curves
