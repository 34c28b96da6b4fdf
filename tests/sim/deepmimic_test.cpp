// DeepMimic character format (tested on ../shared/data when present; its motion clips are tested
// in tests/character).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "podium/base/error.h"
#include "podium/base/json.h"
#include "podium/sim/model.h"
#include "shared_data.h"

namespace podium::sim {
namespace {

using base::Json;

std::filesystem::path deepmimic_dir() { return podium::testing::shared_data("deepmimic/data"); }

std::filesystem::path jump_dir() { return podium::testing::shared_data("jump/data"); }

// A root and one joint below it, in DeepMimic's format; `joint` adds or overrides the joint's keys.
std::filesystem::path write_character(const std::string& name, const Json& joint) {
  Json j = {{"ID", 1}, {"Name", "hip"}, {"Type", "spherical"}, {"Parent", 0}, {"AttachX", 0}, {"AttachY", -0.1}, {"AttachZ", 0}};
  j.update(joint);
  const Json character = {
      {"Skeleton",
       {{"Joints",
         {{{"ID", 0}, {"Name", "root"}, {"Type", "none"}, {"Parent", -1}, {"AttachX", 0}, {"AttachY", 0}, {"AttachZ", 0}}, j}}}},
      {"BodyDefs",
       {{{"ID", 0},
         {"Shape", "sphere"},
         {"Mass", 8},
         {"AttachX", 0},
         {"AttachY", 0},
         {"AttachZ", 0},
         {"Param0", 0.2},
         {"Param1", 0.2},
         {"Param2", 0.2}},
        {{"ID", 1},
         {"Shape", "capsule"},
         {"Mass", 4},
         {"AttachX", 0},
         {"AttachY", -0.2},
         {"AttachZ", 0},
         {"Param0", 0.1},
         {"Param1", 0.3},
         {"Param2", 0.1}}}}};
  auto path = std::filesystem::temp_directory_path() /
              ("podium_sim_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" + name);
  std::ofstream(path) << character.dump(1);
  return path;
}

std::string load_error(const std::filesystem::path& path) {
  try {
    load_deepmimic(path);
  } catch (const base::UserError& e) {
    std::filesystem::remove(path);
    return e.what();
  }
  std::filesystem::remove(path);
  return "(loaded without an error)";
}

TEST(DeepMimic, LoadsHumanoidWith34Dofs) {
  const auto dir = deepmimic_dir();
  if (dir.empty() || !std::filesystem::exists(dir / "characters/humanoid3d.txt"))
    GTEST_SKIP() << "../shared/data/deepmimic absent (PODIUM_SHARED_DIR)";
  const ModelPtr model = load_deepmimic(dir / "characters/humanoid3d.txt", dir / "controllers/humanoid3d_ctrl.txt");
  EXPECT_EQ(model->nv(), 34);
  EXPECT_EQ(model->nq(), 7 + 4 * 8 + 4);  // 8 spherical + 4 revolute
  EXPECT_NEAR(model->total_mass(), 45.0, 1e-9);
  EXPECT_EQ(model->kp()(model->link("chest").v_index), 1000.0);
}

// The thesis's jumper gives its hips, ankles and shoulders a limit per axis (TorqueLimX/Y/Z in
// DeepMimic's y-up joint frame): each DoF gets the file's value for its axis (x, y, z here are
// DeepMimic's x, z, y), never the 1 N·m that a scalar-only reader fell back to.
TEST(DeepMimic, JumperLoadsThePerAxisTorqueLimitsOfItsFile) {
  const auto file = jump_dir() / "characters/humanoid3d_jumper60kg.txt";
  if (jump_dir().empty() || !std::filesystem::exists(file)) GTEST_SKIP() << "../shared/data/jump absent (PODIUM_SHARED_DIR)";
  const ModelPtr model = load_deepmimic(file);
  const Json src = base::read_json_file(file);
  int per_axis = 0, checked = 0;
  for (const Json& j : src["Skeleton"]["Joints"]) {
    const std::string name = j["Name"].get<std::string>(), type = j["Type"].get<std::string>();
    if (type != "spherical" && type != "revolute") continue;
    const Link& l = model->link(name);
    const Eigen::VectorXd got = model->torque_limits().segment(l.v_index, l.nv);
    Eigen::VectorXd want;
    if (j.contains("TorqueLimX")) {
      want = Eigen::Vector3d(j["TorqueLimX"].get<double>(), j["TorqueLimZ"].get<double>(), j["TorqueLimY"].get<double>());
      ++per_axis;
    } else {
      want = Eigen::VectorXd::Constant(l.nv, j["TorqueLim"].get<double>());
    }
    EXPECT_EQ(got, want) << name;
    ++checked;
  }
  EXPECT_EQ(per_axis, 6);  // hips, ankles, shoulders
  EXPECT_EQ(checked, 12);
  const Link& hip = model->link("right_hip");
  EXPECT_EQ(model->torque_limits()(hip.v_index + 1), 500.0);  // flexion, about the lateral axis
  EXPECT_EQ(model->torque_limits()(hip.v_index + 2), 50.0);   // twist, about the thigh
}

// A malformed limit is one line naming the file, the joint and the field.
TEST(DeepMimic, MalformedTorqueLimitNamesFileJointAndField) {
  const std::string not_a_number =
      load_error(write_character("strong.txt", {{"TorqueLimX", 100}, {"TorqueLimY", "strong"}, {"TorqueLimZ", 100}}));
  EXPECT_NE(not_a_number.find("strong.txt: joint hip (Skeleton.Joints[1]).TorqueLimY: \"strong\" is not a number > 0 (N·m)"),
            std::string::npos)
      << not_a_number;
  const std::string missing = load_error(write_character("missing_z.txt", {{"TorqueLimX", 100}, {"TorqueLimY", 50}}));
  EXPECT_NE(missing.find("missing_z.txt: joint hip (Skeleton.Joints[1]).TorqueLimZ: missing"), std::string::npos) << missing;
  const std::string list = load_error(write_character("list.txt", {{"Type", "revolute"}, {"TorqueLim", {1, 2, 3}}}));
  EXPECT_NE(list.find("list.txt: joint hip (Skeleton.Joints[1]).TorqueLim: [1,2,3] is not a number > 0 (N·m)"), std::string::npos)
      << list;
  const std::string none = load_error(write_character("none.txt", Json::object()));
  EXPECT_NE(none.find("none.txt: joint hip (Skeleton.Joints[1]).TorqueLim: missing"), std::string::npos) << none;
  for (const std::string& e : {not_a_number, missing, list, none}) EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  // A well-formed per-axis joint loads with its limits (x, z, y after the y-up → z-up turn).
  const auto good = write_character("good.txt", {{"TorqueLimX", 100}, {"TorqueLimY", 50}, {"TorqueLimZ", 300}});
  const ModelPtr model = load_deepmimic(good);
  std::filesystem::remove(good);
  EXPECT_EQ(model->torque_limits().tail<3>(), Eigen::Vector3d(100, 300, 50));
}

}  // namespace
}  // namespace podium::sim
