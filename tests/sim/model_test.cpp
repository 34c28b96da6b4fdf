// Model files: structure of the shipped characters and error messages for bad input.
#include "podium/sim/model.h"

#include <gtest/gtest.h>

#include "podium/base/error.h"

namespace podium::sim {
namespace {

using base::Json;

Json two_bodies(const Json& joint) {
  return Json{{"name", "t"},
              {"bodies",
               {{{"name", "a"}, {"geoms", {{{"type", "sphere"}, {"radius", 0.1}}}}},
                {{"name", "b"},
                 {"parent", "a"},
                 {"pos", {0, 0, -0.3}},
                 {"geoms", {{{"type", "sphere"}, {"radius", 0.1}}}},
                 {"joints", {joint}}}}}};
}

TEST(Model, Humanoid21HasTable2JointsAndMuJoCoLayout) {
  const ModelPtr m = load_shipped_model("humanoid21");
  EXPECT_EQ(m->links().size(), 22u);   // root + 21 hinges
  EXPECT_EQ(m->bodies().size(), 16u);  // humanoid.xml bodies
  const Link& knee = m->link("knee_right");
  EXPECT_EQ(knee.torque_limit_nm(0), 80.0);
  EXPECT_NEAR(knee.axis.y(), -1.0, 1e-12);
  EXPECT_EQ(knee.lower, -2.79);
  const Link& ankle = m->link("ankle_x_right");
  EXPECT_NEAR(ankle.axis.dot(Eigen::Vector3d(1, 0, 0.5).normalized()), 1.0, 1e-12);
  EXPECT_EQ(&knee, &m->links()[m->find_link("knee_right")]);
  try {
    m->link("knee_middle");
    ADD_FAILURE() << "a joint the model lacks was found";
  } catch (const base::UserError& e) {
    EXPECT_STREQ(e.what(), "model humanoid21 has no joint \"knee_middle\"");
  }
  // Excluded pair (humanoid.xml <contact><exclude>) and parent/child pairs do not collide.
  const auto link_of = [&](const char* body) { return m->bodies()[m->find_body(body)].link; };
  EXPECT_FALSE(m->links_collide(link_of("waist_lower"), link_of("thigh_right")));
  EXPECT_FALSE(m->links_collide(link_of("thigh_right"), link_of("shin_right")));
  EXPECT_TRUE(m->links_collide(link_of("hand_left"), link_of("foot_right")));
}

TEST(Model, ChainsHaveTheThesisDofCounts) {
  EXPECT_EQ(make_chain(11)->nv(), 36);
  EXPECT_EQ(make_chain(23)->nv(), 72);
  EXPECT_EQ(make_chain(64)->nv(), 195);
  EXPECT_EQ(make_chain(50, JointType::revolute)->nv(), 55);
}

TEST(Model, ErrorsNameThePathValueAndRule) {
  Json bad_axis = two_bodies({{"name", "j"}, {"type", "revolute"}, {"axis", {0, 0, 0}}, {"torque_limit", 10}});
  EXPECT_THROW(
      {
        try {
          CharacterModel::from_json(bad_axis, "model t.json");
        } catch (const base::UserError& e) {
          EXPECT_STREQ(e.what(), "model t.json: bodies[1].joints[0].axis: [0,0,0] is not a direction (zero length)");
          throw;
        }
      },
      base::UserError);
  Json bad_parent = two_bodies({{"name", "j"}, {"type", "spherical"}, {"torque_limit", 10}});
  bad_parent["bodies"][1]["parent"] = "nope";
  EXPECT_THROW(CharacterModel::from_json(bad_parent, "m"), base::UserError);
  Json bad_range =
      two_bodies({{"name", "j"}, {"type", "revolute"}, {"axis", {1, 0, 0}}, {"range", {1, -1}}, {"torque_limit", 10}});
  try {
    CharacterModel::from_json(bad_range, "m");
    FAIL() << "no error for an inverted range";
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("bodies[1].joints[0].range: [1,-1] is not [lower, upper]"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(load_shipped_model("humanoid99"), base::UserError);
  try {
    CharacterModel::from_json(two_bodies({{"name", "j"}, {"type", "spherical"}, {"torque_limit", 10}, {"damping", 1}}), "m");
    FAIL() << "no error for damping on a spherical joint";
  } catch (const base::UserError& e) {
    EXPECT_STREQ(e.what(), "m: bodies[1].joints[0]: damping and stiffness are for revolute joints (this one is spherical)");
  }
  EXPECT_THROW(
      CharacterModel::from_json(two_bodies({{"name", "j"}, {"type", "revolute"}, {"axis", {1, 0, 0}}, {"stiffness", -1}}), "m"),
      base::UserError);
}

// The seed repository's MuJoCo humanoid (data/humanoid_high_freq.xml): damping 0.2 and stiffness
// 1 by default, hips and abdomen 2 and 4, hip_y and abdomen_z stiffness 8, ankles 6 and 3.
TEST(Model, Humanoid21CarriesTheSeedHumanoidsPassiveJoints) {
  const ModelPtr m = load_shipped_model("humanoid21");
  EXPECT_EQ(m->link("knee_left").damping, 0.2);
  EXPECT_EQ(m->link("knee_left").stiffness, 1.0);
  EXPECT_EQ(m->link("hip_y_right").damping, 2.0);
  EXPECT_EQ(m->link("hip_y_right").stiffness, 8.0);
  EXPECT_EQ(m->link("abdomen_y").stiffness, 4.0);
  EXPECT_EQ(m->link("ankle_y_left").stiffness, 6.0);
  EXPECT_EQ(m->link("elbow_right").stiffness, 0.0);
  EXPECT_EQ(m->damping()(m->link("hip_x_left").v_index), 2.0);
  EXPECT_TRUE(m->damping().head<6>().isZero(0.0));  // the root
}

// Per-axis limits (the thesis's jumper, §3.6.2): one bound per DoF about the link's x, y, z.
TEST(Model, SphericalJointsTakePerAxisTorqueLimits) {
  const ModelPtr m =
      CharacterModel::from_json(two_bodies({{"name", "j"}, {"type", "spherical"}, {"torque_limit", {100, 300, 50}}}), "m");
  EXPECT_EQ(m->torque_limits().tail<3>(), Eigen::Vector3d(100, 300, 50));
  EXPECT_EQ(m->kp().tail<3>(), Eigen::Vector3d::Constant(300.0));  // default kp: the largest limit
  EXPECT_EQ(m->kd().tail<3>(), Eigen::Vector3d::Constant(30.0));
  auto error = [](const Json& joint) {
    try {
      CharacterModel::from_json(two_bodies(joint), "m");
    } catch (const base::UserError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_EQ(error({{"name", "j"}, {"type", "revolute"}, {"axis", {1, 0, 0}}, {"torque_limit", {1, 2, 3}}}),
            "m: bodies[1].joints[0].torque_limit: [1,2,3] is not a number > 0 (N·m; per-axis limits are for spherical joints)");
  EXPECT_EQ(
      error({{"name", "j"}, {"type", "spherical"}, {"torque_limit", {1, 2}}}),
      "m: bodies[1].joints[0].torque_limit: [1,2] is not a number > 0 or [x, y, z] of numbers > 0 (N·m about the link's axes)");
  EXPECT_EQ(
      error({{"name", "j"}, {"type", "spherical"}, {"torque_limit", {1, 0, 2}}}),
      "m: bodies[1].joints[0].torque_limit: [1,0,2] is not a number > 0 or [x, y, z] of numbers > 0 (N·m about the link's axes)");
  EXPECT_EQ(error({{"name", "j"}, {"type", "revolute"}, {"axis", {1, 0, 0}}, {"torque_limit", "strong"}}),
            "m: bodies[1].joints[0].torque_limit: \"strong\" is not a number > 0 (N·m)");
  EXPECT_EQ(error({{"name", "j"}, {"type", "spherical"}}), "m: bodies[1].joints[0].torque_limit: missing is not > 0");
}

}  // namespace
}  // namespace podium::sim
