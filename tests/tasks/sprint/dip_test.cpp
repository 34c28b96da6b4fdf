// The Dip Finish (sprint seed §3.3) on humanoid34: the dip's change to the targets (both hips'
// flexion, the chest's pitch as an option), that it fires at the first control step with the root
// within d_dip of the line, that θ_dip = 0 leaves the rollout bitwise as without a dip, that a
// restored snapshot continues the original rollout bitwise, and that a candidate's episodes use
// the same draws and seeds whatever the candidate (common random numbers).
#include "dip.h"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "podium/base/error.h"
#include "podium/base/rng.h"
#include "podium/character/pose_bridge.h"
#include "podium/sim/dynamics.h"
#include "train_accelerate.h"

namespace podium::tasks::sprint {
namespace {

using base::Json;

constexpr double kSimHz = 150.0;  // the smoke preset's rate

SprintEnvSettings smoke_with(const std::vector<Json>& starts) {
  SprintEnvSettings s;
  s.preset = load_sprint_preset("smoke");
  s.sim_hz = kSimHz;
  s.handover_states = starts;
  return s;
}

// A deterministic policy that reacts to the state: a = 0.3·tanh(W·o) with W ~ N(0, 0.05²)
// drawn once, so equal observations give equal actions and a changed state changes them.
character::PolicyFn reactive_policy(std::size_t observations, std::size_t actions, std::uint64_t seed) {
  auto w = std::make_shared<Eigen::MatrixXd>(actions, observations);
  base::Rng rng(seed);
  for (Eigen::Index i = 0; i < w->size(); ++i) w->data()[i] = 0.05 * rng.normal();
  return [w](std::span<const double> o, std::span<double> a) {
    const Eigen::VectorXd out = *w * Eigen::Map<const Eigen::VectorXd>(o.data(), static_cast<Eigen::Index>(o.size()));
    for (std::size_t i = 0; i < a.size(); ++i) a[i] = 0.3 * std::tanh(out[static_cast<Eigen::Index>(i)]);
  };
}

// The standing runner `before_m` before the line, sliding forward at `v` on a frictionless,
// windless runway, as a hand-over state: nothing horizontal acts on its COM.
Json slider_snapshot(double before_m, double v) {
  SprintEnvSettings s;
  s.preset = load_sprint_preset("smoke");
  s.sim_hz = kSimHz;
  s.fixed_draw = EpisodeDraw{0.0, 0.0};
  s.standing.x_m = s.preset.track.length_m - before_m;
  SprintEnv env(s);
  std::vector<double> observation;
  env.reset(observation);
  env.world().set_state_world(env.world().data().q, Eigen::Vector3d::Zero(), Eigen::Vector3d(v, 0.0, 0.0),
                              Eigen::VectorXd::Zero(env.model().nv() - 6));
  return env.handover_state();
}

Eigen::Vector3d link_origin(const sim::CharacterModel& model, const sim::CharacterData& d, const std::string& joint) {
  return d.links[static_cast<std::size_t>(model.find_link(joint))].p;
}

// The dip turns both thighs forward by θ about the pelvis's lateral axis (with the chest option,
// the chest forward by θ), and nothing else: checked by forward kinematics from the zero pose.
TEST(SprintDip, TurnsBothHipsInFlexionAndTheChestForwardWhenAsked) {
  const sim::ModelPtr model = sim::load_shipped_model("humanoid34");
  const character::PoseBridge bridge(model);
  const double theta = 30.0 * std::numbers::pi / 180.0;
  for (const bool chest : {false, true}) {
    SCOPED_TRACE(chest ? "chest" : "hips");
    const DipActions dip(model, chest);
    EXPECT_EQ(dip.chest(), chest);
    std::vector<double> zero(bridge.size(), 0.0), action = zero;
    dip.apply(theta, action);
    sim::CharacterData d(*model);
    d.q = bridge.target(action);
    sim::forward_kinematics(*model, d);
    for (const char* side : {"left", "right"}) {
      const Eigen::Vector3d thigh =
          (link_origin(*model, d, std::string(side) + "_knee") - link_origin(*model, d, std::string(side) + "_hip")).normalized();
      EXPECT_NEAR(thigh.x(), std::sin(theta), 1e-12) << side;  // forward
      EXPECT_NEAR(thigh.y(), 0.0, 1e-12) << side;
      EXPECT_NEAR(thigh.z(), -std::cos(theta), 1e-12) << side;
    }
    const Eigen::Vector3d up = (link_origin(*model, d, "neck") - link_origin(*model, d, "chest")).normalized();
    EXPECT_NEAR(up.x(), chest ? std::sin(theta) : 0.0, 1e-12);
    EXPECT_NEAR(up.z(), chest ? std::cos(theta) : 1.0, 1e-12);
    // Only the hips' (and the chest's) entries change.
    std::size_t changed = 0;
    for (std::size_t k = 0; k < action.size(); ++k) changed += action[k] != zero[k];
    EXPECT_EQ(changed, chest ? 3u : 2u);  // the y entry of each exponential map about the lateral axis
  }
  // θ = 0 leaves any action as it is, bitwise.
  const DipActions dip(model, true);
  std::vector<double> action(bridge.size()), before;
  base::Rng rng(3);
  for (double& v : action) v = rng.uniform(-0.5, 0.5);
  before = action;
  dip.apply(0.0, action);
  EXPECT_EQ(action, before);
  dip.apply(0.2, action);
  EXPECT_NE(action, before);
}

// Each step's root distance to the line before the step, and whether the action differs from the
// policy's there.
struct Trace {
  std::vector<double> distance;  // before step k
  std::vector<Eigen::VectorXd> q;
  std::vector<std::vector<double>> actions;
};

DipEpisode traced(SprintEnv& env, const character::PolicyFn& policy, const std::optional<DipParams>& dip, bool chest,
                  Trace& trace) {
  const DipActions actions(env.world().model_ptr(), chest);
  const double length = env.settings().preset.track.length_m;
  return run_dip_episode(env, 5, policy, actions, dip, 99.0, [&](int, const SprintEnv& e, std::span<const double> a) {
    trace.distance.push_back(length - e.world().data().q(0));
    trace.q.push_back(e.world().data().q);
    if (!a.empty()) trace.actions.emplace_back(a.begin(), a.end());
  });
}

// Sliding at 3 m/s from 3.5 m before the line: the dip fires at the first control step whose
// state has the root within d_dip of the line and changes the actions from then on only. (On a
// frictionless runway flexing the hips swings the legs forward rather than the trunk, so the
// slider says nothing of the dip's gain: the stage measures that on real runs.)
TEST(SprintDip, FiresAtTheFirstControlStepWithinDDip) {
  SprintEnv env(smoke_with({slider_snapshot(3.5, 3.0)}));
  const std::vector<double> zero(env.action_space().size(), 0.0);
  const character::PolicyFn still = [](std::span<const double>, std::span<double> a) { std::fill(a.begin(), a.end(), 0.0); };
  for (const double d : {1.0, 2.0, 3.2}) {
    SCOPED_TRACE(d);
    Trace trace;
    const DipEpisode e = traced(env, still, DipParams{d, 30.0}, false, trace);
    ASSERT_GE(e.fired_step, 1);
    const auto k = static_cast<std::size_t>(e.fired_step);
    // trace.distance[k] is the distance before step k (after step k − 1; [0] after the reset).
    EXPECT_LE(trace.distance[k], d);
    EXPECT_GT(trace.distance[k - 1], d);
    EXPECT_EQ(e.fired_distance_m, trace.distance[k]);
    for (std::size_t j = 0; j < trace.actions.size(); ++j) EXPECT_EQ(trace.actions[j] == zero, j < k) << j;
    EXPECT_EQ(e.time_s, e.finished ? e.finish_time_s - e.start_time_s : 99.0);  // a fall: the penalty
  }
  // Without a dip it never fires, and the time runs from the snapshot.
  Trace none;
  const DipEpisode e = traced(env, still, std::nullopt, false, none);
  EXPECT_EQ(e.fired_step, -1);
  ASSERT_TRUE(e.finished) << e.outcome;
  EXPECT_EQ(e.time_s, e.finish_time_s - e.start_time_s);
  Trace one;
  const DipEpisode dip = traced(env, still, DipParams{1.0, 30.0}, false, one);
  std::printf("slider from 3.5 m at 3 m/s: %.4f s to the line without a dip, %.4f s with (1 m, 30°: %s)\n", e.time_s, dip.time_s,
              dip.outcome.c_str());
  // Already within d_dip at the snapshot: it fires at once.
  Trace c;
  EXPECT_EQ(traced(env, still, DipParams{5.0, 30.0}, false, c).fired_step, 0);
}

// θ_dip = 0: the dip's path (its firing, the action passed through it) leaves the rollout as the
// policy alone gives it, bitwise, on a runner whose actions react to its state.
TEST(SprintDip, ZeroTiltEqualsNoDipBitwise) {
  const std::vector<Json> starts = fallback_starts("smoke", kSimHz, 10.0 - 4.0);  // the root 4 m before the line
  SprintEnv env(smoke_with({starts[0]}));
  const character::PolicyFn policy = reactive_policy(env.observation_space().size(), env.action_space().size(), 11);
  Trace none, zero;
  const DipEpisode a = traced(env, policy, std::nullopt, true, none);
  const DipEpisode b = traced(env, policy, DipParams{3.8, 0.0}, true, zero);
  ASSERT_GE(b.fired_step, 1);  // it fired, mid-episode
  EXPECT_EQ(none.distance, zero.distance);
  EXPECT_EQ(none.q, zero.q);
  EXPECT_EQ(none.actions, zero.actions);
  EXPECT_EQ(a.time_s, b.time_s);
  EXPECT_EQ(a.outcome, b.outcome);
  EXPECT_EQ(a.control_steps, b.control_steps);
  EXPECT_GT(a.control_steps, b.fired_step + 1);  // steps ran after the firing
  // A tilt changes the rollout from the step it fires.
  Trace tilted;
  const DipEpisode c = traced(env, policy, DipParams{3.8, 20.0}, true, tilted);
  EXPECT_EQ(c.fired_step, b.fired_step);
  const auto k = static_cast<std::size_t>(c.fired_step);
  for (std::size_t j = 0; j <= k; ++j) EXPECT_EQ(tilted.distance[j], none.distance[j]) << j;
  EXPECT_NE(tilted.actions[k], none.actions[k]);
}

// A snapshot taken mid-run and restored in another env, stepped by the same policy (so with the
// same actions while the states agree), continues the original rollout bitwise to its end.
TEST(SprintDip, RestoredSnapshotContinuesTheOriginalRolloutBitwise) {
  const std::vector<Json> starts = fallback_starts("smoke", kSimHz);
  SprintEnv original(smoke_with({starts[1]}));
  const character::PolicyFn policy = reactive_policy(original.observation_space().size(), original.action_space().size(), 4);
  original.seed(8);
  std::vector<double> observation, action(original.action_space().size());
  original.reset(observation);
  learn::StepResult r;
  for (int k = 0; k < 6; ++k) {
    policy(observation, action);
    original.step(action, r);
    observation = r.observation;
    ASSERT_FALSE(r.terminated || r.truncated);
  }
  const Json snapshot = original.handover_state();
  std::vector<std::vector<double>> expected = {observation}, actions;
  do {
    policy(observation, action);
    actions.push_back(action);
    original.step(action, r);
    observation = r.observation;
    expected.push_back(observation);
  } while (!r.terminated && !r.truncated);
  ASSERT_GT(expected.size(), 3u);

  SprintEnv restored(smoke_with({snapshot}));
  const DipActions dip(restored.world().model_ptr(), false);
  std::vector<std::vector<double>> seen, taken;  // what the policy saw before each step, what the env took
  const character::PolicyFn watched = [&](std::span<const double> o, std::span<double> a) {
    seen.emplace_back(o.begin(), o.end());
    policy(o, a);
  };
  const DipEpisode e = run_dip_episode(restored, 123, watched, dip, std::nullopt, 99.0,
                                       [&](int step, const SprintEnv&, std::span<const double> a) {
                                         if (step >= 0) taken.emplace_back(a.begin(), a.end());
                                       });
  EXPECT_EQ(taken, actions);
  ASSERT_EQ(seen.size() + 1, expected.size());
  for (std::size_t k = 0; k < seen.size(); ++k) EXPECT_EQ(seen[k], expected[k]) << k;
  EXPECT_EQ(e.outcome, to_string(original.outcome()));
  EXPECT_EQ(restored.world().time_s(), original.world().time_s());
  EXPECT_EQ(restored.world().data().q, original.world().data().q);
  EXPECT_EQ(restored.world().data().qd, original.world().data().qd);
  EXPECT_EQ(restored.finish_line().finish_time(), original.finish_line().finish_time());
}

// Common random numbers: a snapshot without a draw takes the same draw and seed for every
// candidate, so two runs of one candidate agree exactly and a dip and no dip share the draw.
TEST(SprintDip, EveryCandidateRunsTheSameEpisodes) {
  const std::vector<Json> starts = fallback_starts("smoke", kSimHz, 10.0 - 4.5);  // no draw in them
  DipSettings s;
  s.sim_hz = kSimHz;
  s.episodes = 3;
  DipEvaluator evaluator(s, starts);
  EXPECT_EQ(evaluator.size(), 3u);  // the first three of four
  EXPECT_EQ(evaluator.fall_penalty_s(), load_sprint_preset("smoke").dip.fall_penalty_s);
  SprintEnv probe(smoke_with(starts));
  const character::PolicyFn policy = reactive_policy(probe.observation_space().size(), probe.action_space().size(), 2);
  const std::vector<DipEpisode> none = evaluator.run(policy, std::nullopt), one = evaluator.run(policy, DipParams{4.0, 45.0}),
                                again = evaluator.run(policy, DipParams{4.0, 45.0});
  ASSERT_EQ(one.size(), 3u);
  for (std::size_t i = 0; i < one.size(); ++i) {
    EXPECT_EQ(one[i].to_json(), again[i].to_json()) << i;
    EXPECT_EQ(one[i].draw.to_json(), none[i].draw.to_json()) << i;
    EXPECT_EQ(one[i].start_time_s, none[i].start_time_s) << i;
    EXPECT_EQ(one[i].time_s, one[i].finished ? one[i].finish_time_s - one[i].start_time_s : evaluator.fall_penalty_s());
  }
  EXPECT_NE(one[0].draw.wind_mps, one[1].draw.wind_mps);  // each episode its own draw
  const DipSummary summary = DipSummary::of(one);
  double sum = 0.0;
  for (const DipEpisode& e : one) sum += e.time_s;
  EXPECT_EQ(summary.mean_time_s, sum / 3.0);
  EXPECT_THROW(DipEvaluator(s, {}), base::UserError);
}

// A cancelled dip trial stops at the next episode rather than running its candidate's whole set.
TEST(SprintDip, ACancelStopsTheEvaluationBetweenEpisodes) {
  const std::vector<Json> starts = fallback_starts("smoke", kSimHz, 10.0 - 4.5);
  DipSettings s;
  s.sim_hz = kSimHz;
  s.episodes = 3;
  DipEvaluator evaluator(s, starts);
  SprintEnv probe(smoke_with(starts));
  const character::PolicyFn inner = reactive_policy(probe.observation_space().size(), probe.action_space().size(), 2);
  std::atomic<bool> cancel = false;
  int calls = 0;
  const character::PolicyFn cancelling = [&](std::span<const double> o, std::span<double> a) {
    ++calls;
    cancel = true;  // asked to stop during the first episode
    inner(o, a);
  };
  EXPECT_THROW(evaluator.run(cancelling, std::nullopt, &cancel), std::runtime_error);
  const int first_episode = calls;
  calls = 0;
  cancel = false;
  const character::PolicyFn counting = [&](std::span<const double> o, std::span<double> a) { ++calls, inner(o, a); };
  ASSERT_EQ(evaluator.run(counting, std::nullopt, &cancel).size(), 3u);
  EXPECT_LT(first_episode, calls);  // the first episode only, not all three
}

}  // namespace
}  // namespace podium::tasks::sprint
