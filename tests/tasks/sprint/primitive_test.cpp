// The sport primitive (tasks/sprint/primitive.h): the stride cut on scripted signals, the
// resampling, the Gaussian KL against its closed form, and Φ1 on ../shared/data's runs — their
// strides score higher than a walk's, and Φ2's posterior changes as it trains on other strides.
#include "primitive.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>
#include <vector>

#include "podium/base/error.h"
#include "podium/sim/model.h"
#include "shared_data.h"

namespace podium::tasks::sprint {
namespace {

namespace fs = std::filesystem;

// A gait signal: s = A sin(2π t / T) sampled at 30 Hz; every maximum (t = T/4 + nT) is a cut, known
// once s falls below −h, and jitter of ±0.05 rad within the excursion adds none.
TEST(StrideCutter, CutsOncePerCycleAtItsMaximumWhateverTheJitter) {
  for (const double jitter : {0.0, 0.05}) {
    StrideCutter cutter(0.1);
    std::vector<std::int64_t> cuts;
    const double period = 0.7, dt = 1.0 / 30.0;
    for (std::int64_t i = 0; i < 90; ++i) {
      const double t = static_cast<double>(i) * dt;
      const double s = 0.8 * std::sin(2.0 * std::numbers::pi * t / period) + jitter * ((i % 2 == 0) ? 1.0 : -1.0);
      if (auto c = cutter.observe(i, s)) cuts.push_back(*c);
    }
    ASSERT_EQ(cuts.size(), 4u) << jitter;  // maxima at 0.175, 0.875, 1.575, 2.275 s; 2.975 s is not confirmed by 3 s
    for (std::size_t n = 0; n < cuts.size(); ++n)
      EXPECT_NEAR(static_cast<double>(cuts[n]) * dt, period / 4 + static_cast<double>(n) * period, 1.5 * dt) << jitter;
  }
}

TEST(StrideCutter, ASignalThatNeverSwingsBackMakesNoCut) {
  StrideCutter cutter(0.1);
  for (std::int64_t i = 0; i < 50; ++i) EXPECT_FALSE(cutter.observe(i, 0.5 + 0.01 * static_cast<double>(i % 3)));
}

TEST(Stride, ResamplingKeepsTheEndsAndInterpolatesLinearly) {
  const std::vector<std::vector<double>> frames = {{0.0, 1.0}, {1.0, 1.0}, {2.0, 0.0}};
  const std::vector<double> k5 = resample_stride(frames, 5);
  EXPECT_EQ(k5, (std::vector<double>{0.0, 1.0, 0.5, 1.0, 1.0, 1.0, 1.5, 0.5, 2.0, 0.0}));
  EXPECT_THROW(resample_stride(std::vector<std::vector<double>>{{1.0}}, 5), base::UserError);
}

// The recorder hands out a stride (K frames of F values) at each confirmed maximum after the
// first, of the frames from one maximum to the next.
TEST(Stride, TheRecorderCutsFromMaximumToMaximum) {
  PrimitiveSettings s;
  s.frames = 3;
  s.min_stride_s = 0.1;
  StrideRecorder recorder(s, 1.0 / 30.0);
  std::vector<std::vector<double>> strides;
  for (int i = 0; i < 70; ++i) {
    const double signal = std::sin(2.0 * std::numbers::pi * i / 21.0);  // period 21 frames, maxima at i ≈ 5.25 + 21n
    if (auto stride = recorder.observe({static_cast<double>(i)}, signal)) strides.push_back(*stride);
  }
  ASSERT_EQ(strides.size(), 2u);
  EXPECT_EQ(strides[0], (std::vector<double>{5.0, 15.5, 26.0}));  // the frame index is the value
  EXPECT_EQ(strides[1], (std::vector<double>{26.0, 36.5, 47.0}));
}

// KL(N(m, diag s²) ‖ N(μ, Σ)): zero against itself, and the closed form in one dimension.
TEST(Primitive, GaussianKlMatchesItsClosedForm) {
  const Eigen::Vector2d m(0.3, -0.2), s(0.5, 2.0);
  EXPECT_NEAR(gaussian_kl(m, s, m, Eigen::Vector2d(0.25, 4.0).asDiagonal()), 0.0, 1e-12);
  const double ms = 0.4, ss = 0.3, mu = 1.0, sd = 0.8;
  const double expected = std::log(sd / ss) + (ss * ss + (ms - mu) * (ms - mu)) / (2 * sd * sd) - 0.5;
  EXPECT_NEAR(gaussian_kl(Eigen::VectorXd::Constant(1, ms), Eigen::VectorXd::Constant(1, ss), Eigen::VectorXd::Constant(1, mu),
                          Eigen::MatrixXd::Constant(1, 1, sd * sd)),
              expected, 1e-12);
}

// ../shared/data's 3–4 m/s runs (the list), or empty when absent.
std::vector<std::string> run_clips(fs::path& data) {
  data = podium::testing::shared_data();
  if (data.empty()) return {};
  const fs::path vae = data / "jump/data/vae/txt";
  std::vector<std::string> clips;
  for (const char* c : {"cmu01-09/09/09_02", "cmu01-09/09/09_04", "cmu01-09/09/09_06", "cmu01-09/09/09_07", "cmu15-19/16/16_48",
                        "cmu15-19/16/16_49", "cmu113-128/127/127_06", "cmu113-128/127/127_07", "cmu113-128/127/127_08",
                        "cmu113-128/127/127_09", "cmu113-128/127/127_10", "cmu113-128/127/127_15", "cmu113-128/127/127_38"})
    if (fs::is_regular_file(vae / (std::string(c) + ".txt"))) clips.push_back((vae / (std::string(c) + ".txt")).string());
  const fs::path run = data / "deepmimic/data/motions/humanoid3d_run.txt";
  if (fs::is_regular_file(run)) clips.push_back(run.string());
  return clips;
}

// Φ1 pretrained on the runs: a run stride scores higher than a walk stride (DeepMimic's walk,
// never seen), and Φ2, trained online on walk strides, gives them another KL (printed).
TEST(Primitive, RunStridesScoreAboveAWalksAndPhi2LearnsOnline) {
  fs::path data;
  PrimitiveSettings s;
  s.clips = run_clips(data);
  const fs::path walk = data / "deepmimic/data/motions/humanoid3d_walk.txt";
  if (s.clips.size() < 5 || !fs::is_regular_file(walk)) GTEST_SKIP() << "../shared/data's runs absent (PODIUM_SHARED_DIR)";
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  const learn::PoseDataset strides = strides_from_clips(model, 30.0, s);
  std::printf("%zu run strides of %zu values from %zu clips\n", strides.size(), strides.dof_names.size(), s.clips.size());
  ASSERT_GE(strides.size(), 10u);
  const SportPrimitive primitive(strides, s, 7);
  std::printf("primitive: %s\n", primitive.summary().dump().c_str());
  PrimitiveSettings w = s;
  w.clips = {walk.string()};
  const learn::PoseDataset walks = strides_from_clips(model, 30.0, w);
  ASSERT_GE(walks.size(), 1u);
  std::vector<double> run_rewards, walk_rewards;
  for (std::size_t i = 4; i < strides.size(); i += 5) run_rewards.push_back(primitive.reward(strides.poses[i]));  // held out
  for (const auto& stride : walks.poses) walk_rewards.push_back(primitive.reward(stride));
  double run_mean = 0.0, walk_mean = 0.0;
  for (const double r : run_rewards) run_mean += r / static_cast<double>(run_rewards.size());
  for (const double r : walk_rewards) walk_mean += r / static_cast<double>(walk_rewards.size());
  std::printf("r_primitive: held-out run strides %.3f (%zu), walk strides %.3f (%zu)\n", run_mean, run_rewards.size(), walk_mean,
              walk_rewards.size());
  EXPECT_GT(run_mean, walk_mean);

  SportPrimitive online(strides, s, 7);
  const double before = online.kl(walks.poses.front());
  for (int i = 0; i < 20; ++i) online.adapt(walks.poses);
  const double after = online.kl(walks.poses.front());
  std::printf("walk stride KL under Φ2: %.2f before, %.2f after 20 online epochs\n", before, after);
  EXPECT_NE(before, after);

  // A resumed stage: Φ1 and the reference remade from the seed are the same, Φ2 comes back from
  // its file, and the KL is the same to the bit.
  SportPrimitive resumed(strides, s, 7);
  EXPECT_EQ(resumed.reference_mean(), online.reference_mean());
  EXPECT_EQ(resumed.reference_covariance(), online.reference_covariance());
  const fs::path file = fs::temp_directory_path() / "podium-primitive-test-phi2.pt";
  online.save_online(file);
  resumed.load_online(file);
  fs::remove(file);
  EXPECT_EQ(resumed.kl(walks.poses.front()), after);
}

}  // namespace
}  // namespace podium::tasks::sprint
