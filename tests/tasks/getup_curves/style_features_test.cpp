// The style features (curve get-up seed §3.3, §4.2) on humanoid34 poses made by turning the
// standing pose: upright, on the back, on the front, on the right side.
#include "style_features.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <numbers>

#include "podium/base/error.h"
#include "podium/character/frames.h"
#include "podium/sim/model.h"

namespace podium::tasks::getup_curves {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

class StyleFeaturesTest : public ::testing::Test {
 protected:
  sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  sim::CharacterData scratch{*model};
  StyleFeatureReader read{*model};

  // The standing pose turned by `turn` about the root and lifted to `root_z`.
  Eigen::VectorXd turned(const Eigen::Quaterniond& turn, double root_z) const {
    Eigen::VectorXd q = model->standing_pose();
    character::set_quat(q, 3, turn * character::quat_at(q, 3));
    q(2) = root_z;
    return q;
  }
};

TEST_F(StyleFeaturesTest, StandingGivesNeckHeightAndLevelTorsoVectors) {
  const Eigen::VectorXd& standing = model->standing_pose();
  // The neck's height from the model file: root height plus the chest's and the neck's anchors
  // (the standing pose keeps both joints at identity).
  const sim::Link& chest = model->link("chest");
  const sim::Link& neck = model->link("neck");
  ASSERT_TRUE(character::quat_at(standing, chest.q_index).isApprox(Eigen::Quaterniond::Identity()));
  ASSERT_TRUE(character::quat_at(standing, neck.q_index).isApprox(Eigen::Quaterniond::Identity()));
  const double neck_z = standing(2) + chest.joint_pos.z() + neck.joint_pos.z();
  const StyleFeatures w = read.at(standing, scratch);
  EXPECT_NEAR(w(0), neck_z, 1e-12);
  EXPECT_NEAR(w(1), kPi / 2, 1e-12);
  EXPECT_NEAR(w(2), kPi / 2, 1e-12);
  // Heights are to the ground given (the mean terrain height under the height map).
  EXPECT_NEAR(read.at(standing, scratch, 0.25)(0), neck_z - 0.25, 1e-12);
  std::printf("humanoid34 standing: h = %.4f m\n", w(0));
}

TEST_F(StyleFeaturesTest, LyingOnTheBackFrontAndRightSide) {
  // Forward is +x and right is −y: a quarter turn about y tips the body onto its back (front up)
  // or its front, a quarter turn about x rolls it onto its right side.
  const StyleFeatures supine =
      read.at(turned(Eigen::Quaterniond(Eigen::AngleAxisd(-kPi / 2, Eigen::Vector3d::UnitY())), 0.15), scratch);
  const StyleFeatures prone =
      read.at(turned(Eigen::Quaterniond(Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY())), 0.15), scratch);
  const StyleFeatures right =
      read.at(turned(Eigen::Quaterniond(Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitX())), 0.15), scratch);
  const StyleFeatures left =
      read.at(turned(Eigen::Quaterniond(Eigen::AngleAxisd(-kPi / 2, Eigen::Vector3d::UnitX())), 0.15), scratch);
  EXPECT_NEAR(supine(2), 0.0, 1e-6);
  EXPECT_NEAR(supine(1), kPi / 2, 1e-9);
  EXPECT_NEAR(prone(2), kPi, 1e-6);
  EXPECT_NEAR(prone(1), kPi / 2, 1e-9);
  EXPECT_NEAR(right(1), kPi, 1e-6);
  EXPECT_NEAR(right(2), kPi / 2, 1e-9);
  EXPECT_NEAR(left(1), 0.0, 1e-6);
  // Lying, the neck base is at the root's height.
  EXPECT_NEAR(supine(0), 0.15, 1e-12);
  EXPECT_NEAR(prone(0), 0.15, 1e-12);
}

TEST_F(StyleFeaturesTest, SittingUpTurnsTheFrontVectorAndTurningAboutUpChangesNothing) {
  for (double pitch_deg : {-90.0, -60.0, -30.0, 0.0, 45.0}) {
    const Eigen::Quaterniond pitch(Eigen::AngleAxisd(pitch_deg * kDeg, Eigen::Vector3d::UnitY()));
    const StyleFeatures w = read.at(turned(pitch, 0.5), scratch);
    EXPECT_NEAR(w(2), (90.0 + pitch_deg) * kDeg, 1e-9) << pitch_deg;
    for (double yaw : {0.7, 2.0, -2.9}) {
      const StyleFeatures y = read.at(turned(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * pitch, 0.5), scratch);
      EXPECT_LT((y - w).cwiseAbs().maxCoeff(), 1e-9) << pitch_deg << " " << yaw;
    }
  }
  // Bending the chest forward moves the front vector (upper torso) but not the side vector (hips).
  Eigen::VectorXd q = model->standing_pose();
  character::set_quat(q, model->link("chest").q_index, Eigen::Quaterniond(Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitY())));
  const StyleFeatures bent = read.at(q, scratch);
  EXPECT_NEAR(bent(1), kPi / 2, 1e-12);
  EXPECT_GT(bent(2), kPi / 2 + 0.1);
}

TEST(StyleFeatures, AModelWithoutTheJointsIsRefusedByName) {
  try {
    StyleFeatureReader read(*sim::make_chain(3));
    FAIL() << "expected UserError";
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find("neck"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace podium::tasks::getup_curves
