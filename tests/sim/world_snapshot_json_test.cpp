// WorldSnapshot as JSON text: every double survives, and a World restored from the text in a
// fresh World replays bitwise (checkpoints that resume in another process).
#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <limits>
#include <vector>

#include "podium/base/error.h"
#include "podium/sim/starts.h"
#include "podium/sim/world.h"

namespace podium::sim {
namespace {

// nlohmann writes each double as a decimal that reads back to the same bits: random bit patterns
// over all exponents, subnormals, ±0 and the extremes.
TEST(WorldSnapshotJson, DoublesRoundTripBitwiseThroughNlohmann) {
  base::Rng rng(5);
  std::vector<double> values = {0.0,
                                -0.0,
                                0.1,
                                1.0 / 3.0,
                                std::numeric_limits<double>::denorm_min(),
                                std::numeric_limits<double>::min(),
                                std::numeric_limits<double>::max(),
                                -std::numeric_limits<double>::max(),
                                std::numeric_limits<double>::epsilon()};
  while (values.size() < 100000) {
    const double x = std::bit_cast<double>(rng.next());
    if (std::isfinite(x)) values.push_back(x);
  }
  const base::Json back = base::Json::parse(base::Json(values).dump());
  for (std::size_t i = 0; i < values.size(); ++i)
    ASSERT_EQ(std::bit_cast<std::uint64_t>(back[i].get<double>()), std::bit_cast<std::uint64_t>(values[i]))
        << base::Json(values[i]).dump();
}

// humanoid34 on rough tiles beside a mat, with a locked elbow, wind, per-episode friction and
// strength: a snapshot taken mid-fall, written as text and read into a fresh World, replays 2 s
// (torque and SPD steps) bitwise, and snapshots again to the same text.
TEST(WorldSnapshotJson, FreshWorldFromTheTextReplaysBitwise) {
  const ModelPtr model = load_shipped_model("humanoid34");
  WorldConfig config;
  TerrainRegion tiles;  // beside the drop point: the plane, tiles and the mat all get touched
  tiles.kind = TerrainRegion::Kind::rough;
  tiles.min = Eigen::Vector2d(-3.0, 0.3), tiles.max = Eigen::Vector2d(3.0, 3.3);
  tiles.tile_size_m = 0.5;
  tiles.min_tile_height_m = -0.05, tiles.max_tile_height_m = 0.1;
  tiles.seed = 3;
  config.terrain.regions = {tiles};
  config.terrain.boxes = {{"mat", Eigen::Vector3d(0.7, -0.4, 0.1), Eigen::Vector3d(0.4, 0.5, 0.1),
                           Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX())), 0.8, "mat"}};
  config.edits.joints = {{"left_elbow", base::Json{{"lock", 0.6}}}};
  World world(model, config);
  world.set_friction(0.7);
  world.set_strength(0.8);
  base::Rng rng(11);
  RagdollStart fall;
  fall.control_steps = 30;
  ASSERT_TRUE(ragdoll_start(world, rng, fall).ok);
  const Wind wind{Eigen::Vector3d(4.0, 1.0, 0.0)};
  world.apply_wind(wind);
  const std::string text = world.snapshot().to_json().dump();

  std::vector<Eigen::VectorXd> actions;
  const Eigen::VectorXd limits = world.model().torque_limits();
  for (int k = 0; k < 80; ++k) {
    if (k < 40) {
      Eigen::VectorXd tau = Eigen::VectorXd::Zero(world.model().nv());
      for (int i = 6; i < tau.size(); ++i) tau(i) = rng.normal(0.0, 0.1) * limits(i);
      actions.push_back(tau);
    } else {
      actions.push_back(random_pose(world.model(), rng, 0.0, 0.8));
    }
  }
  auto run = [&](World& w, std::vector<Eigen::VectorXd>& q, std::vector<Eigen::VectorXd>& qd, std::vector<Contact>& seen) {
    for (std::size_t k = 0; k < actions.size(); ++k) {
      ASSERT_TRUE(w.control_step(k < 40 ? Control::torque : Control::spd_maba, actions[k]).ok) << k;
      w.apply_wind(wind);
      q.push_back(w.data().q), qd.push_back(w.data().qd);
      for (const Contact& c : w.observe().contacts) seen.push_back(c);
    }
  };
  std::vector<Eigen::VectorXd> q, qd, q2, qd2;
  std::vector<Contact> seen, seen2;
  run(world, q, qd, seen);
  bool ground = false, prop = false;
  for (const Contact& c : seen) ground |= c.partner == Contact::Partner::ground, prop |= c.partner == Contact::Partner::prop;
  EXPECT_TRUE(ground && prop);

  WorldConfig plain;
  plain.edits = config.edits;
  World fresh(model, plain);
  fresh.restore(WorldSnapshot::from_json(base::Json::parse(text), fresh.model_ptr()));
  EXPECT_TRUE(fresh.snapshot().to_json().dump() == text) << "a snapshot of the restored World differs";
  EXPECT_EQ(fresh.config().friction, 0.7);
  EXPECT_EQ(fresh.terrain().config().boxes.at(0).name, "mat");
  EXPECT_EQ(fresh.terrain().config().boxes.at(0).kind, "mat");
  run(fresh, q2, qd2, seen2);
  ASSERT_EQ(q2.size(), q.size());
  for (std::size_t k = 0; k < q.size(); ++k) {
    ASSERT_EQ(q2[k], q[k]) << "control step " << k;
    ASSERT_EQ(qd2[k], qd[k]) << "control step " << k;
  }
  EXPECT_EQ(seen2, seen);
}

TEST(WorldSnapshotJson, RejectsAnotherModelAndBadFields) {
  const ModelPtr model = load_shipped_model("humanoid34");
  World world(model, WorldConfig{});
  const base::Json json = world.snapshot().to_json();
  EXPECT_THROW(WorldSnapshot::from_json(json, load_shipped_model("humanoid21")), base::UserError);
  // The same model with other edits is another model.
  EXPECT_THROW(WorldSnapshot::from_json(json, edit_model(model, ModelEdits{{"left_hand"}, {}})), base::UserError);
  base::Json bad = json;
  bad["qd"].erase(bad["qd"].begin());
  try {
    WorldSnapshot::from_json(bad, model);
    FAIL() << "a short qd was accepted";
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("qd: expected an array of 34 numbers, got 33 entries"), std::string::npos) << e.what();
  }
  bad = json;
  bad["config"]["terrain"].erase("boxes");
  EXPECT_THROW(WorldSnapshot::from_json(bad, model), base::UserError);
  bad = json;
  bad["q"][3] = "one";
  EXPECT_THROW(WorldSnapshot::from_json(bad, model), base::UserError);
  // Non-finite values are written as strings and read back.
  bad = json;
  bad["qdd"][0] = "nan";
  bad["tau"][0] = "-inf";
  const WorldSnapshot s = WorldSnapshot::from_json(bad, model);
  const base::Json again = s.to_json();
  EXPECT_EQ(again["qdd"][0], "nan");
  EXPECT_EQ(again["tau"][0], "-inf");
}

}  // namespace
}  // namespace podium::sim
