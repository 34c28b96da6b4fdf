// Curves from clips (curve get-up seed §4.1): a synthetic sit-up is fitted exactly where a cubic
// B-spline can be exact; the get-up clips of ../shared/data start lying the right way up and are
// fitted within the bars (h ≤ 0.06 m, each angle ≤ 12° RMS), the 9-sample curves reported beside.
#include "curve_extraction.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numbers>

#include "podium/base/error.h"
#include "podium/character/frames.h"
#include "podium/sim/model.h"
#include "shared_data.h"

namespace podium::tasks::getup_curves {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// humanoid34 sitting up from its back: the standing pose pitched from −90° (supine) to 0° at a
// constant rate over 2 s, 61 frames.
character::Clip sit_up_clip() {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  character::Clip clip{model, {}, {}, false};
  for (int f = 0; f <= 60; ++f) {
    const double t = f / 30.0;
    Eigen::VectorXd q = model->standing_pose();
    const Eigen::Quaterniond pitch(Eigen::AngleAxisd((-90.0 + 45.0 * t) * kDeg, Eigen::Vector3d::UnitY()));
    character::set_quat(q, 3, pitch);
    q(2) = 0.15;
    clip.times_s.push_back(t);
    clip.poses.push_back(q);
  }
  return clip;
}

TEST(CurveExtraction, LeastSquaresReproducesALinearTurnAndSamplesFollowIt) {
  const character::Clip clip = sit_up_clip();
  const Extraction fit = extract_curve(clip, {ExtractMethod::least_squares, "sit-up", "synthetic", 1.0});
  const Extraction samples = extract_curve(clip, {ExtractMethod::samples, "sit-up", "synthetic", 1.0});
  EXPECT_EQ(fit.curve.duration_s, 2.0);
  EXPECT_EQ(fit.track.features.size(), 61u);
  // θ_z rises linearly from 0 to 90°: a cubic B-spline holds a line exactly; θ_x stays at 90°.
  EXPECT_LT(fit.rms(2), 1e-9);
  EXPECT_LT(fit.rms(1), 1e-9);
  EXPECT_LT(fit.rms(0), 2e-3);  // h = 0.15 + 0.54 sin(pitch): smooth, nearly a cubic
  // The 9 samples lie on the line; the curve through them as control points does not (it bends
  // toward the Greville abscissae), but stays within a few degrees.
  EXPECT_NEAR(samples.curve.points(2, 4), 45.0 * kDeg, 1e-9);
  EXPECT_GT(samples.rms(2), fit.rms(2));
  EXPECT_LT(samples.rms(2), 5.0 * kDeg);
  EXPECT_EQ(fit.curve.start.kind, CurveStart::Kind::clip);
  EXPECT_EQ(fit.curve.start.clip, "synthetic");
  // height_scale carries h to another body's proportions.
  const Extraction scaled = extract_curve(clip, {ExtractMethod::samples, "sit-up", "synthetic", 2.0});
  EXPECT_LT((scaled.curve.points.row(0) - 2.0 * samples.curve.points.row(0)).cwiseAbs().maxCoeff(), 1e-12);
}

TEST(CurveExtraction, StandingNeckHeightIsTheStandingCharactersH) {
  // humanoid34's standing root height puts its soles on the ground, so its standing h is the
  // neck's height above them (to the sole boxes' round-off in the model file).
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  sim::CharacterData scratch(*model);
  EXPECT_NEAR(standing_neck_height(*model), StyleFeatureReader(*model).at(model->standing_pose(), scratch)(0), 0.01);
}

TEST(CurveExtraction, AClipShorterThanNineFramesIsRefusedByName) {
  character::Clip clip = sit_up_clip();
  clip.times_s.resize(8);
  clip.poses.resize(8);
  try {
    extract_curve(clip, {ExtractMethod::least_squares, "short", "short.txt", 1.0});
    FAIL() << "expected UserError";
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("short.txt: 8 frames"), std::string::npos) << e.what();
  }
}

struct GetUpClip {
  const char* file;       // under data/
  const char* character;  // the skeleton it was captured for, under data/
};

// The seven get-up clips of ../shared/data in the humanoid3d layout, each on its own skeleton.
const GetUpClip kClips[] = {
    {"deepmimic/data/motions/humanoid3d_getup_faceup.txt", "deepmimic/data/characters/humanoid3d.txt"},
    {"deepmimic/data/motions/humanoid3d_getup_facedown.txt", "deepmimic/data/characters/humanoid3d.txt"},
    {"jump/data/vae/txt/cmu136-140/139/139_16.txt", "jump/data/characters/humanoid3d_jumper60kg.txt"},
    {"jump/data/vae/txt/cmu136-140/139/139_17.txt", "jump/data/characters/humanoid3d_jumper60kg.txt"},
    {"jump/data/vae/txt/cmu136-140/140/140_01.txt", "jump/data/characters/humanoid3d_jumper60kg.txt"},
    {"jump/data/vae/txt/cmu136-140/140/140_02.txt", "jump/data/characters/humanoid3d_jumper60kg.txt"},
    {"jump/data/vae/txt/cmu136-140/140/140_03.txt", "jump/data/characters/humanoid3d_jumper60kg.txt"},
};

// The missing file, or "" when every clip and skeleton is there.
std::string missing_data() {
  const std::filesystem::path data = podium::testing::shared_data();
  if (data.empty()) return "PODIUM_SHARED_DIR/data is absent";
  for (const GetUpClip& c : kClips)
    for (const char* f : {c.file, c.character})
      if (!std::filesystem::exists(data / f)) return (data / f).string() + " is absent";
  return "";
}

character::Clip load_clip(const GetUpClip& c) {
  const std::filesystem::path data = podium::testing::shared_data();
  return character::read_deepmimic_clip(sim::load_deepmimic(data / c.character), data / c.file);
}

TEST(CurveExtraction, DeepMimicGetUpsStartOnTheBackAndOnTheFront) {
  if (const std::string missing = missing_data(); !missing.empty()) GTEST_SKIP() << missing;
  const FeatureTrack faceup = feature_track(load_clip(kClips[0]));
  const FeatureTrack facedown = feature_track(load_clip(kClips[1]));
  std::printf("faceup starts at θ_z = %.1f°, facedown at θ_z = %.1f°\n", faceup.features.front()(2) / kDeg,
              facedown.features.front()(2) / kDeg);
  EXPECT_LT(faceup.features.front()(2), 15.0 * kDeg);
  EXPECT_GT(facedown.features.front()(2), 150.0 * kDeg);
  // Both end standing: torso vectors level.
  for (const FeatureTrack* t : {&faceup, &facedown}) {
    EXPECT_NEAR(t->features.back()(1), 90.0 * kDeg, 20.0 * kDeg);
    EXPECT_NEAR(t->features.back()(2), 90.0 * kDeg, 20.0 * kDeg);
  }
}

TEST(CurveExtraction, TheSevenGetUpClipsAreFittedWithinTheBars) {
  if (const std::string missing = missing_data(); !missing.empty()) GTEST_SKIP() << missing;
  // Heights on humanoid34's proportions (the task's character) scale by its standing neck height over the clip skeleton's.
  const double humanoid34_neck = standing_neck_height(*sim::load_shipped_model("humanoid34"));
  std::printf("%-26s %6s %5s | %-24s | %-24s | %s\n", "clip", "frames", "T s", "fit RMS: h m, θx °, θz °",
              "9 samples: h m, θx °, θz °", "h m on humanoid34: fit, samples");
  for (const GetUpClip& c : kClips) {
    const character::Clip clip = load_clip(c);
    const double scale = humanoid34_neck / standing_neck_height(*clip.model);
    const std::string name = std::filesystem::path(c.file).stem().string();
    const Extraction fit = extract_curve(clip, {ExtractMethod::least_squares, name, c.file, 1.0});
    const Extraction samples = extract_curve(clip, {ExtractMethod::samples, name, c.file, 1.0});
    std::printf("%-26s %6zu %5.2f | %6.3f %6.1f %6.1f     | %6.3f %6.1f %6.1f     | %.3f %.3f (× %.3f)\n", name.c_str(),
                clip.size(), clip.duration_s(), fit.rms(0), fit.rms(1) / kDeg, fit.rms(2) / kDeg, samples.rms(0),
                samples.rms(1) / kDeg, samples.rms(2) / kDeg, fit.rms(0) * scale, samples.rms(0) * scale, scale);
    EXPECT_LE(fit.rms(0), 0.06) << name;
    EXPECT_LE(fit.rms(1), 12.0 * kDeg) << name;
    EXPECT_LE(fit.rms(2), 12.0 * kDeg) << name;
    // The fitted curve is a valid curve file's content.
    EXPECT_GE(fit.curve.points.minCoeff(), 0.0) << name;
    EXPECT_LE(fit.curve.points.bottomRows<2>().maxCoeff(), std::numbers::pi) << name;
  }
}

}  // namespace
}  // namespace podium::tasks::getup_curves
