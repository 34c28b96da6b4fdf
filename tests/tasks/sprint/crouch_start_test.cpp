// The Start phase's keyframed crouch starts on humanoid34: the set position in the blocks (each
// foot on its block, both hands on the ground behind the line), the first landing (the rear-block
// foot on the ground at the set distance), the frames at the control rate and within the joints'
// limits.
#include "crouch_start.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "podium/base/error.h"
#include "podium/sim/dynamics.h"
#include "podium/sim/world.h"

namespace podium::tasks::sprint {
namespace {

constexpr double kHz = 30.0;

sim::ModelPtr humanoid() { return sim::load_shipped_model("humanoid34"); }

std::unique_ptr<sim::World> world_at(const sim::ModelPtr& model, const std::vector<BlockSpec>& blocks, const Eigen::VectorXd& q) {
  sim::WorldConfig config;
  config.sim_hz = 600.0, config.control_hz = kHz;
  config.terrain.boxes = starting_blocks(blocks);
  auto world = std::make_unique<sim::World>(model, config);
  world->reset(q, Eigen::VectorXd::Zero(model->nv()));
  return world;
}

// The hand's sphere: its centre's world position and radius.
std::pair<Eigen::Vector3d, double> hand_sphere(const sim::CharacterModel& m, const sim::CharacterData& d, int hand) {
  const int link = m.bodies()[static_cast<std::size_t>(hand)].link;
  for (const sim::Geom& g : m.links()[static_cast<std::size_t>(link)].geoms)
    if (g.body == hand)
      return {d.links[static_cast<std::size_t>(link)].p + d.links[static_cast<std::size_t>(link)].R * g.pos, g.radius};
  ADD_FAILURE() << "no hand geom";
  return {};
}

std::string side(Foot f) { return f == Foot::left ? "left_" : "right_"; }
Foot other(Foot f) { return f == Foot::left ? Foot::right : Foot::left; }

TEST(SprintCrouchStart, TheSetHasFourStartsLeftAndRightFootTimesTwoArmActions) {
  const std::vector<CrouchStart> set = crouch_start_set(humanoid(), kHz);
  ASSERT_EQ(set.size(), 4u);
  EXPECT_EQ(set[0].name, "left_straight");
  EXPECT_EQ(set[1].name, "left_bent");
  EXPECT_EQ(set[2].name, "right_straight");
  EXPECT_EQ(set[3].name, "right_bent");
  // The arm actions differ (the elbow's crook) and the right starts are the left ones mirrored.
  EXPECT_GT((set[0].clip->poses[5] - set[1].clip->poses[5]).norm(), 0.5);
  EXPECT_EQ(set[2].blocks[0].y_m, -set[0].blocks[0].y_m);
}

TEST(SprintCrouchStart, TheSetPositionPutsEachFootOnItsBlockAndBothHandsOnTheGroundBehindTheLine) {
  const sim::ModelPtr model = humanoid();
  for (const CrouchStart& s : crouch_start_set(model, kHz)) {
    SCOPED_TRACE(s.name);
    const auto world = world_at(model, s.blocks, s.clip->poses.front());
    const int front = model->find_body(side(s.spec.front) + "foot"), rear = model->find_body(side(other(s.spec.front)) + "foot");
    // Blocks: prop 0 the front, 1 the rear; each sole on its face, within 5 mm.
    EXPECT_NEAR(world->prop_distance(front, 0), 0.0, 0.005);
    EXPECT_NEAR(world->prop_distance(rear, 1), 0.0, 0.005);
    EXPECT_GT(world->prop_distance(front, 1), 0.05);
    EXPECT_GT(world->prop_distance(rear, 0), 0.05);
    for (const char* hand : {"left_hand", "right_hand"}) {
      const auto [centre, radius] = hand_sphere(*model, world->data(), model->find_body(hand));
      EXPECT_NEAR(centre.z() - radius, 0.0, 0.005) << hand;  // on the ground
      EXPECT_LT(centre.x() + radius, 0.0) << hand;           // behind the line
    }
    // Nothing else touches the ground: feet on the blocks, hands on the track.
    const sim::Observation o = world->observe();
    for (const sim::Contact& c : o.contacts) {
      const std::string& name = model->bodies()[static_cast<std::size_t>(c.body)].name;
      if (c.partner == sim::Contact::Partner::ground) {
        EXPECT_NE(name.find("hand"), std::string::npos) << name;
      }
    }
    EXPECT_TRUE(o.touches(front, sim::Contact::Partner::prop, 0));
    EXPECT_TRUE(o.touches(rear, sim::Contact::Partner::prop, 1));
  }
}

TEST(SprintCrouchStart, TheLastFrameIsTheFirstLandingOfTheRearBlockFootAtTheSetDistance) {
  const sim::ModelPtr model = humanoid();
  for (const double landing : {0.6, 2.5}) {  // ours and the seed's "about 2.5 m"
    CrouchStartSpec base;
    base.landing_x_m = landing;
    for (const CrouchStart& s : crouch_start_set(model, kHz, base)) {
      SCOPED_TRACE(s.name + " at " + std::to_string(landing));
      const auto world = world_at(model, s.blocks, s.clip->poses.back());
      const int stance = model->find_body(side(other(s.spec.front)) + "foot");
      const int swing = model->find_body(side(s.spec.front) + "foot");
      const sim::Observation o = world->observe();
      EXPECT_TRUE(o.touches(stance, sim::Contact::Partner::ground));
      for (const sim::Contact& c : o.contacts) EXPECT_EQ(c.body, stance);  // only the stance foot touches anything
      EXPECT_NEAR(world->body_centroid(stance).x(), landing, 0.05);
      EXPECT_GT(world->body_centroid(swing).z(), 0.1);
      // Before the last frame no foot is on the ground past the blocks: this is the first landing.
      for (std::size_t f = 0; f + 1 < s.clip->size(); ++f) {
        sim::CharacterData d(*model);
        d.q = s.clip->poses[f];
        sim::forward_kinematics(*model, d);
        EXPECT_GT(sim::body_point(*model, d, stance, Eigen::Vector3d::Zero()).z(), 0.05) << "frame " << f;
      }
    }
  }
}

TEST(SprintCrouchStart, FramesAreAtTheControlRateWithinTheJointLimits) {
  const sim::ModelPtr model = humanoid();
  for (const CrouchStart& s : crouch_start_set(model, kHz)) {
    SCOPED_TRACE(s.name);
    const character::Clip& clip = *s.clip;
    ASSERT_GE(clip.size(), 10u);
    EXPECT_FALSE(clip.loop);
    for (std::size_t f = 0; f < clip.size(); ++f) {
      EXPECT_NEAR(clip.times_s[f], static_cast<double>(f) / kHz, 1e-9);
      for (const sim::Link& l : model->links()) {
        if (l.joint == sim::JointType::revolute) {
          EXPECT_GE(clip.poses[f](l.q_index), l.lower - 1e-9) << l.name << " frame " << f;
          EXPECT_LE(clip.poses[f](l.q_index), l.upper + 1e-9) << l.name << " frame " << f;
        } else if (l.joint == sim::JointType::spherical && l.swing_limit >= 0) {
          const Eigen::Vector4d w = clip.poses[f].segment<4>(l.q_index);
          EXPECT_NEAR(w.norm(), 1.0, 1e-12);
          EXPECT_LE(2.0 * std::acos(std::min(1.0, std::abs(w(0)))), l.swing_limit + 1e-9) << l.name << " frame " << f;
        }
      }
    }
    // The runner moves forward throughout, and no body but the supports dips below the ground.
    for (std::size_t f = 1; f < clip.size(); ++f) EXPECT_GE(clip.poses[f](0), clip.poses[f - 1](0) - 1e-12) << f;
    for (std::size_t f = 0; f < clip.size(); ++f) {
      sim::CharacterData d(*model);
      d.q = clip.poses[f];
      sim::forward_kinematics(*model, d);
      EXPECT_GT(sim::lowest_geom_point(*model, d), -0.01) << "frame " << f;
    }
  }
}

TEST(SprintCrouchStart, BadSettingsAreRefusedWithTheirName) {
  CrouchStartSpec spec;
  spec.landing_x_m = -0.2;  // behind the take-off
  EXPECT_THROW(crouch_start_clip(humanoid(), spec, kHz), base::UserError);
  spec = {};
  spec.rear_off_s = 0.5;  // after the front foot's take-off
  EXPECT_THROW(crouch_start_clip(humanoid(), spec, kHz), base::UserError);
  std::vector<BlockSpec> far = default_blocks();
  far[0].x_m = -2.5;  // out of the set position's reach
  EXPECT_THROW(crouch_start_clip(humanoid(), CrouchStartSpec{}, kHz, far), base::UserError);
}

}  // namespace
}  // namespace podium::tasks::sprint
