// The sprint environment's Start mode (sprint seed §3.1) on humanoid34 with our crouch starts:
// each episode starts in the first frame of a reference drawn from the set, on its blocks; r_I is
// 1 on the reference; the phase ends at the first counted landing, whose hand-over state, saved
// and reloaded into a stage-2 environment, continues bitwise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "crouch_start.h"
#include "podium/base/error.h"
#include "podium/character/pose_bridge.h"
#include "podium/sim/dynamics.h"
#include "shared_data.h"
#include "sprint_env.h"
#include "train_start.h"
#include "user_start.h"

namespace podium::tasks::sprint {
namespace {

SprintEnvSettings start_settings() {
  SprintEnvSettings s;
  s.preset = load_sprint_preset("smoke");
  s.start_references = crouch_start_references(sim::load_shipped_model(s.model), s.control_hz, s.preset.start);
  return s;
}

std::size_t info(const std::string& name) {
  const std::vector<std::string> names = sprint_env_info_names(true);
  const auto at = std::find(names.begin(), names.end(), name);
  EXPECT_NE(at, names.end()) << name;
  return static_cast<std::size_t>(at - names.begin());
}

// Puts the env in frame f of its reference: pose, frame velocity and clock.
void to_frame(SprintEnv& env, std::size_t f) {
  const character::ImitationReference& ref = env.imitation();
  const double t = ref.clip().times_s[f];
  env.world().set_state(ref.pose(t), ref.velocity(t));
  env.set_reference_time(t);
  std::vector<double> observation;
  env.observe(observation);
}

TEST(SprintStartEnv, EachEpisodeStartsInTheFirstFrameOfAReferenceDrawnFromTheSetOnItsBlocks) {
  const SprintEnvSettings settings = start_settings();
  ASSERT_EQ(settings.start_references.size(), 4u);
  SprintEnv env(settings);
  env.seed(3);
  EXPECT_EQ(env.observation_space().size(), 236u + 1u + 4u);  // the phase and the one-hot before z
  std::set<int> drawn;
  std::vector<double> observation;
  for (int episode = 0; episode < 24; ++episode) {
    env.reset(observation);
    const int r = env.reference_index();
    drawn.insert(r);
    const StartReference& ref = settings.start_references[static_cast<std::size_t>(r)];
    EXPECT_LT((env.world().data().q - ref.clip->poses.front()).cwiseAbs().maxCoeff(), 1e-12);  // up to round-off
    EXPECT_EQ(env.reference_time_s(), 0.0);
    // The props are this reference's blocks, and each foot is on its own.
    EXPECT_EQ(env.world().config().terrain.boxes[0].center.y(), ref.blocks[0].y_m);
    const std::string front = ref.blocks[0].y_m > 0 ? "left_foot" : "right_foot";
    const std::string rear = ref.blocks[0].y_m > 0 ? "right_foot" : "left_foot";
    EXPECT_NEAR(env.world().prop_distance(env.model().find_body(front), 0), 0.0, 0.005);
    EXPECT_NEAR(env.world().prop_distance(env.model().find_body(rear), 1), 0.0, 0.005);
    const std::size_t phase = observation.size() - 6;
    EXPECT_EQ(observation[phase], 0.0);
    for (int k = 0; k < 4; ++k) EXPECT_EQ(observation[phase + 1 + static_cast<std::size_t>(k)], k == r ? 1.0 : 0.0);
  }
  EXPECT_EQ(drawn.size(), 4u);
}

TEST(SprintStartEnv, TheImitationTermIsOneOnTheReferenceAndLessOffIt) {
  SprintEnv env(start_settings());
  std::vector<double> observation;
  env.reset(observation);
  EXPECT_NEAR(env.imitation_terms().total, 1.0, 1e-12);  // the first frame, as the episode starts
  const std::size_t frames = env.imitation().clip().size();
  for (const std::size_t f : {frames / 3, frames / 2, frames - 2}) {
    to_frame(env, f);
    const character::ImitationTerms terms = env.imitation_terms();
    EXPECT_NEAR(terms.total, 1.0, 1e-12) << "frame " << f;
    EXPECT_NEAR(terms.pose, 1.0, 1e-12) << "frame " << f;
  }
  // Off the reference: the pose of another frame at this frame's clock.
  const double t = env.reference_time_s();
  env.world().set_state(env.imitation().pose(0.0), env.imitation().velocity(t));
  env.observe(observation);
  EXPECT_LT(env.imitation_terms().pose, 0.5);
  EXPECT_LT(env.imitation_terms().total, 0.8);
}

// A scripted rollout: from a few frames before the landing, at the reference's state, the
// reference's poses as SPD targets until the episode ends.
struct Landing {
  int steps = 0;
  std::vector<std::vector<double>> infos;
  bool terminated = false, truncated = false;  // how the last step ended the episode
};
Landing land(SprintEnv& env) {
  std::vector<double> observation;
  env.reset(observation);
  const character::Clip& clip = env.imitation().clip();
  std::size_t f = clip.size() - 4;
  to_frame(env, f);
  const character::PoseBridge bridge(env.world().model_ptr());
  Landing out;
  learn::StepResult step;
  do {
    const std::vector<double> target = bridge.pose(clip.poses[std::min(++f, clip.size() - 1)]);
    env.step(target, step);
    out.infos.push_back(step.info);
    ++out.steps;
  } while (!step.terminated && !step.truncated && out.steps < 30);
  out.terminated = step.terminated, out.truncated = step.truncated;
  return out;
}

TEST(SprintStartEnv, ThePhaseEndsAtTheFirstCountedLandingOnTheGround) {
  SprintEnv env(start_settings());
  env.seed(5);
  for (int episode = 0; episode < 4; ++episode) {
    const Landing run = land(env);
    SCOPED_TRACE("reference " + std::to_string(env.reference_index()));
    ASSERT_EQ(env.outcome(), SprintEnv::Outcome::landed);
    // A hand-over, not a terminal state: PPO bootstraps there, so landing costs the policy nothing.
    EXPECT_TRUE(run.truncated);
    EXPECT_FALSE(run.terminated);
    for (std::size_t k = 0; k < run.infos.size(); ++k) {
      const bool last = k + 1 == run.infos.size();
      EXPECT_EQ(run.infos[k][info("landed")], last ? 1.0 : 0.0) << k;
      EXPECT_EQ(run.infos[k][info("steps")], last ? 1.0 : 0.0) << k;  // the first counted touchdown ends it
      EXPECT_GT(run.infos[k][info("imitation")], 0.0) << k;
      EXPECT_EQ(run.infos[k][info("reference")], env.reference_index());
    }
    // The landing foot is the reference's: the rear-block foot, on the ground ahead of the line.
    const StartReference& ref = env.settings().start_references[static_cast<std::size_t>(env.reference_index())];
    const Foot landing_foot = ref.blocks[0].y_m > 0 ? Foot::right : Foot::left;
    EXPECT_EQ(env.step_counter().last_foot(), landing_foot);
    const int foot = landing_foot == Foot::left ? env.bodies().left_foot : env.bodies().right_foot;
    EXPECT_TRUE(env.features().touches(foot, sim::Contact::Partner::ground));
    EXPECT_GT(env.world().body_centroid(foot).x(), 0.0);
    ASSERT_TRUE(env.landing_state().has_value());
    EXPECT_EQ(env.landing_state()->at("draw"), env.draw().to_json());
    EXPECT_EQ(env.episode_record().at("reference"), ref.name);
  }
}

// The Start with deviation never ending an episode: holding the set position is far off the
// reference, and these tests are about steps and the reference's end.
SprintEnvSettings held_set_settings() {
  SprintEnvSettings s = start_settings();
  s.preset.start.max_com_deviation_m = 1e3;
  return s;
}

// The set position (the drawn reference's first frame) as SPD targets.
std::vector<double> set_position_targets(const SprintEnv& env) {
  return character::PoseBridge(env.world().model_ptr()).pose(env.imitation().clip().poses.front());
}

// A step is a touchdown on the track past the start line. Held in the set position (the first
// frame's pose as targets, from rest) the feet slide off their blocks and touch the track with
// their toes within a few control steps; that is no step (before, it was counted: the Start
// "landed" in the blocks, or its hands, still on the track, made it a fall).
TEST(SprintStartEnv, FeetSlidingOffTheirBlocksTakeNoStep) {
  for (std::uint64_t seed : {6u, 7u, 8u, 9u}) {
    SprintEnv env(held_set_settings());
    env.seed(seed);
    std::vector<double> observation;
    env.reset(observation);
    const character::ImitationReference& ref = env.imitation();
    env.world().set_state(ref.pose(0.0), Eigen::VectorXd::Zero(env.model().nv()));
    env.observe(observation);
    const std::vector<double> hold = set_position_targets(env);
    learn::StepResult step;
    bool toe_on_track = false;
    for (int k = 0; k < 8; ++k) {
      env.step(hold, step);
      for (const sim::Contact& c : env.features().contacts)
        toe_on_track |=
            c.partner == sim::Contact::Partner::ground && (c.body == env.bodies().left_foot || c.body == env.bodies().right_foot);
    }
    SCOPED_TRACE("reference " + std::to_string(env.reference_index()));
    EXPECT_TRUE(toe_on_track);  // the case this is about
    EXPECT_EQ(env.step_counter().steps(), 0);
    EXPECT_EQ(env.outcome(), SprintEnv::Outcome::running) << to_string(env.outcome());
  }
}

// A Start that has not landed when its reference is over (plus extra_time_s) has failed: a
// terminal state, worth nothing, so that not landing cannot pay more than landing.
TEST(SprintStartEnv, AStartNotLandedWhenItsReferenceIsOverHasFailed) {
  const SprintEnvSettings settings = held_set_settings();
  SprintEnv env(settings);
  env.seed(6);
  std::vector<double> observation;
  env.reset(observation);
  const character::Clip& clip = env.imitation().clip();
  const double end_s = clip.duration_s() + settings.preset.start.extra_time_s;
  env.set_reference_time(end_s - 1.5 * env.control_dt_s());
  const std::vector<double> hold = set_position_targets(env);
  learn::StepResult step;
  env.step(hold, step);  // still inside the reference's time: running
  EXPECT_EQ(env.outcome(), SprintEnv::Outcome::running) << to_string(env.outcome());
  EXPECT_FALSE(step.terminated || step.truncated);
  env.step(hold, step);  // past it, unlanded
  EXPECT_EQ(env.outcome(), SprintEnv::Outcome::no_landing) << to_string(env.outcome());
  EXPECT_TRUE(step.terminated);
  EXPECT_FALSE(step.truncated);
  EXPECT_GE(env.reference_time_s(), end_s - 1e-9);
  EXPECT_FALSE(env.landing_state().has_value());
}

TEST(SprintStartEnv, ALandingStateSavedAndReloadedContinuesBitwiseInTheStageTwoEnvironment) {
  SprintEnv start(start_settings());
  start.seed(11);
  land(start);
  ASSERT_EQ(start.outcome(), SprintEnv::Outcome::landed);
  const base::Json landing = *start.landing_state();
  const std::string file = (std::filesystem::temp_directory_path() / "podium_sprint_landings.json").string();
  save_handover_states(file, {landing, landing});
  SprintEnvSettings next;
  next.preset = load_sprint_preset("smoke");
  next.handover_states = load_handover_states(file);
  std::filesystem::remove(file);
  ASSERT_EQ(next.handover_states.size(), 2u);
  SprintEnv stage2(next);
  stage2.seed(1);
  std::vector<double> observation;
  stage2.reset(observation);
  EXPECT_EQ(stage2.draw().to_json(), start.draw().to_json());
  EXPECT_EQ(stage2.step_counter().steps(), 1);
  EXPECT_EQ(stage2.world().data().q, start.world().data().q);
  const Eigen::VectorXd at_landing = start.world().data().q;
  base::Rng rng(7);
  learn::StepResult a, b;
  for (int k = 0; k < 10; ++k) {
    std::vector<double> action(start.action_space().size());
    for (double& v : action) v = rng.uniform(-0.3, 0.3);
    start.step(action, a);
    stage2.step(action, b);
    ASSERT_EQ(start.world().data().q, stage2.world().data().q) << "step " << k;
    ASSERT_EQ(start.world().data().qd, stage2.world().data().qd) << "step " << k;
  }
  EXPECT_GT((start.world().data().q - at_landing).norm(), 1e-2);  // and it moved
}

TEST(SprintStartEnv, ACheckpointMidStartContinuesBitwiseWithItsReference) {
  const SprintEnvSettings settings = start_settings();
  SprintEnv a(settings), b(settings);
  a.seed(21);
  b.seed(99);
  std::vector<double> observation;
  a.reset(observation);
  b.reset(observation);
  learn::StepResult sa, sb;
  const std::vector<double> rest(a.action_space().size(), 0.0);
  for (int k = 0; k < 3; ++k) a.step(rest, sa);
  b.load_state(base::Json::parse(a.save_state()->dump()));
  EXPECT_EQ(b.reference_index(), a.reference_index());
  for (int k = 0; k < 5; ++k) {
    a.step(rest, sa);
    b.step(rest, sb);
    ASSERT_EQ(sa.reward, sb.reward) << k;
    ASSERT_EQ(sa.info, sb.info) << k;
  }
}

}  // namespace
}  // namespace podium::tasks::sprint

namespace podium::tasks::sprint {
namespace {

// DeepMimic's run (../shared/data), or empty when PODIUM_SHARED_DIR is unset or the file absent.
std::filesystem::path deepmimic_run() { return podium::testing::shared_data("deepmimic/data/motions/humanoid3d_run.txt"); }

double lowest_over(const character::Clip& clip) {
  double low = 1e300;
  for (const Eigen::VectorXd& q : clip.poses) {
    sim::CharacterData d(*clip.model);
    d.q = q;
    sim::forward_kinematics(*clip.model, d);
    low = std::min(low, sim::lowest_geom_point(*clip.model, d));
  }
  return low;
}

// A user clip as a Start reference: without blocks, turned to run along +x from the start line;
// with them, as authored; on the ground at its lowest; at the control rate.
TEST(SprintUserStart, AClipRunsAlongTheTrackFromTheLineOnTheGround) {
  const std::filesystem::path run = deepmimic_run();
  if (run.empty()) GTEST_SKIP() << "../shared/data/deepmimic absent (PODIUM_SHARED_DIR): no user clip to read";
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  const StartReference r = user_start_reference(model, 30.0, {run.string(), "none"});
  EXPECT_EQ(r.name, "clip:humanoid3d_run");
  EXPECT_TRUE(r.blocks.empty());
  const character::Clip& c = *r.clip;
  ASSERT_GE(c.size(), 2u);
  for (std::size_t f = 1; f < c.size(); ++f) EXPECT_NEAR(c.times_s[f] - c.times_s[f - 1], 1.0 / 30.0, 1e-9);
  EXPECT_NEAR(c.poses.front()(0), 0.0, 1e-12);
  EXPECT_NEAR(c.poses.front()(1), 0.0, 1e-12);
  EXPECT_GT(c.poses.back()(0), 1.0);          // it runs forward
  EXPECT_NEAR(c.poses.back()(1), 0.0, 1e-9);  // along +x
  EXPECT_NEAR(lowest_over(c), 0.0, 1e-9);     // on the ground, not through it
  // With blocks: as authored (only lifted), the blocks for that front foot.
  const StartReference authored = user_start_reference(model, 30.0, {run.string(), "right"});
  const character::Clip raw = character::resample(character::read_deepmimic_clip(model, run), 1.0 / 30.0);
  EXPECT_EQ(authored.blocks.size(), 2u);
  EXPECT_LT(authored.blocks[0].y_m, 0.0);  // the right foot's block
  EXPECT_EQ(authored.clip->poses.front().head<2>(), raw.poses.front().head<2>());
  EXPECT_EQ(authored.clip->poses.front().tail(model->nq() - 3), raw.poses.front().tail(model->nq() - 3));
  EXPECT_NEAR(lowest_over(*authored.clip), 0.0, 1e-9);
  EXPECT_THROW(user_start_reference(model, 30.0, {(run.parent_path() / "no_such_clip.txt").string(), "none"}), base::UserError);
}

// In the Start mode a user clip is drawn with the crouch starts: one more reference in the
// observation's one-hot, its first frame the start, no blocks on the track.
TEST(SprintUserStart, TheStartModeDrawsItBesideTheCrouchStartsWithoutBlocks) {
  const std::filesystem::path run = deepmimic_run();
  if (run.empty()) GTEST_SKIP() << "../shared/data/deepmimic absent (PODIUM_SHARED_DIR): no user clip to read";
  SprintEnvSettings settings;
  settings.preset = load_sprint_preset("smoke");
  settings.start_references = start_references(sim::load_shipped_model(settings.model), settings.control_hz,
                                               settings.preset.start, {{run.string(), "none"}});
  ASSERT_EQ(settings.start_references.size(), 5u);
  SprintEnv env(settings);
  env.seed(5);
  EXPECT_EQ(env.observation_space().size(), 236u + 1u + 5u);
  std::vector<double> observation;
  int clip_drawn = 0, crouch_drawn = 0;
  for (int episode = 0; episode < 30; ++episode) {
    env.reset(observation);
    const StartReference& ref = settings.start_references[static_cast<std::size_t>(env.reference_index())];
    EXPECT_LT((env.world().data().q - ref.clip->poses.front()).cwiseAbs().maxCoeff(), 1e-12);
    EXPECT_EQ(env.world().config().terrain.boxes.size(), ref.blocks.size());
    (env.reference_index() == 4 ? clip_drawn : crouch_drawn)++;
  }
  EXPECT_GT(clip_drawn, 0);
  EXPECT_GT(crouch_drawn, 0);
}

}  // namespace
}  // namespace podium::tasks::sprint
