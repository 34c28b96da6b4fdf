// The curve tool (`podium tool getup_curves extract|edit|stats`): edits in-process (a shift of 0
// and a scale of 1 give the same curve, a shifted rise lands where asked with the ends kept, a
// moved control point moves only itself), then through the real `podium` binary: edit round
// trips, extract equal to curve_extraction.h's functions (and the shipped faceup and facedown remade),
// stats on a small label file, and bad input as one line with exit 2. Clip tests skip with the
// reason printed when ../shared/data is absent.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <tuple>

#include "curve_edit.h"
#include "curve_extraction.h"
#include "curve_stats.h"
#include "podium/base/json.h"
#include "podium/sim/model.h"
#include "process.h"
#include "shared_data.h"

namespace podium::tasks::getup_curves {
namespace {

namespace fs = std::filesystem;
using base::Json;
using podium::testing::run_podium;
using podium::testing::TempDir;
using podium::testing::write_file;

constexpr double kDeg = std::numbers::pi / 180.0;

const fs::path kCurves = fs::path(PODIUM_GETUP_CURVES_DATA_DIR) / "curves";

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }
bool one_line(const std::string& text) { return !text.empty() && text.find('\n') == text.size() - 1; }
double max_abs(const ControlPoints& a) { return a.cwiseAbs().maxCoeff(); }

TEST(CurveEdit, AShiftOfZeroAndAScaleOfOneGiveTheSameCurve) {
  const StyleCurve faceup = load_style_curve(kCurves / "faceup.json");
  const StyleCurve shifted = shift_rise(faceup, 0.0);
  EXPECT_LT(max_abs(shifted.points - faceup.points), 1e-9);
  EXPECT_EQ(shifted.duration_s, faceup.duration_s);
  const StyleCurve scaled = scale_duration(faceup, 1.0);
  EXPECT_EQ(scaled.points, faceup.points);
  EXPECT_EQ(scaled.duration_s, faceup.duration_s);
}

TEST(CurveEdit, AShiftedRiseLandsWhereAskedWithTheStartEndAndTKept) {
  const StyleCurve faceup = load_style_curve(kCurves / "faceup.json");
  const double rise = rise_time_s(faceup);
  // The rise is where h first reaches half its end value.
  EXPECT_NEAR(faceup.target(rise)(0), 0.5 * faceup.at(1.0)(0), 1e-9);
  EXPECT_LT(faceup.target(rise - 0.01)(0), 0.5 * faceup.at(1.0)(0));
  for (const double shift : {-0.5, 0.5, -1.0}) {
    const StyleCurve c = shift_rise(faceup, shift);
    std::printf("shift %+.1f s: rise %.3f -> %.3f s (asked %.3f)\n", shift, rise, rise_time_s(c), rise + shift);
    EXPECT_NEAR(rise_time_s(c), rise + shift, 0.05) << shift;
    EXPECT_EQ(c.points.col(0), faceup.points.col(0));
    EXPECT_EQ(c.points.col(kControlPoints - 1), faceup.points.col(kControlPoints - 1));
    EXPECT_EQ(c.duration_s, faceup.duration_s);
  }
  EXPECT_LT(rise_time_s(shift_rise(faceup, -0.5)) + 0.25, rise);
  EXPECT_GT(rise_time_s(shift_rise(faceup, 0.5)) - 0.25, rise);
}

TEST(CurveEdit, AMovedControlPointMovesOnlyThatPoint) {
  const StyleCurve faceup = load_style_curve(kCurves / "faceup.json");
  const StyleCurve h = move_control_point(faceup, "h", 4, 0.05);
  ControlPoints expected = faceup.points;
  expected(0, 4) += 0.05;
  EXPECT_LT(max_abs(h.points - expected), 1e-12);
  const StyleCurve z = move_control_point(faceup, "theta_z", 2, -10.0);  // degrees
  expected = faceup.points;
  expected(2, 2) -= 10.0 * kDeg;
  EXPECT_LT(max_abs(z.points - expected), 1e-12);
  EXPECT_EQ(z.duration_s, faceup.duration_s);
}

// The message of the UserError `edit` throws, or "".
template <class Edit>
std::string edit_error(Edit edit) {
  try {
    edit();
  } catch (const base::UserError& e) {
    return e.what();
  }
  return "";
}

TEST(CurveEdit, AnEditThatLeavesTheFilesRangesIsRefusedByValue) {
  const StyleCurve faceup = load_style_curve(kCurves / "faceup.json");
  std::string e = edit_error([&] { shift_rise(faceup, 3.0); });
  EXPECT_TRUE(contains(e, "curve \"faceup\": --shift-rise 3 s moves its rise from ")) << e;
  EXPECT_TRUE(contains(e, ", outside (0, 3.7665) s")) << e;
  e = edit_error([&] { scale_duration(faceup, 0.0); });
  EXPECT_TRUE(contains(e, "--scale-T 0 makes T 0 s; T must lie in (0, 60] s")) << e;
  e = edit_error([&] { move_control_point(faceup, "theta_z", 0, -10.0); });
  EXPECT_TRUE(contains(e, "--move theta_z:0:-10: theta_z control point 0 would be -4.75°, outside [0, 180]")) << e;
  e = edit_error([&] { move_control_point(faceup, "height", 0, 0.1); });
  EXPECT_TRUE(contains(e, "no feature \"height\"")) << e;
  e = edit_error([&] { move_control_point(faceup, "h", 9, 0.1); });
  EXPECT_TRUE(contains(e, "control point 9 is not in [0, 8]")) << e;
  StyleCurve standing = faceup;
  standing.points.row(0).setConstant(1.5);
  e = edit_error([&] { rise_time_s(standing); });
  EXPECT_TRUE(contains(e, "already half its end height")) << e;
}

TEST(CurveTool, EditThroughPodiumRoundTripsAndMovesOnePoint) {
  TempDir dir;
  const std::string faceup = (kCurves / "faceup.json").string();
  const auto same = run_podium({"tool", "getup_curves", "edit", faceup, "--out", "same.json"}, dir.path());
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_TRUE(contains(same.out, "same: rise ")) << same.out;
  const StyleCurve original = load_style_curve(faceup), copy = load_style_curve(dir / "same.json");
  EXPECT_LT(max_abs(copy.points - original.points), 1e-9);
  EXPECT_EQ(copy.duration_s, original.duration_s);
  EXPECT_EQ(copy.name, "same");
  const auto moved = run_podium(
      {"tool", "getup_curves", "edit", faceup, "--out", "moved.json", "--move", "h:4:0.05", "--name", "m"}, dir.path());
  ASSERT_EQ(moved.exit_code, 0) << moved.err;
  const StyleCurve m = load_style_curve(dir / "moved.json");
  ControlPoints expected = original.points;
  expected(0, 4) += 0.05;
  EXPECT_LT(max_abs(m.points - expected), 1e-9);
  EXPECT_EQ(m.name, "m");
  const auto slow = run_podium({"tool", "getup_curves", "edit", faceup, "--out", "slow.json", "--scale-T", "2"}, dir.path());
  ASSERT_EQ(slow.exit_code, 0) << slow.err;
  EXPECT_NEAR(load_style_curve(dir / "slow.json").duration_s, 2.0 * original.duration_s, 1e-4);
}

TEST(CurveTool, TheShippedShiftedFaceupCurvesAreTheEditsTheyClaim) {
  // data/curves/README.md: faceup_early and faceup_late are `edit faceup.json --shift-rise ∓0.5`.
  TempDir dir;
  for (const auto& [name, shift] : {std::pair{"faceup_early", "-0.5"}, std::pair{"faceup_late", "0.5"}}) {
    const auto r = run_podium({"tool", "getup_curves", "edit", (kCurves / "faceup.json").string(), "--out",
                               std::string(name) + ".json", "--shift-rise", shift},
                              dir.path());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(base::read_json_file(dir / (std::string(name) + ".json")).dump(),
              base::read_json_file(kCurves / (std::string(name) + ".json")).dump())
        << name;
  }
}

TEST(CurveTool, BadInputIsOneLineWithExitTwo) {
  TempDir dir;
  const std::string faceup = (kCurves / "faceup.json").string();
  const auto expect_line = [&](const std::vector<std::string>& args, const std::string& part) {
    const auto r = run_podium(args, dir.path());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(contains(r.err, part)) << r.err;
    EXPECT_TRUE(one_line(r.err)) << r.err;
  };
  expect_line({"tool", "getup_curves", "edit", "nope.json", "--out", "x.json"}, "nope.json");
  expect_line({"tool", "getup_curves", "edit", faceup}, "podium tool getup_curves edit: the option '--out' is required");
  expect_line({"tool", "getup_curves", "edit", faceup, "--out", "x.json", "--move", "h4"},
              "--move \"h4\": not FEATURE:INDEX:DELTA");
  expect_line({"tool", "getup_curves", "edit", faceup, "--out", "x.json", "--move", "h:4:x"}, "--move \"h:4:x\"");
  expect_line({"tool", "getup_curves", "edit", faceup, "--out", "x.json", "--shift-rise", "9"}, "outside (0, 3.7665) s");
  expect_line({"tool", "getup_curves", "extract", "nope.txt", "--out", "x.json"}, "nope.txt: no such clip");
  expect_line({"tool", "getup_curves", "extract", faceup, "--out", "x.json", "--method", "spline"},
              "--method \"spline\": not fit or samples");
  write_file(dir / "bad_curve.json", R"({"name": "b", "duration_s": -1, "control_points": {}, "start": {"drop": "supine"}})");
  expect_line({"tool", "getup_curves", "edit", "bad_curve.json", "--out", "x.json"}, "bad_curve.json: duration_s: -1");
  write_file(dir / "labels.json", R"({"clips": [{"clip": "a.txt", "model": "humanoid34", "strategy": "situp"}]})");
  expect_line({"tool", "getup_curves", "stats", "labels.json", "--data", dir.path().string()},
              "labels.json: clips[0].strategy: \"situp\" is not one of");
  expect_line({"tool", "getup_curves", "stats", "labels.json", "--data", dir.path().string(), "--method", "x"}, "--method \"x\"");
  EXPECT_FALSE(dir.path().empty());
}

// ../shared/data, or the reason it cannot be used.
struct SharedData {
  fs::path root;
  std::string missing;
};
SharedData shared_data(const std::vector<std::string>& files) {
  const fs::path root = podium::testing::shared_data();
  if (root.empty()) return {{}, "PODIUM_SHARED_DIR/data is absent"};
  for (const auto& f : files)
    if (!fs::exists(root / f)) return {root, (root / f).string() + " is absent"};
  return {root, ""};
}

const char* const kFaceup = "deepmimic/data/motions/humanoid3d_getup_faceup.txt";
const char* const kFacedown = "deepmimic/data/motions/humanoid3d_getup_facedown.txt";
const char* const kHumanoid3d = "deepmimic/data/characters/humanoid3d.txt";

TEST(CurveTool, ExtractMatchesTheExtractionFunctionsAndRemakesTheShippedCurves) {
  const SharedData data = shared_data({kFaceup, kFacedown, kHumanoid3d});
  if (!data.missing.empty()) GTEST_SKIP() << data.missing;
  TempDir dir;
  const auto fit = run_podium({"tool", "getup_curves", "extract", kFaceup, "--data", data.root.string(), "--model", kHumanoid3d,
                               "--to", "none", "--out", "fit.json", "--track", "track.csv"},
                              dir.path());
  ASSERT_EQ(fit.exit_code, 0) << fit.err;
  std::printf("%s", fit.out.c_str());
  const sim::ModelPtr model = sim::load_deepmimic(data.root / kHumanoid3d);
  const Extraction expected =
      extract_curve(character::read_deepmimic_clip(model, data.root / kFaceup), {ExtractMethod::least_squares, "x", "x", 1.0});
  const StyleCurve got = load_style_curve(dir / "fit.json");
  EXPECT_EQ(got.name, "humanoid3d_getup_faceup");
  EXPECT_NEAR(got.duration_s, expected.curve.duration_s, 1e-4);
  EXPECT_LT(max_abs(got.points - expected.curve.points), 1e-4);  // the file's rounding: 0.1 mm, 0.01°
  // Its clip start names the clip from the curve file's folder.
  ASSERT_EQ(got.start.kind, CurveStart::Kind::clip);
  EXPECT_TRUE(fs::equivalent(dir / got.start.clip, data.root / kFaceup)) << got.start.clip;
  EXPECT_TRUE(fs::exists(dir / "track.csv"));
  // The shipped faceup and facedown curves are §4.1's 9 samples on humanoid3d carried to
  // humanoid34, started as drops: the tool remakes them (all but their source text).
  for (const auto& [clip, name, start] : {std::tuple{kFaceup, "faceup", "supine"}, std::tuple{kFacedown, "facedown", "prone"}}) {
    const auto samples =
        run_podium({"tool", "getup_curves", "extract", clip, "--data", data.root.string(), "--model", kHumanoid3d, "--method",
                    "samples", "--start", start, "--name", name, "--out", "remade.json"},
                   dir.path());
    ASSERT_EQ(samples.exit_code, 0) << samples.err;
    Json shipped = base::read_json_file(kCurves / (std::string(name) + ".json")),
         remade = base::read_json_file(dir / "remade.json");
    shipped.erase("source");
    remade.erase("source");
    EXPECT_EQ(remade, shipped) << name;
  }
}

TEST(CurveTool, StatsTabulatesASmallLabelFileAndAveragesEachStrategy) {
  const SharedData data = shared_data({kFaceup, kFacedown, kHumanoid3d});
  if (!data.missing.empty()) GTEST_SKIP() << data.missing;
  TempDir dir;
  const Json labels = {{"clips",
                        {{{"clip", kFaceup}, {"model", kHumanoid3d}, {"strategy", "sit_up_roll_over"}},
                         {{"clip", kFacedown}, {"model", kHumanoid3d}, {"strategy", "quadruped_push_up_prone"}},
                         {{"clip", kFaceup}, {"model", kHumanoid3d}, {"strategy", "quadruped_push_up_prone"}}}}};
  write_file(dir / "labels.json", labels.dump());
  const auto r = run_podium({"tool", "getup_curves", "stats", "labels.json", "--data", data.root.string(), "--out", "stats.json"},
                            dir.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::printf("%s", r.out.c_str());
  EXPECT_TRUE(contains(r.out, "humanoid3d_getup_faceup.txt")) << r.out;
  EXPECT_TRUE(contains(r.out, "sit_up_roll_over")) << r.out;
  const Json stats = base::read_json_file(dir / "stats.json");
  ASSERT_EQ(stats["clips"].size(), 3u);
  ASSERT_EQ(stats["strategies"].size(), 2u);  // in the strategies' order, only those with clips
  const Json& one = stats["strategies"][0];
  const Json& two = stats["strategies"][1];
  EXPECT_EQ(one["strategy"], "sit_up_roll_over");
  EXPECT_EQ(two["strategy"], "quadruped_push_up_prone");
  EXPECT_TRUE(one["duration_s"]["sd"].is_null());  // one clip: no sd
  // The means are the clips' own extractions (heights carried to humanoid34), averaged.
  const sim::ModelPtr model = sim::load_deepmimic(data.root / kHumanoid3d);
  const double scale = standing_neck_height(*sim::load_shipped_model("humanoid34")) / standing_neck_height(*model);
  const auto curve_of = [&](const char* clip) {
    return extract_curve(character::read_deepmimic_clip(model, data.root / clip), {ExtractMethod::least_squares, "", "", scale})
        .curve;
  };
  const StyleCurve up = curve_of(kFaceup), down = curve_of(kFacedown);
  base::Json mean_json = one["mean_curve"];
  EXPECT_LT(max_abs(base::ConfigReader::parse(mean_json, "mean", read_style_curve).points - up.points), 1e-9);
  mean_json = two["mean_curve"];
  const StyleCurve mean = base::ConfigReader::parse(mean_json, "mean", read_style_curve);
  EXPECT_LT(max_abs(mean.points - 0.5 * (up.points + down.points)), 1e-9);
  EXPECT_NEAR(two["duration_s"]["mean"].get<double>(), 0.5 * (up.duration_s + down.duration_s), 1e-12);
  // Sample sd of two values: |a − b| / √2.
  EXPECT_NEAR(two["duration_s"]["sd"].get<double>(), std::abs(up.duration_s - down.duration_s) / std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(two["control_points_sd"]["h_m"][4].get<double>(), std::abs(up.points(0, 4) - down.points(0, 4)) / std::sqrt(2.0),
              1e-12);
  EXPECT_EQ(two["samples"]["s"].size(), 21u);
}

TEST(CurveTool, TheShippedLabelFileReadsAndNamesEveryGetUpClip) {
  const auto labels = load_clip_labels(fs::path(PODIUM_GETUP_CURVES_DATA_DIR) / "getup_labels.json");
  EXPECT_EQ(labels.size(), 7u);
  for (const auto& l : labels) EXPECT_FALSE(l.why.empty()) << l.clip;
}

}  // namespace
}  // namespace podium::tasks::getup_curves

namespace podium::tasks::getup_curves {
namespace {

// data/curves/make_styles.sh remakes the 15 shipped style curves with the tool, byte for byte (run
// on a copy of the folder), each at its name's T; the paper preset trains on them.
TEST(CurveTool, MakeStylesRemakesTheShippedStyleCurves) {
  const SharedData data = shared_data({"jump/data/vae/txt/cmu136-140/140/140_03.txt", kFaceup});
  if (!data.missing.empty()) GTEST_SKIP() << data.missing;
  TempDir dir;
  const fs::path copy = dir / "tasks/getup_curves/data";
  fs::create_directories(copy / "curves");
  fs::copy_file(kCurves.parent_path() / "getup_labels.json", copy / "getup_labels.json");
  for (const char* f : {"make_styles.sh", "faceup.json"}) fs::copy_file(kCurves / f, copy / "curves" / f);
  const podium::testing::ShellResult r = podium::testing::shell("PODIUM_SHARED_DIR=" + data.root.parent_path().string() +
                                                                " bash " + (copy / "curves/make_styles.sh").string() + " " +
                                                                podium::testing::podium_binary().string() + " 2>&1");
  ASSERT_TRUE(WIFEXITED(r.status) && WEXITSTATUS(r.status) == 0) << r.out;
  int styles = 0;
  for (const char* style : {"situp_rollover", "pushup_prone", "pushup_supine", "sidesit_pivot", "pushup_kneel"})
    for (const auto& [tag, duration] : {std::pair{"t25", 2.5}, std::pair{"t51", 5.1}, std::pair{"t76", 7.6}}) {
      const std::string file = std::string(style) + "_" + tag + ".json";
      EXPECT_EQ(podium::testing::file_bytes(copy / "curves" / file), podium::testing::file_bytes(kCurves / file)) << file;
      EXPECT_NEAR(load_style_curve(kCurves / file).duration_s, duration, 1e-3) << file;
      ++styles;
    }
  EXPECT_EQ(styles, 15);
}

}  // namespace
}  // namespace podium::tasks::getup_curves
