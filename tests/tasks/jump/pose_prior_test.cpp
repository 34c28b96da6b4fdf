// The jump task's pose prior (thesis §3.4.2, tasks/jump/pose_prior.h): the shipped athlete pose
// set, P-VAE training with real libtorch, a saved prior driving JumpEnv, the captured clips
// (when ../shared/data/jump is present) and the errors for bad paths.
#include "pose_prior.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "jump_test_util.h"
#include "podium/base/error.h"
#include "podium/character/frames.h"

namespace podium::tasks::jump {
namespace {

namespace fs = std::filesystem;

// An empty folder of this test's own (tests of one binary may run at once).
fs::path scratch(const std::string& name) {
  fs::path dir = fs::temp_directory_path() / ("jump_pose_prior_test_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// The first joint limit `pose` breaks, as sim measures them (hinge range; for ball joints the swing
// cone and the twist about the link's axis, sim/src/contact_solver.cpp); "" when none.
std::string broken_limit(const character::PoseBridge& bridge, const std::vector<double>& pose) {
  const Eigen::VectorXd q = bridge.target(pose);
  for (const sim::Link& l : bridge.model().links()) {
    if (l.joint == sim::JointType::revolute && (q(l.q_index) < l.lower || q(l.q_index) > l.upper)) return l.name;
    if (l.joint != sim::JointType::spherical) continue;
    Eigen::Quaterniond r = character::quat_at(q, l.q_index);
    if (r.w() < 0) r.coeffs() = -r.coeffs();
    const double swing = std::acos(std::clamp(l.axis.dot(r * l.axis), -1.0, 1.0));
    const double twist = 2.0 * std::atan2(r.vec().dot(l.axis), r.w());
    if (swing > l.swing_limit || twist < l.twist_lower || twist > l.twist_upper) return l.name;
  }
  return "";
}

std::vector<double> mean_pose(const learn::PoseDataset& set) {
  std::vector<double> mean(set.dof_names.size(), 0.0);
  for (const auto& p : set.poses)
    for (std::size_t k = 0; k < p.size(); ++k) mean[k] += p[k] / double(set.size());
  return mean;
}

double rms_distance(const std::vector<double>& a, const std::vector<double>& b) {
  double sq = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) sq += (a[k] - b[k]) * (a[k] - b[k]);
  return std::sqrt(sq / double(a.size()));
}

// The message of the UserError `f` throws, checked to be one line naming `name`.
template <class F>
void expect_one_line_error_naming(F&& f, const std::string& name) {
  try {
    f();
    ADD_FAILURE() << "no error for " << name;
  } catch (const base::UserError& e) {
    const std::string message = e.what();
    std::printf("%s\n", message.c_str());
    EXPECT_NE(message.find(name), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(PosePrior, ShippedSetHasTheAthletesPosesWithinItsJointLimits) {
  const sim::ModelPtr model = sim::load_shipped_model("athlete");
  const character::PoseBridge bridge(model);
  const learn::PoseDataset set = read_pose_prior_set("", model);
  EXPECT_EQ(set.dof_names, bridge.dof_names());
  EXPECT_EQ(set.lower, bridge.lower());  // the decoder's box
  EXPECT_EQ(set.upper, bridge.upper());
  EXPECT_GE(set.size(), 2000u);
  EXPECT_TRUE(set.conditions.empty());
  std::size_t broken = 0;
  std::string first;
  for (const auto& pose : set.poses) {
    ASSERT_EQ(pose.size(), bridge.size());
    const std::string joint = broken_limit(bridge, pose);
    if (!joint.empty() && broken++ == 0) first = joint;
  }
  EXPECT_EQ(broken, 0u) << "first at joint " << first;
  // Varied where jumps move most: hips and knees flex and extend over a wide range.
  const std::vector<double> mean = mean_pose(set);
  for (const char* dof : {"right_hip_y", "left_hip_y", "right_knee", "left_knee"}) {
    const std::size_t k = std::size_t(std::find(set.dof_names.begin(), set.dof_names.end(), dof) - set.dof_names.begin());
    double sq = 0.0;
    for (const auto& p : set.poses) sq += (p[k] - mean[k]) * (p[k] - mean[k]);
    EXPECT_GT(std::sqrt(sq / double(set.size())), 0.4) << dof;
  }
}

TEST(PosePrior, TrainingReducesTheLossAndSavesAFileThatLoads) {
  PosePriorSettings s;  // the thesis's settings, a few epochs
  s.vae.epochs = 4;
  std::vector<double> reported;
  double progress = 0.0;
  PosePriorReport report{[&](double f) { progress = f; },
                         [&](const std::string& name, double, double v) {
                           if (name == "pose_vae_loss") reported.push_back(v);
                         }};
  const fs::path dir = scratch("train");
  const PoseVaeOutcome out = train_pose_prior(s, dir, 3, nullptr, report);
  ASSERT_EQ(out.epoch_losses.size(), 4u);
  EXPECT_EQ(reported, out.epoch_losses);
  EXPECT_EQ(progress, 1.0);
  std::printf("loss per epoch %.4f %.4f %.4f %.4f, RMSE %.3f rad, %.1f s\n", out.epoch_losses[0], out.epoch_losses[1],
              out.epoch_losses[2], out.epoch_losses[3], out.rmse_rad, out.seconds);
  EXPECT_LT(out.epoch_losses.back(), 0.7 * out.epoch_losses.front());
  EXPECT_EQ(out.poses, read_pose_prior_set("", sim::load_shipped_model("athlete")).size());
  ASSERT_TRUE(fs::is_regular_file(out.file));
  EXPECT_FALSE(fs::exists(dir / "pose_vae.pt.partial"));
  const PosePrior prior = load_pose_prior(out.file);
  EXPECT_EQ(prior.vae->latent_size(), 13u);
  EXPECT_EQ(prior.frame, character::PoseBridge::Frame::z_up);
  fs::remove_all(dir);
}

TEST(PosePrior, CancelStopsAfterTheEpochAndSavesNothing) {
  PosePriorSettings s;
  s.vae.epochs = 50;
  std::atomic<bool> cancel{false};
  PosePriorReport report{{}, [&](const std::string&, double epoch, double) { cancel = epoch >= 2; }};
  const fs::path dir = scratch("cancel");
  const PoseVaeOutcome out = train_pose_prior(s, dir, 3, &cancel, report);
  EXPECT_TRUE(out.cancelled);
  EXPECT_EQ(out.epoch_losses.size(), 2u);
  EXPECT_TRUE(out.file.empty());
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

// decode(0) is the prior's "default" pose: after training it sits near the middle of the set.
TEST(PosePrior, SavedPriorGivesJumpEnvTheCompositeActionsAndAPlausibleZeroPose) {
  PosePriorSettings s;
  s.vae.epochs = 20;
  s.vae.learning_rate = 1e-3;  // a few seconds' training instead of the thesis's 80 epochs at 1e-4
  const fs::path dir = scratch("env");
  const PosePrior prior = load_pose_prior(train_pose_prior(s, dir, 5).file);
  fs::remove_all(dir);

  const JumpEnv env(testing::settings(), prior);
  const character::PoseBridge bridge(env.world().model_ptr());
  ASSERT_EQ(env.action_space().size(), 13u + bridge.size());  // thesis §3.4.2: d_latent + d_offset (28)

  const learn::PoseDataset set = read_pose_prior_set("", env.world().model_ptr());
  const std::vector<double> mean = mean_pose(set), zero = prior.vae->decode(std::vector<double>(13, 0.0));
  double spread = 0.0, nearest = 1e9;  // the poses' mean distance to the mean pose; decode(0)'s to the nearest pose
  for (const auto& p : set.poses) {
    spread += rms_distance(p, mean) / double(set.size());
    nearest = std::min(nearest, rms_distance(p, zero));
  }
  std::printf("decode(0) is %.3f rad (RMS) from the mean pose, %.3f from the nearest pose; the poses are %.3f from the mean\n",
              rms_distance(zero, mean), nearest, spread);
  EXPECT_LT(rms_distance(zero, mean), 0.5 * spread);
  EXPECT_LT(nearest, 0.15);  // a pose of the set, give or take its noise and the VAE's error
}

TEST(PosePrior, CapturedClipsFolderGivesAthletePoses) {
  const fs::path data = testing::captured_jump_dir();
  if (data.empty()) GTEST_SKIP() << "../shared/data/jump is absent (set PODIUM_SHARED_DIR): the captured clips are not checked";
  const sim::ModelPtr model = sim::load_shipped_model("athlete");
  const learn::PoseDataset set = read_pose_prior_set((data / "vae/txt").string(), model);
  std::printf("%zu poses from the captured clips (each frame and its mirror image)\n", set.size());
  EXPECT_GT(set.size(), 10000u);
  EXPECT_EQ(set.size() % 2, 0u);
  EXPECT_EQ(set.dof_names, character::PoseBridge(model).dof_names());
  for (const auto& pose : set.poses) ASSERT_EQ(pose.size(), 28u);
}

TEST(PosePrior, BadFoldersAndFilesAreNamedInOneLine) {
  const sim::ModelPtr model = sim::load_shipped_model("athlete");
  const fs::path dir = scratch("bad");
  expect_one_line_error_naming([&] { read_pose_prior_set((dir / "missing").string(), model); }, (dir / "missing").string());
  expect_one_line_error_naming([&] { read_pose_prior_set(dir.string(), model); }, dir.string());  // no clips in it
  const fs::path clip = dir / "clips" / "broken.txt";
  fs::create_directories(clip.parent_path());
  std::ofstream(clip) << R"({"Loop": "none", "Frames": [[0.03, 1, 2, 3]]})";
  expect_one_line_error_naming([&] { read_pose_prior_set(clip.parent_path().string(), model); }, clip.string());
  // A pose set of another skeleton (the get-up's 21-hinge humanoid).
  const fs::path other = fs::path(shipped_pose_set_path()).replace_filename("humanoid21_poses.json");
  expect_one_line_error_naming([&] { read_pose_prior_set(other.string(), model); }, other.string());
  expect_one_line_error_naming([&] { load_pose_prior(dir / "none.pt"); }, (dir / "none.pt").string());
  expect_one_line_error_naming([&] { load_pose_prior(clip); }, clip.string());  // not a saved VAE
  fs::remove_all(dir);
}

TEST(PosePrior, ConfigKeysReadTheThesisDefaults) {
  const base::Json empty = base::Json::object();
  base::ConfigReader r(empty, "");
  const PosePriorSettings s = read_pose_prior_settings(r);
  EXPECT_EQ(s.pose_set, "");
  EXPECT_EQ(s.vae.latent_size, 13);
  EXPECT_EQ(s.vae.beta, 1e-5 * 128);
  EXPECT_EQ(s.vae.learning_rate, 1e-4);
  EXPECT_EQ(s.vae.batch_size, 128);
  EXPECT_EQ(s.vae.epochs, 80);
  EXPECT_EQ(s.vae.hidden, (std::vector<int>{256, 256}));
  const base::Json set = {{"pose_set", "clips"}, {"vae_epochs", 5}, {"vae_beta", 0.001}};
  base::ConfigReader r2(set, "");
  const PosePriorSettings t = read_pose_prior_settings(r2);
  EXPECT_EQ(t.pose_set, "clips");
  EXPECT_EQ(t.vae.epochs, 5);
  EXPECT_EQ(t.vae.beta, 0.001);
  const base::Json bad = {{"vae_epochs", 0}};
  base::ConfigReader r3(bad, "");
  EXPECT_THROW(read_pose_prior_settings(r3), base::ConfigError);
}

}  // namespace
}  // namespace podium::tasks::jump
