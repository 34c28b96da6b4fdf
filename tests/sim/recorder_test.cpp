// Trajectory and BVH writers: the files describe the recorded motion exactly enough to replay it.
#include "podium/sim/recorder.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "podium/base/json.h"
#include "podium/sim/starts.h"

namespace podium::sim {
namespace {

std::filesystem::path temp_file(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("podium_sim_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" + name);
}

Recorder record_ragdoll(const ModelPtr& model, int steps, const TerrainConfig& terrain = {}) {
  WorldConfig config;
  config.terrain = terrain;
  World world(model, config);
  base::Rng rng(4);
  world.set_state(random_pose(*model, rng, 1.5), Eigen::VectorXd::Zero(model->nv()));
  Recorder rec(model);
  for (int k = 0; k < steps; ++k) {
    rec.record(world);
    world.control_step(Control::torque, Eigen::VectorXd::Zero(model->nv()));
  }
  return rec;
}

// The file carries the props and the terrain's boxes (what the replay draws) and per frame q and q̇.
TEST(Recorder, TrajectoryFileHasHeaderPropsTerrainAndOneLinePerFrame) {
  const ModelPtr model = load_shipped_model("humanoid21");
  TerrainConfig terrain;
  TerrainRegion tiles;
  tiles.kind = TerrainRegion::Kind::rough;
  tiles.min = {2.0, -1.0};
  tiles.max = {4.0, 1.0};
  tiles.min_tile_height_m = -0.05;
  tiles.max_tile_height_m = 0.05;
  terrain.regions.push_back(tiles);
  terrain.boxes.push_back(
      {"bar", Eigen::Vector3d(0, 1.5, 1.2), Eigen::Vector3d(0.6, 0.02, 0.02), Eigen::Quaterniond::Identity(), 1.0, "crossbar"});
  const Recorder rec = record_ragdoll(model, 20, terrain);
  const auto path = temp_file("traj.jsonl");
  write_trajectory(rec, path);
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  const base::Json header = base::Json::parse(line);
  EXPECT_EQ(header["format"], "podium-trajectory");
  EXPECT_EQ(header["version"], 2);
  EXPECT_EQ(header["links"].size(), model->links().size());
  ASSERT_EQ(header["props"].size(), 1u);
  EXPECT_EQ(header["props"][0]["name"], "bar");
  EXPECT_EQ(header["props"][0]["kind"], "crossbar");  // what the box stands for, as declared
  EXPECT_EQ(header["props"][0]["pos"], base::Json({0.0, 1.5, 1.2}));
  EXPECT_EQ(header["props"][0]["quat"], base::Json({1.0, 0.0, 0.0, 0.0}));
  ASSERT_EQ(header["terrain"]["pieces"].size(), 4u);  // 2 × 2 one-metre tiles
  const Terrain check(terrain);
  for (const base::Json& p : header["terrain"]["pieces"]) {
    const double top = p["pos"][2].get<double>() + p["half_extents"][2].get<double>();
    EXPECT_NEAR(top, check.height(p["pos"][0].get<double>(), p["pos"][1].get<double>()), 1e-5);
  }
  int frames = 0;
  while (std::getline(in, line)) {
    const base::Json f = base::Json::parse(line);
    const Frame& ref = rec.frames()[frames];
    // Link 3's world position survives the round trip to 1e-5 m, and so do the velocities.
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(f["links"][3][k].get<double>(), ref.links[3](k), 1e-5);
    EXPECT_EQ(f["q"].size(), static_cast<std::size_t>(model->nq()));
    ASSERT_EQ(f["qd"].size(), static_cast<std::size_t>(model->nv()));
    for (int k = 0; k < model->nv(); ++k) EXPECT_NEAR(f["qd"][k].get<double>(), ref.qd(k), 1e-5);
    ++frames;
  }
  EXPECT_EQ(frames, 20);
  EXPECT_GT(rec.frames().back().qd.norm(), 1.0);  // falling
  std::filesystem::remove(path);
}

// Forward kinematics of a BVH frame (ZXY Euler, offsets) reproduces the recorded link positions.
TEST(Recorder, BvhForwardKinematicsReproducesLinkPositions) {
  const ModelPtr model = load_shipped_model("humanoid34");
  const Recorder rec = record_ragdoll(model, 5);
  const auto path = temp_file("motion.bvh");
  write_bvh(rec, path, 1.0 / 40.0);
  std::ifstream in(path);
  std::stringstream all;
  all << in.rdbuf();
  const std::string text = all.str();
  const std::string last_line = text.substr(text.rfind('\n', text.size() - 2) + 1);
  std::istringstream values(last_line);
  const auto& links = model->links();
  std::vector<Eigen::Matrix3d> R(links.size());
  std::vector<Eigen::Vector3d> p(links.size());
  const double deg = M_PI / 180.0;
  for (std::size_t i = 0; i < links.size(); ++i) {
    Eigen::Vector3d pos = Eigen::Vector3d::Zero();
    if (i == 0) values >> pos.x() >> pos.y() >> pos.z();
    double z, x, y;
    values >> z >> x >> y;
    const Eigen::Matrix3d local =
        (Eigen::AngleAxisd(z * deg, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(x * deg, Eigen::Vector3d::UnitX()) *
         Eigen::AngleAxisd(y * deg, Eigen::Vector3d::UnitY()))
            .toRotationMatrix();
    if (i == 0) {
      R[i] = local;
      p[i] = pos;
    } else {
      R[i] = R[links[i].parent] * local;
      p[i] = p[links[i].parent] + R[links[i].parent] * links[i].joint_pos;
    }
    EXPECT_LE((p[i] - rec.frames().back().links[i].head<3>()).norm(), 1e-4) << links[i].name;
  }
  EXPECT_NE(text.find("Frames: 5"), std::string::npos);
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace podium::sim
