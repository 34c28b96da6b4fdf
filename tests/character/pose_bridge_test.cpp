// The pose bridge (VAE poses ↔ sim targets) and pose labels by forward kinematics.
#include "podium/character/pose_bridge.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "podium/base/error.h"
#include "test_util.h"

namespace podium::character {
namespace {

using testing::config_distance;

double pose_distance(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0;
  for (std::size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(a[k] - b[k]));
  return worst;
}

// Every frame of the DeepMimic face-up get-up round-trips to 1e-9, and
// the y-up exponential maps are those of the file's own joint quaternions (what VAEs trained on
// DeepMimic clips see).
TEST(PoseBridge, RoundTripsEveryFrameOfTheDeepMimicGetUp) {
  const auto dir = testing::deepmimic_dir();
  if (dir.empty() || !std::filesystem::exists(dir / "motions/humanoid3d_getup_faceup.txt"))
    GTEST_SKIP() << "../shared/data/deepmimic/data/motions/humanoid3d_getup_faceup.txt absent (PODIUM_SHARED_DIR)";
  const sim::ModelPtr model = sim::load_deepmimic(dir / "characters/humanoid3d.txt", dir / "controllers/humanoid3d_ctrl.txt");
  const Clip clip = read_deepmimic_clip(model, dir / "motions/humanoid3d_getup_faceup.txt");
  const base::Json raw = base::read_json_file(dir / "motions/humanoid3d_getup_faceup.txt");
  const PoseBridge bridge(model, PoseBridge::Frame::y_up);
  ASSERT_EQ(bridge.size(), 28u);  // thesis §3.6.2: 28 internal DoFs (8 balls × 3 + 4 hinges)
  const sim::Link& chest = model->link("chest");
  double worst_q = 0, worst_pose = 0, worst_file = 0;
  for (std::size_t f = 0; f < clip.size(); ++f) {
    const std::vector<double> pose = bridge.pose(clip.poses[f]);
    Eigen::VectorXd q = clip.poses[f];
    q.tail(q.size() - 7).setZero();
    bridge.set_pose(pose, q);
    worst_q = std::max(worst_q, config_distance(*model, q, clip.poses[f]));
    worst_pose = std::max(worst_pose, pose_distance(bridge.pose(bridge.target(pose)), pose));
    // The file's chest quaternion (entries 1 + 7 .. 1 + 10 of the frame) in its own y-up frame.
    const auto& fr = raw["Frames"][f];
    const int at = 1 + chest.q_index;
    const Eigen::Vector3d e = log_map(Eigen::Quaterniond(fr[at], fr[at + 1], fr[at + 2], fr[at + 3]));
    worst_file = std::max(worst_file, (e - Eigen::Vector3d(pose[0], pose[1], pose[2])).cwiseAbs().maxCoeff());
  }
  std::printf("%zu frames: q → pose → q %.1e, pose → q → pose %.1e, y-up map vs file %.1e\n", clip.size(), worst_q, worst_pose,
              worst_file);
  EXPECT_LE(worst_q, 1e-9);
  EXPECT_LE(worst_pose, 1e-9);
  EXPECT_LE(worst_file, 1e-9);
}

TEST(PoseBridge, RoundTripsRandomConfigurationsInBothFrames) {
  base::Rng rng(5);
  for (const char* name : {"humanoid21", "humanoid34"}) {
    const sim::ModelPtr model = sim::load_shipped_model(name);
    for (auto frame : {PoseBridge::Frame::z_up, PoseBridge::Frame::y_up}) {
      const PoseBridge bridge(model, frame);
      EXPECT_EQ(bridge.size(), static_cast<std::size_t>(model->nv() - 6)) << name;
      for (int n = 0; n < 20; ++n) {
        const Eigen::VectorXd q = testing::random_q(*model, rng);
        Eigen::VectorXd target = bridge.target(bridge.pose(q));
        target.head<7>() = q.head<7>();
        EXPECT_LE(config_distance(*model, target, q), 1e-12) << name;
      }
    }
  }
  const PoseBridge bridge(sim::load_shipped_model("humanoid21"));
  EXPECT_EQ(bridge.dof_names()[0], "abdomen_z");
  EXPECT_THROW(bridge.target(std::vector<double>(3, 0.0)), base::UserError);
}

// A y-up exponential map about DeepMimic's up axis (y) is a turn about our z.
TEST(PoseBridge, YUpMapsTurnAboutTheMatchingZUpAxis) {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  const PoseBridge bridge(model, PoseBridge::Frame::y_up);
  std::vector<double> pose(bridge.size(), 0.0);
  pose[1] = 0.4;  // chest_y
  const Eigen::AngleAxisd r(quat_at(bridge.target(pose), model->link("chest").q_index));
  EXPECT_NEAR(r.angle(), 0.4, 1e-12);
  EXPECT_LE((r.axis() - Eigen::Vector3d::UnitZ()).norm(), 1e-12);
}

// The heading is the yaw of an upright body, and stays the facing direction of a body lying on
// its back or front (where its forward axis points up or down).
TEST(Frames, HeadingIsDefinedStandingAndLying) {
  for (double yaw : {0.0, 0.7, -2.9}) {
    const Eigen::Matrix3d turn = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    EXPECT_NEAR(heading_yaw(turn), yaw, 1e-12);
    for (double pitch : {-std::numbers::pi / 2, std::numbers::pi / 2, 0.4}) {
      const Eigen::Matrix3d lying = turn * Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()).toRotationMatrix();
      EXPECT_NEAR(heading_yaw(lying), yaw, 1e-12) << pitch;
    }
  }
}

TEST(PoseLabels, HeightAndTorsoTiltsFromForwardKinematics) {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  sim::CharacterData scratch(*model);
  Eigen::VectorXd q = model->neutral();  // upright, joints at zero
  q(2) = 0.9;
  const auto standing = pose_labels(*model, scratch, q);
  EXPECT_NEAR(standing[0], 0.9, 1e-12);
  EXPECT_NEAR(standing[1], 0.0, 1e-9);
  EXPECT_NEAR(standing[2], 0.0, 1e-9);
  // Lying on the back (root pitched −90°), then the same turned about the vertical: tilts π/2.
  set_quat(q, 3, Eigen::Quaterniond(Eigen::AngleAxisd(-std::numbers::pi / 2, Eigen::Vector3d::UnitY())));
  q(2) = 0.12;
  const auto lying = pose_labels(*model, scratch, q);
  set_quat(q, 3, Eigen::AngleAxisd(2.0, Eigen::Vector3d::UnitZ()) * quat_at(q, 3));
  const auto turned = pose_labels(*model, scratch, q);
  EXPECT_NEAR(lying[1], std::numbers::pi / 2, 1e-9);
  EXPECT_NEAR(lying[2], std::numbers::pi / 2, 1e-9);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(turned[k], lying[k], 1e-12);
}

TEST(PoseLabels, DeepMimicGetUpBecomesALabelledPoseSet) {
  const auto dir = testing::deepmimic_dir();
  if (dir.empty() || !std::filesystem::exists(dir / "motions/humanoid3d_getup_faceup.txt"))
    GTEST_SKIP() << "../shared/data/deepmimic absent (PODIUM_SHARED_DIR)";
  const sim::ModelPtr model = sim::load_deepmimic(dir / "characters/humanoid3d.txt");
  const Clip clip = read_deepmimic_clip(model, dir / "motions/humanoid3d_getup_faceup.txt");
  const learn::PoseDataset d = poses_from_clip(PoseBridge(model, PoseBridge::Frame::y_up), clip);
  EXPECT_EQ(d.dof_names.size(), 28u);
  EXPECT_EQ(d.size(), clip.size());
  EXPECT_EQ(d.dof_names[0], "chest_x");
  ASSERT_EQ(d.dof_names[9], "right_knee");  // chest 3, neck 3, right hip 3
  EXPECT_EQ(d.condition_names, pose_label_names());
  // The clip gets up from lying on the back: the root rises and the torso turns upright.
  EXPECT_LT(d.conditions.front()[0], 0.3);
  EXPECT_GT(d.conditions.back()[0], 0.7);
  EXPECT_GT(d.conditions.front()[1], 1.0);
  EXPECT_LT(d.conditions.back()[1], 0.5);
  for (const auto& p : d.poses)
    for (std::size_t k = 0; k < p.size(); ++k) ASSERT_TRUE(p[k] >= d.lower[k] && p[k] <= d.upper[k]);
}

// The thesis's P-VAE training clips (CMU-derived, for the 60 kg jumper) make one pose set.
TEST(PoseLabels, JumpVaeClipsBuildOnePoseSet) {
  const std::filesystem::path root = podium::testing::shared_data("jump/data");
  if (root.empty() || !std::filesystem::exists(root / "vae/txt"))
    GTEST_SKIP() << "PODIUM_SHARED_DIR/data/jump/data/vae is absent";
  const sim::ModelPtr model = sim::load_deepmimic(root / "characters/humanoid3d_jumper60kg.txt");
  const PoseBridge bridge(model, PoseBridge::Frame::y_up);
  learn::PoseDataset all;
  std::size_t clips = 0, frames = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(root / "vae/txt")) {
    if (!entry.is_regular_file() || entry.path().extension() != ".txt") continue;
    const Clip clip = read_deepmimic_clip(model, entry.path());
    const learn::PoseDataset poses = poses_from_clip(bridge, clip);
    if (clips++ == 0) {
      all = poses;
    } else {
      all.append(poses);
    }
    frames += clip.size();
  }
  std::printf("%zu clips, %zu poses of %zu DoFs\n", clips, all.size(), all.dof_names.size());
  EXPECT_GT(clips, 50u);
  EXPECT_EQ(all.size(), frames);
  EXPECT_EQ(all.dof_names.size(), 28u);
}

}  // namespace
}  // namespace podium::character
