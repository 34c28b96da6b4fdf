// The clip type: retiming, resampling, velocities, mirroring, DeepMimic clips and recordings.
#include "podium/character/motion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>

#include "podium/base/error.h"
#include "podium/sim/dynamics.h"
#include "podium/sim/world.h"
#include "test_util.h"

namespace podium::character {
namespace {

using testing::config_distance;
using testing::random_q;

Clip random_clip(const sim::ModelPtr& model, int frames, double dt, std::uint64_t seed) {
  base::Rng rng(seed);
  Clip clip{model, {}, {}, false};
  for (int f = 0; f < frames; ++f) {
    clip.times_s.push_back(f * dt);
    clip.poses.push_back(random_q(*model, rng));
  }
  return clip;
}

// Get-up seed §6: τ_slow at κ has length T/κ and passes through τ_fast's states.
TEST(Motion, RetimingByKappaLastsTOverKappaAndPassesThroughTheOriginalFrames) {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  const double dt = 1.0 / 40.0;
  const Clip fast = random_clip(model, 11, dt, 3);  // T = 0.25 s
  for (double kappa : {0.5, 0.25, 0.3, 0.8}) {
    const Clip slow = retime(fast, kappa);
    EXPECT_NEAR(slow.duration_s(), fast.duration_s() / kappa, 1e-12) << kappa;
    for (std::size_t i = 0; i < fast.size(); ++i)
      EXPECT_LE(config_distance(*model, slow.sample(fast.times_s[i] / kappa), fast.poses[i]), 1e-12)
          << "κ " << kappa << " frame " << i;
    // Between two original frames it moves on, by slerp, at κ times the speed.
    const Eigen::VectorXd mid_slow = slow.sample(0.5 * (fast.times_s[2] + fast.times_s[3]) / kappa);
    EXPECT_LE(config_distance(*model, mid_slow, fast.sample(0.5 * (fast.times_s[2] + fast.times_s[3]))), 1e-12) << kappa;
    // At the control rate: T/κ / dt + 1 frames (whole control steps).
    const Clip frames = resample(slow, dt);
    EXPECT_EQ(frames.size(), static_cast<std::size_t>(std::floor(fast.duration_s() / kappa / dt + 1e-9)) + 1) << kappa;
    EXPECT_NEAR(frames.duration_s(), fast.duration_s() / kappa, dt) << kappa;
  }
  // κ = 1/4 puts every original frame on the control grid: frame i is resampled frame 4i.
  const Clip quarter = resample(retime(fast, 0.25), dt);
  ASSERT_EQ(quarter.size(), 41u);
  for (std::size_t i = 0; i < fast.size(); ++i)
    EXPECT_LE(config_distance(*model, quarter.poses[4 * i], fast.poses[i]), 1e-9) << i;
  EXPECT_THROW(retime(fast, 0.0), base::UserError);
}

// Between frames: hinges linearly, ball joints by slerp (half-way = half the relative angle).
TEST(Motion, SamplingInterpolatesHingesLinearlyAndBallsBySlerp) {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  Clip clip{model, {0.0, 0.1}, {model->neutral(), model->neutral()}, false};
  const sim::Link& knee = model->link("right_knee");
  const sim::Link& hip = model->link("right_hip");
  clip.poses[1](knee.q_index) = -1.0;
  set_quat(clip.poses[1], hip.q_index, Eigen::Quaterniond(Eigen::AngleAxisd(1.2, Eigen::Vector3d(0, 1, 1).normalized())));
  const Eigen::VectorXd mid = clip.sample(0.05);
  EXPECT_NEAR(mid(knee.q_index), -0.5, 1e-12);
  const Eigen::AngleAxisd half(quat_at(mid, hip.q_index));
  EXPECT_NEAR(half.angle(), 0.6, 1e-12);
  EXPECT_LE((half.axis() - Eigen::Vector3d(0, 1, 1).normalized()).norm(), 1e-12);
  EXPECT_EQ(clip.sample(-1.0), clip.poses[0]);  // clamped outside
  EXPECT_EQ(clip.sample(5.0), clip.poses[1]);
}

// A motion with constant rates: the finite-difference velocities are those rates exactly.
TEST(Motion, VelocitiesOfAConstantRateMotion) {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  const sim::Link& knee = model->link("left_knee");
  const sim::Link& chest = model->link("chest");
  const Eigen::Vector3d omega(0.3, -0.2, 0.5), root_omega(0.0, 0.4, 0.1), root_v(1.0, -0.5, 0.2);
  const Eigen::Quaterniond q0(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  Clip clip{model, {}, {}, false};
  for (int f = 0; f < 5; ++f) {
    const double t = 0.05 * f;
    Eigen::VectorXd q = model->neutral();
    const Eigen::Quaterniond root = q0 * exp_map(root_omega * t);
    // Root origin moving with root-frame velocity v: p(t) = ∫ R(t) v, here for a rotating root
    // only the forward difference over each step is checked, so build p from those steps.
    q.head<3>() =
        clip.poses.empty()
            ? Eigen::Vector3d(0, 0, 1)
            : Eigen::Vector3d(clip.poses.back().head<3>() + quat_at(clip.poses.back(), 3).toRotationMatrix() * root_v * 0.05);
    set_quat(q, 3, root);
    q(knee.q_index) = -0.2 - 1.5 * t;
    set_quat(q, chest.q_index, q0 * exp_map(omega * t));
    clip.times_s.push_back(t);
    clip.poses.push_back(q);
  }
  for (const Eigen::VectorXd& qd : clip.velocities()) {
    EXPECT_NEAR(qd(knee.v_index), -1.5, 1e-9);
    EXPECT_LE((qd.segment<3>(chest.v_index) - omega).norm(), 1e-9);
    EXPECT_LE((qd.head<3>() - root_omega).norm(), 1e-9);
    EXPECT_LE((qd.segment<3>(3) - root_v).norm(), 1e-9);
  }
}

// Mirroring reflects every body across the x–z plane onto its partner, and twice is identity.
TEST(Motion, MirrorReflectsBodiesOntoTheirPartners) {
  for (const char* name : {"humanoid21", "humanoid34"}) {
    const sim::ModelPtr model = sim::load_shipped_model(name);
    const Clip clip = random_clip(model, 4, 0.1, 11);
    const Clip mirrored = mirror(clip);
    const Clip back = mirror(mirrored);
    sim::CharacterData a(*model), b(*model);
    for (std::size_t f = 0; f < clip.size(); ++f) {
      EXPECT_LE(config_distance(*model, back.poses[f], clip.poses[f]), 1e-12) << name;
      a.q = clip.poses[f];
      b.q = mirrored.poses[f];
      sim::forward_kinematics(*model, a);
      sim::forward_kinematics(*model, b);
      for (std::size_t body = 0; body < model->bodies().size(); ++body) {
        std::string partner = model->bodies()[body].name;
        if (auto p = partner.find("left"); p != std::string::npos) {
          partner.replace(p, 4, "right");
        } else if (auto r = partner.find("right"); r != std::string::npos) {
          partner.replace(r, 5, "left");
        }
        const int pb = model->find_body(partner);
        ASSERT_GE(pb, 0) << partner;
        for (const Eigen::Vector3d& local : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.05, 0.0, 0.1)}) {
          const Eigen::Vector3d mirrored_local(local.x(), -local.y(), local.z());
          const Eigen::Vector3d p = sim::body_point(*model, a, static_cast<int>(body), local);
          const Eigen::Vector3d m = sim::body_point(*model, b, pb, mirrored_local);
          EXPECT_LE((m - Eigen::Vector3d(p.x(), -p.y(), p.z())).norm(), 1e-9) << name << " body " << model->bodies()[body].name;
        }
      }
    }
  }
}

TEST(Motion, ClipFromARecordingKeepsItsFrames) {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid21");
  sim::World world(model, sim::WorldConfig{});
  sim::Recorder recorder(model);
  world.reset(model->standing_pose(), Eigen::VectorXd::Zero(model->nv()));
  for (int k = 0; k < 5; ++k) {
    recorder.record(world);
    world.control_step(sim::Control::torque, Eigen::VectorXd::Zero(model->nv()));
  }
  const Clip clip = clip_from_recording(recorder, model);
  ASSERT_EQ(clip.size(), 5u);
  EXPECT_NEAR(clip.duration_s(), 4.0 / 40.0, 1e-12);
  EXPECT_EQ(clip.poses[3], recorder.frames()[3].q);
  EXPECT_THROW(clip_from_recording(recorder, sim::load_shipped_model("humanoid34")), base::UserError);
}

// Replaying a DeepMimic get-up clip kinematically: the root height follows the file (z-up =
// DeepMimic's y), and the body stays on the ground (lowest geom within a few cm of z = 0).
TEST(Motion, DeepMimicGetUpClipReproducesItsRootHeightCurve) {
  const auto dir = testing::deepmimic_dir();
  if (dir.empty() || !std::filesystem::exists(dir / "motions/humanoid3d_getup_faceup.txt"))
    GTEST_SKIP() << "../shared/data/deepmimic absent (PODIUM_SHARED_DIR)";
  const sim::ModelPtr model = sim::load_deepmimic(dir / "characters/humanoid3d.txt", dir / "controllers/humanoid3d_ctrl.txt");
  sim::CharacterData data(*model);
  for (const char* clip_name : {"humanoid3d_getup_faceup.txt", "humanoid3d_getup_facedown.txt"}) {
    const Clip clip = read_deepmimic_clip(model, dir / "motions" / clip_name);
    const base::Json raw = base::read_json_file(dir / "motions" / clip_name);
    ASSERT_GT(clip.size(), 10u);
    double worst = 0, lowest = 1e9, highest_low = -1e9, t = 0;
    for (std::size_t f = 0; f < clip.size(); ++f) {
      data.q = clip.poses[f];
      sim::forward_kinematics(*model, data);
      worst = std::max(worst, std::abs(data.links[0].p.z() - raw["Frames"][f][2].get<double>()));
      EXPECT_NEAR(clip.times_s[f], t, 1e-12);
      t += raw["Frames"][f][0].get<double>();
      const double low = sim::lowest_geom_point(*model, data);
      lowest = std::min(lowest, low);
      highest_low = std::max(highest_low, low);
    }
    std::printf("%s: %zu frames, %.2f s, root height error %.2e m, lowest geom point in [%.3f, %.3f] m\n", clip_name, clip.size(),
                clip.duration_s(), worst, lowest, highest_low);
    EXPECT_LE(worst, 1e-9);
    EXPECT_GT(lowest, -0.08);  // captured clips sink into the floor by a few centimetres at most
    EXPECT_LT(highest_low, 0.06);
  }
}

TEST(Motion, DeepMimicReaderNamesTheFileAndFrame) {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  const auto path = std::filesystem::temp_directory_path() / "podium_character_bad_clip.txt";
  std::ofstream(path) << R"({"Loop": "none", "Frames": [[0.1, 0, 0, 0]]})";
  try {
    read_deepmimic_clip(model, path);
    FAIL() << "expected UserError";
  } catch (const base::UserError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string() + ": Frames[0]: has 4 numbers but model humanoid34 needs"),
              std::string::npos)
        << e.what();
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace podium::character
