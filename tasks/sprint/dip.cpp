// The Dip Finish (sprint seed §3.3): the dip on top of the frozen stage-2 policy and its episodes
// from the snapshots before the line.
#include "dip.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <numbers>
#include <stdexcept>

#include "podium/base/error.h"
#include "podium/base/rng.h"
#include "podium/character/frames.h"
#include "podium/character/pose_bridge.h"

namespace podium::tasks::sprint {

using base::Json;

namespace {

// The pose entry of ball joint `joint`'s first exponential-map value, checking it hangs from the root.
std::size_t ball_entry(const sim::CharacterModel& model, const character::PoseBridge& bridge, const std::string& joint) {
  const std::vector<std::string>& names = bridge.dof_names();
  const auto at = std::find(names.begin(), names.end(), joint + "_x");
  const int link = model.find_link(joint);
  if (at == names.end() || link < 0 || model.links()[static_cast<std::size_t>(link)].parent != 0)
    throw base::UserError("sprint dip: model " + model.name() + " has no ball joint " + joint + " on its root body");
  return static_cast<std::size_t>(at - names.begin());
}

// §3.3's tilt in the parent's (the pelvis's) frame: hip flexion turns the thigh forward, about −y
// (x forward, y left, z up); the chest pitches forward about +y.
void turn(std::span<double> action, std::size_t entry, const Eigen::Quaterniond& by) {
  const Eigen::Vector3d e(action[entry], action[entry + 1], action[entry + 2]);
  const Eigen::Vector3d turned = character::log_map(by * character::exp_map(e));
  for (int i = 0; i < 3; ++i) action[entry + static_cast<std::size_t>(i)] = turned[i];
}

}  // namespace

DipActions::DipActions(const sim::ModelPtr& model, bool chest) {
  const character::PoseBridge bridge(model);
  for (const char* hip : {"left_hip", "right_hip"}) hips_.push_back(ball_entry(*model, bridge, hip));
  if (chest) chest_.push_back(ball_entry(*model, bridge, "chest"));
}

void DipActions::apply(double angle_rad, std::span<double> action) const {
  if (angle_rad == 0.0) return;
  const Eigen::Quaterniond flexion(Eigen::AngleAxisd(angle_rad, -Eigen::Vector3d::UnitY()));
  const Eigen::Quaterniond pitch(Eigen::AngleAxisd(angle_rad, Eigen::Vector3d::UnitY()));
  for (const std::size_t hip : hips_) turn(action, hip, flexion);
  for (const std::size_t chest : chest_) turn(action, chest, pitch);
}

Json DipEpisode::to_json() const {
  return {{"outcome", outcome},
          {"finished", finished},
          {"start_time_s", start_time_s},
          {"finish_time_s", finished ? Json(finish_time_s) : Json(nullptr)},
          {"time_s", time_s},
          {"fired_step", fired_step},
          {"fired_distance_m", fired_step >= 0 ? Json(fired_distance_m) : Json(nullptr)},
          {"control_steps", control_steps},
          {"draw", draw.to_json()}};
}

DipTrigger::DipTrigger(const DipParams& dip, const DipActions& actions, double length_m)
    : dip_(dip), actions_(&actions), length_m_(length_m), angle_rad_(dip.angle_deg * std::numbers::pi / 180.0) {}

void DipTrigger::apply(int step, double root_x_m, std::span<double> action) {
  const double distance = length_m_ - root_x_m;
  if (fired_step_ < 0 && distance <= dip_.distance_m) fired_step_ = step, fired_distance_m_ = distance, fired_x_m_ = root_x_m;
  if (fired_step_ >= 0) actions_->apply(angle_rad_, action);
}

DipEpisode run_dip_episode(SprintEnv& env, std::uint64_t seed, const character::PolicyFn& policy, const DipActions& actions,
                           const std::optional<DipParams>& dip, double fall_penalty_s, const DipStepFn& each_step) {
  env.seed(seed);
  std::vector<double> observation, action(env.action_space().size());
  env.reset(observation);
  DipEpisode e;
  e.draw = env.draw();
  e.start_time_s = env.world().time_s();
  if (each_step) each_step(-1, env, {});
  std::optional<DipTrigger> trigger;
  if (dip) trigger.emplace(*dip, actions, env.settings().preset.track.length_m);
  learn::StepResult r;
  for (int k = 0;; ++k) {
    policy(observation, action);
    if (trigger) trigger->apply(k, env.world().data().q(0), action);
    env.step(action, r);
    std::swap(observation, r.observation);
    if (each_step) each_step(k, env, action);
    if (r.terminated || r.truncated) break;
  }
  if (trigger && trigger->fired_step() >= 0)
    e.fired_step = trigger->fired_step(), e.fired_distance_m = trigger->fired_distance_m();
  e.control_steps = env.step_index();
  e.outcome = to_string(env.outcome());
  e.finished = env.outcome() == SprintEnv::Outcome::finished;
  e.finish_time_s = e.finished ? *env.finish_line().finish_time() : 0.0;
  e.time_s = e.finished ? e.finish_time_s - e.start_time_s : fall_penalty_s;
  return e;
}

DipSummary DipSummary::of(const std::vector<DipEpisode>& episodes) {
  DipSummary s;
  if (episodes.empty()) return s;
  int finished = 0, fired = 0;
  for (const DipEpisode& e : episodes) {
    s.mean_time_s += e.time_s;
    if (e.finished) ++finished, s.mean_finish_time_s += e.finish_time_s;
    if (e.fired_step >= 0) ++fired;
  }
  const auto n = static_cast<double>(episodes.size());
  s.mean_time_s /= n;
  s.finish_rate = finished / n;
  s.fired_rate = fired / n;
  if (finished > 0) s.mean_finish_time_s /= finished;
  return s;
}

Json DipSummary::to_json() const {
  return {{"mean_time_s", mean_time_s},
          {"finish_rate", finish_rate},
          {"mean_finish_time_s", mean_finish_time_s},
          {"fired_rate", fired_rate}};
}

void read_dip_settings(base::ConfigReader& r, DipSettings& s) {
  s.episodes = r.integer<int>("dip_episodes", s.episodes, {1, 100'000},
                              "dip: the snapshots (the first ones of stage 2's) each candidate runs from, one episode each");
  s.chest = r.boolean("dip_chest", s.chest, "dip: also pitch the chest forward by θ_dip (besides both hips' flexion)");
}

DipEvaluator::DipEvaluator(const DipSettings& settings, const std::vector<Json>& snapshots) : s_(settings) {
  if (snapshots.empty()) throw base::UserError("sprint dip: no snapshots to start from");
  if (s_.episodes < 1) throw base::UserError("sprint dip: episodes " + std::to_string(s_.episodes) + " is not ≥ 1");
  SprintEnvSettings e;
  e.preset = load_sprint_preset(s_.track);
  e.sim_hz = s_.sim_hz;
  penalty_s_ = e.preset.dip.fall_penalty_s;
  const std::size_t n = std::min(snapshots.size(), static_cast<std::size_t>(s_.episodes));
  for (std::size_t i = 0; i < n; ++i) {
    e.handover_states = {snapshots[i]};
    envs_.push_back(std::make_unique<SprintEnv>(e));
  }
  actions_ = std::make_unique<DipActions>(envs_.front()->world().model_ptr(), s_.chest);
}

std::vector<DipEpisode> DipEvaluator::run(const character::PolicyFn& policy, const std::optional<DipParams>& dip,
                                          const std::atomic<bool>* cancel) {
  std::vector<DipEpisode> out;
  for (std::size_t i = 0; i < envs_.size(); ++i) {
    if (cancel && cancel->load()) throw std::runtime_error("sprint dip: cancelled");
    out.push_back(run_dip_episode(*envs_[i], base::derive_seed(s_.seed, i), policy, *actions_, dip, penalty_s_));
  }
  return out;
}

}  // namespace podium::tasks::sprint
