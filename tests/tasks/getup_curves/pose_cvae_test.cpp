// The pose C-VAE (curve get-up seed §3.5) and its action space (§3.4): CurveGetupEnv with actions
// "cvae" decodes every action to a pose within the joint limits, starts from the encoding of its
// start pose, and reads Δq for r_natural (eq. 3); with the get-up clips of ../shared/data
// (skipped with the reason printed when absent), the C-VAE trained on their poses labelled by
// their style features reconstructs held-out frames better than their training mean pose.
#include "pose_cvae.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>

#include "curve_env.h"
#include "curve_extraction.h"
#include "podium/base/error.h"
#include "podium/character/pose_bridge.h"
#include "process.h"
#include "shared_data.h"

namespace podium::tasks::getup_curves {
namespace {

namespace fs = std::filesystem;
constexpr double kDeg = std::numbers::pi / 180.0;

// From lying on the back to standing at humanoid34's neck height over 2 s.
StyleCurve rising_curve(const sim::ModelPtr& model) {
  StyleCurve c;
  c.name = "rise";
  c.duration_s = 2.0;
  const double stand_h = standing_neck_height(*model);
  for (int k = 0; k < kControlPoints; ++k) {
    const double u = static_cast<double>(k) / (kControlPoints - 1);
    c.points.col(k) << 0.2 + (stand_h - 0.2) * u, 90.0 * kDeg, 90.0 * kDeg * u;
  }
  c.start.kind = CurveStart::Kind::drop;
  c.source = "test";
  return c;
}

// An untrained C-VAE of humanoid34's poses and the 3 style features: the action map's mechanics
// do not depend on training.
std::shared_ptr<const learn::PoseVae> untrained_cvae(const sim::ModelPtr& model) {
  const character::PoseBridge bridge(model);
  learn::VaeConfig config = learn::VaeConfig::conditional();
  config.hidden = {32, 32};
  return std::make_shared<learn::PoseVae>(config, bridge.lower(), bridge.upper(), 3, 11);
}

TEST(PoseCvaeActions, EveryActionDecodesToAPoseWithinTheJointLimits) {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  CurveEnvSettings settings;
  settings.actions = "cvae";
  settings.cvae = untrained_cvae(model);
  CurveGetupEnv env(settings, make_curve_set({rising_curve(model)}, model));
  const character::PoseBridge bridge(model);
  // §3.4: a = [z ∈ R¹⁶, Δq per pose entry]; the state carries y_{t−1}: 279 values as the issue computes.
  const learn::BoxSpace box = env.action_space();
  ASSERT_EQ(box.size(), 16 + bridge.size());
  std::vector<double> obs;
  env.seed(3);
  env.reset(obs);
  EXPECT_EQ(obs.size(), 279u);
  // y_0: the start pose's encoding under c = p(0), no offsets.
  const Eigen::VectorXd& y0 = env.filtered_action();
  const std::vector<double> z0 = settings.cvae->encode(bridge.pose(env.world().data().q), env.condition());
  for (std::size_t k = 0; k < 16; ++k)
    EXPECT_DOUBLE_EQ(y0(static_cast<Eigen::Index>(k)), std::clamp(z0[k], -settings.latent_bound, settings.latent_bound));
  for (Eigen::Index k = 16; k < y0.size(); ++k) EXPECT_EQ(y0(k), 0.0);
  EXPECT_EQ(env.condition(), (std::vector<double>{0.2, 90.0 * kDeg, 0.0}));
  // Random actions at the box's corners and inside: every decoded target within the limits, and
  // r_natural from the filtered Δq (eq. 3, c = 10).
  base::Rng rng(9);
  learn::StepResult out;
  for (int step = 0; step < 20 && !out.terminated; ++step) {
    std::vector<double> a(box.size());
    for (std::size_t k = 0; k < a.size(); ++k)
      a[k] = step % 2 ? rng.uniform(box.low[k], box.high[k]) : (rng.uniform() < 0.5 ? box.low[k] : box.high[k]);
    env.step(a, out);
    const Eigen::VectorXd& y = env.filtered_action();
    const std::span<const double> ys(y.data(), static_cast<std::size_t>(y.size()));
    const std::vector<double> pose = env.target_pose(ys);
    ASSERT_EQ(pose.size(), bridge.size());
    for (std::size_t k = 0; k < pose.size(); ++k) {
      EXPECT_GE(pose[k], bridge.lower()[k]) << bridge.dof_names()[k];
      EXPECT_LE(pose[k], bridge.upper()[k]) << bridge.dof_names()[k];
    }
    double l1 = 0.0;
    for (std::size_t k = 16; k < ys.size(); ++k) l1 += std::abs(ys[k]);
    EXPECT_DOUBLE_EQ(env.offset_l1(ys), l1);
    EXPECT_NEAR(env.reward_terms().natural, 1.0 - std::min(1.0, (l1 / 10.0) * (l1 / 10.0)), 1e-12);
  }
}

TEST(PoseCvaeActions, AMissingOrMisshapenCvaeIsRefused) {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  CurveEnvSettings settings;
  settings.actions = "cvae";
  EXPECT_THROW(CurveGetupEnv(settings, make_curve_set({rising_curve(model)}, model)), base::UserError);
  const character::PoseBridge bridge(model);
  settings.cvae = std::make_shared<learn::PoseVae>(learn::VaeConfig::conditional(), bridge.lower(), bridge.upper(), 2, 1);
  try {
    CurveGetupEnv env(settings, make_curve_set({rising_curve(model)}, model));
    FAIL() << "a C-VAE of 2 conditions was accepted";
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("from 2 conditions"), std::string::npos) << e.what();
  }
}

TEST(PoseCvae, PrincipalComponentsAndTheMeanPoseBaselineOnHandMadePoses) {
  learn::PoseDataset d;
  d.dof_names = {"a", "b", "c"};
  // Poses on a line along (1, 1, 1): one component holds all the variance. Their mean pose is
  // (1, 1, 1), 1 rad from (0, 0, 0) and from (2, 2, 2) in every entry.
  for (double t : {-1.0, 0.0, 1.0}) d.poses.push_back({1.0 + t, 1.0 + t, 1.0 + t});
  EXPECT_EQ(principal_components_for(d, 0.85), 1);
  learn::PoseDataset ends = d;
  ends.poses = {{0.0, 0.0, 0.0}, {2.0, 2.0, 2.0}};
  EXPECT_DOUBLE_EQ(mean_pose_rmse(d, ends), 1.0);
}

// The seven get-up clips of ../shared/data and the skeletons they were captured on.
std::vector<PoseClip> getup_clips(std::string& missing) {
  const fs::path data = podium::testing::shared_data();
  if (data.empty()) {
    missing = "PODIUM_SHARED_DIR/data is absent";
    return {};
  }
  const std::string deepmimic = (data / "deepmimic/data/characters/humanoid3d.txt").string();
  const std::string jumper = (data / "jump/data/characters/humanoid3d_jumper60kg.txt").string();
  std::vector<PoseClip> clips = {{(data / "deepmimic/data/motions/humanoid3d_getup_faceup.txt").string(), deepmimic},
                                 {(data / "deepmimic/data/motions/humanoid3d_getup_facedown.txt").string(), deepmimic}};
  for (const char* cmu : {"139/139_16", "139/139_17", "140/140_01", "140/140_02", "140/140_03"})
    clips.push_back({(data / "jump/data/vae/txt/cmu136-140" / (std::string(cmu) + ".txt")).string(), jumper});
  for (const PoseClip& c : clips)
    for (const std::string& f : {c.clip, c.character})
      if (!fs::exists(f)) missing = f + " is absent";
  return missing.empty() ? clips : std::vector<PoseClip>{};
}

TEST(PoseCvae, TrainedOnTheGetUpClipsItReconstructsHeldOutFramesBetterThanTheMeanPose) {
  std::string missing;
  PoseCvaeSettings settings;
  settings.clips = getup_clips(missing);
  if (!missing.empty()) GTEST_SKIP() << missing;
  ASSERT_EQ(settings.vae.epochs, 100);  // §3.5
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  // Labels: the first faceup frame lies on its back, the first facedown frame on its front.
  const CvaePoses poses = read_cvae_poses(settings.clips, model, settings.holdout_every);
  EXPECT_LT(poses.train.conditions.front()[2], 15.0 * kDeg);
  podium::testing::TempDir dir;
  const PoseCvaeOutcome out = train_pose_cvae(settings, dir.path(), 5, nullptr, {}, {});
  std::printf(
      "C-VAE on %zu training / %zu held-out frames, %d epochs: RMSE train %.3f rad, held-out %.3f rad; "
      "mean pose on held-out %.3f rad; PCA components for 85%%: %d\n",
      out.train_poses, out.heldout_poses, settings.vae.epochs, out.train_rmse_rad, out.heldout_rmse_rad, out.mean_pose_rmse_rad,
      out.pca_components_85);
  EXPECT_EQ(out.train_poses + out.heldout_poses, poses.train.size() + poses.heldout.size());
  EXPECT_GT(out.heldout_poses, 100u);
  EXPECT_LT(out.heldout_rmse_rad, 0.5 * out.mean_pose_rmse_rad);
  // The saved file loads as a C-VAE of the 3 features that the env's action map accepts.
  CurveEnvSettings env_settings;
  env_settings.actions = "cvae";
  env_settings.cvae = std::shared_ptr<const learn::PoseVae>(learn::PoseVae::from_file(out.file));
  EXPECT_EQ(env_settings.cvae->condition_size(), 3u);
  CurveGetupEnv env(env_settings, make_curve_set({rising_curve(model)}, model));
  EXPECT_EQ(env.action_space().size(), 16 + character::PoseBridge(model).size());
}

}  // namespace
}  // namespace podium::tasks::getup_curves
