// Take-off states (thesis §3.4.1, §3.6.1): the shipped reference is one-leg support at running
// speed; the explored features; loaders for the captured run-ups when ../shared/data is present.
#include "takeoff.h"

#include <gtest/gtest.h>

#include <fstream>

#include "jump_test_util.h"
#include "podium/base/error.h"
#include "podium/sim/dynamics.h"

namespace podium::tasks::jump {
namespace {

struct Support {
  double foot_low = 0.0, others_low = 1e9;
};

// The take-off foot's lowest point and the lowest point of every other body.
Support support_of(const sim::ModelPtr& model, const TakeoffState& s, int foot) {
  sim::World world(model, sim::WorldConfig{});
  world.reset(s.q, s.qd());
  const sim::Observation obs = world.observe();
  Support out;
  out.foot_low = 1e9;
  for (const sim::Contact& c : obs.contacts) {
    if (c.partner != sim::Contact::Partner::ground) continue;
    if (c.body == foot) out.foot_low = 0.0;
    else out.others_low = 0.0;
  }
  return out;
}

TEST(Takeoff, ShippedStateIsOneLegSupportAtRunningSpeed) {
  const sim::ModelPtr model = sim::load_shipped_model("athlete");
  const int foot = model->find_body("right_foot");
  const TakeoffState s = read_takeoff_json(model, shipped_takeoff_path(), foot);
  EXPECT_EQ(s.q(0), 0.0);
  EXPECT_EQ(s.q(1), 0.0);
  const double speed = s.root_velocity.head<2>().norm();
  EXPECT_GE(speed, 5.0);
  EXPECT_LE(speed, 7.0);
  const Support support = support_of(model, s, foot);
  EXPECT_EQ(support.foot_low, 0.0) << "the take-off foot touches the ground";
  EXPECT_GT(support.others_low, 0.0) << "nothing else does";
  // The root faces +x (heading 0) and stands about a leg's length up.
  EXPECT_NEAR(character::heading_yaw(character::quat_at(s.q, 3).toRotationMatrix()), 0.0, 1e-12);
  EXPECT_GT(s.q(2), 0.85);
}

TEST(Takeoff, FeaturesSetRootAngularAndLateralVelocity) {
  const sim::ModelPtr model = sim::load_shipped_model("athlete");
  const TakeoffState ref = read_takeoff_json(model, shipped_takeoff_path(), model->find_body("right_foot"));
  ASSERT_EQ(takeoff_features(JumpKind::high_jump).size(), 4u);
  ASSERT_EQ(takeoff_features(JumpKind::obstacle).size(), 3u);
  const std::vector<double> x = {1.0, -2.0, 0.5, 2.0};
  const TakeoffState high = apply_takeoff_features(JumpKind::high_jump, ref, x);
  EXPECT_EQ(high.root_omega, Eigen::Vector3d(-2.0, 0.5, 3.0));  // ω_z fixed at 3 rad/s
  EXPECT_EQ(high.root_velocity.y(), 2.0);
  EXPECT_EQ(high.root_velocity.x(), ref.root_velocity.x());
  EXPECT_EQ(high.q, ref.q);
  EXPECT_EQ(approach_angle(JumpKind::high_jump, x, 9.0), 1.0);
  const TakeoffState box = apply_takeoff_features(JumpKind::obstacle, ref, std::vector<double>{0.1, 0.2, 0.3});
  EXPECT_EQ(box.root_omega, Eigen::Vector3d(0.1, 0.2, 0.3));
  EXPECT_EQ(box.root_velocity, ref.root_velocity);
  EXPECT_EQ(approach_angle(JumpKind::obstacle, std::vector<double>{0.1, 0.2, 0.3}, 9.0), 9.0);
  EXPECT_THROW(apply_takeoff_features(JumpKind::obstacle, ref, x), base::UserError);
  // qd() holds the world velocities in the root frame.
  const Eigen::VectorXd qd = high.qd();
  const Eigen::Matrix3d R = character::quat_at(high.q, 3).toRotationMatrix();
  EXPECT_LT((R * qd.head<3>() - high.root_omega).norm(), 1e-12);
  EXPECT_LT((R * qd.segment<3>(3) - high.root_velocity).norm(), 1e-12);
}

TEST(Takeoff, StateFileErrorsNameTheKey) {
  const sim::ModelPtr model = sim::load_shipped_model("athlete");
  const auto path = std::filesystem::temp_directory_path() / "podium_jump_bad_takeoff.json";
  std::ofstream(path) << R"({"root_rotation": [0, 0, 0], "root_velocity": [6, 0, 0], "root_angular_velocity": [0, 0, 0],
                            "joints": {"tail": 0.3}})";
  try {
    read_takeoff_json(model, path, model->find_body("right_foot"));
    FAIL();
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("joints.tail: model athlete has no such joint"), std::string::npos) << e.what();
  }
  // Standing on both feet is not a one-leg take-off.
  std::ofstream(path) << R"({"root_rotation": [0, 0, 0], "root_velocity": [6, 0, 0], "root_angular_velocity": [0, 0, 0]})";
  try {
    read_takeoff_json(model, path, model->find_body("right_foot"));
    FAIL();
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("left_foot is"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

// arpspoof/Jump's run-up end (data/states/jumper_run_p1.npy) plants the left foot (its right knee
// is folded at 1.85 rad, the left nearly straight): with take-off foot "left_foot" it loads as a
// one-leg take-off, with the right foot it is refused.
TEST(Takeoff, CapturedRunUpEndLoadsWhenPresent) {
  const auto dir = testing::captured_jump_dir();
  if (dir.empty()) GTEST_SKIP() << "../shared/data/jump absent (PODIUM_SHARED_DIR)";
  const sim::ModelPtr model = sim::load_shipped_model("athlete");
  const auto path = dir / "states/jumper_run_p1.npy";
  EXPECT_THROW(read_takeoff_npy(model, path, model->find_body("right_foot")), base::UserError);
  const int foot = model->find_body("left_foot");
  const TakeoffState s = read_takeoff_npy(model, path, foot);
  const double speed = s.root_velocity.head<2>().norm();
  std::printf("captured run-up end: speed %.2f m/s, root ω (%.2f, %.2f, %.2f) rad/s, v_z %.2f m/s\n", speed, s.root_omega.x(),
              s.root_omega.y(), s.root_omega.z(), s.root_velocity.z());
  EXPECT_GT(speed, 4.0);
  EXPECT_GT(s.root_omega.z(), 1.5);  // the curved sprint's turn (thesis: ω about the vertical 3 rad/s)
  EXPECT_EQ(support_of(model, s, foot).foot_low, 0.0);
  // As the episode's reference state.
  JumpSettings settings = testing::settings();
  settings.takeoff_state = path.string();
  settings.takeoff_foot = "left_foot";
  JumpEnv env(settings);
  std::vector<double> obs;
  env.reset(obs);
  EXPECT_TRUE(env.features().touches(foot, sim::Contact::Partner::ground));
}

// The captured high jumps' take-off frames: the foot that leaves the ground last before the peak
// leaves it moving up fast (Fosbury flop and scissor off the right foot, straddle off the left).
TEST(Takeoff, CapturedJumpTakeoffFrameWhenPresent) {
  const auto dir = testing::captured_jump_dir();
  if (dir.empty()) GTEST_SKIP() << "../shared/data/jump absent (PODIUM_SHARED_DIR)";
  const sim::ModelPtr model = sim::load_shipped_model("athlete");
  for (auto [name, foot_name] : {std::pair{"VC5_high_jump__fosbury_flop_06.txt", "right_foot"},
                                 {"VC5_high_jump__scissor_01.txt", "right_foot"},
                                 {"VC5_high_jump__straddle_02.txt", "left_foot"}}) {
    const character::Clip clip = character::read_deepmimic_clip(model, dir / "motions/beyond" / name);
    const TakeoffState s = takeoff_from_clip(clip, model->find_body(foot_name));
    std::printf("%s off the %s: horizontal %.2f m/s, up %.2f m/s, root ω (%.2f, %.2f, %.2f) rad/s\n", name, foot_name,
                s.root_velocity.head<2>().norm(), s.root_velocity.z(), s.root_omega.x(), s.root_omega.y(), s.root_omega.z());
    EXPECT_GT(s.root_velocity.head<2>().norm(), 1.5) << name;
    EXPECT_GT(s.root_velocity.z(), 1.0) << name;
  }
}

}  // namespace
}  // namespace podium::tasks::jump
