#include "getup_env.h"

#include <algorithm>

#include "podium/base/error.h"
#include "podium/character/actions.h"
#include "podium/character/observations.h"
#include "podium/character/starts.h"

namespace podium::tasks::getup {

namespace {

// s_weak and β̂ (Algorithm 1: a ~ π(s, β̂)).
character::CharacterEnvParts parts_for(const EnvSettings& s, const sim::ModelPtr& model) {
  using namespace character;
  CharacterEnvParts p;
  p.model = model;
  p.world.sim_hz = s.sim_hz;
  p.world.control_hz = s.control_hz;
  p.world.passive_joints = s.passive_joints;
  p.episode_steps = s.episode_steps;
  p.action = std::make_unique<TorqueActions>();
  add_weak_observation(p.observation, model);
  p.observation.push_back(std::make_unique<TaskScalars>(
      1, [](const CharacterEnv& env, std::span<double> out) { out[0] = static_cast<const GetupEnv&>(env).strength(); }));
  p.start = std::make_unique<RagdollDrop>(s.fall, RagdollDrop::Lying::any);
  p.record_start_transitions = s.fall_transitions;
  // §7: no early termination in Discover and Weaker.
  p.reward = [](const CharacterEnv& env, std::span<const double>, learn::StepResult& out) {
    out.reward = reward_weak(static_cast<const GetupEnv&>(env).weak());
  };
  p.before_episode = [](CharacterEnv& env, base::Rng& rng) { static_cast<GetupEnv&>(env).begin_episode(rng); };
  return p;
}

}  // namespace

void add_weak_observation(std::vector<std::unique_ptr<character::ObservationPart>>& parts, const sim::ModelPtr& model) {
  using namespace character;
  parts.push_back(std::make_unique<JointAngles>(model));
  parts.push_back(std::make_unique<JointVelocities>());
  parts.push_back(std::make_unique<RootVelocity>());
  parts.push_back(std::make_unique<HeadHeight>());
  parts.push_back(std::make_unique<CenterOfMass>());
  parts.push_back(std::make_unique<EndEffectors>());
  parts.push_back(std::make_unique<TorsoAxes>(true));
}

void check_policy_fits(const learn::FrozenPolicy& policy, const learn::Env& env, const std::string& who) {
  if (policy.observation_size() == env.observation_space().size() && policy.action_size() == env.action_space().size()) return;
  throw base::UserError(who + " takes " + std::to_string(policy.observation_size()) + " observations and gives " +
                        std::to_string(policy.action_size()) + " actions; the env of this config has " +
                        std::to_string(env.observation_space().size()) + " and " + std::to_string(env.action_space().size()) +
                        " (a policy trained for another variant or model?)");
}

sim::ModelEdits variant_edits(const std::string& variant) {
  sim::ModelEdits edits;
  if (variant == "casts") {
    // Straight at 0 rad, the standing pose's angle: a cast holds the limb as it was set.
    edits.joints = {{"elbow_left", base::Json{{"lock", 0.0}}}, {"knee_right", base::Json{{"lock", 0.0}}}};
  } else if (variant == "missing_arm") {
    edits.remove = {"upper_arm_left"};
  } else if (variant != "none") {
    throw base::UserError("getup env: unknown variant \"" + variant + "\" (none, casts, missing_arm)");
  }
  return edits;
}

double draw_strength(base::Rng& rng, double beta, double sigma, double floor) {
  return std::clamp(rng.normal(beta, sigma), floor, 1.0);
}

GetupEnv::GetupEnv(const EnvSettings& settings, std::shared_ptr<const double> curriculum, bool sample_strength,
                   std::shared_ptr<const double> floor)
    : GetupEnv(settings, sim::edit_model(sim::load_shipped_model(settings.model), variant_edits(settings.variant)),
               std::move(curriculum), sample_strength, std::move(floor)) {}

GetupEnv::GetupEnv(const EnvSettings& settings, const sim::ModelPtr& model, std::shared_ptr<const double> curriculum,
                   bool sample_strength, std::shared_ptr<const double> floor)
    : CharacterEnv(parts_for(settings, model)),
      curriculum_(std::move(curriculum)),
      floor_(std::move(floor)),
      sample_(sample_strength),
      settings_(settings),
      readings_(BodyReadings::of(*model)) {
  if (!curriculum_) throw base::UserError("getup env: no curriculum strength");
}

void GetupEnv::begin_episode(base::Rng& rng) {
  if (!replaying_) {
    const double beta = *curriculum_, floor = floor_ ? *floor_ : settings_.min_strength;
    strength_ = sample_ ? draw_strength(rng, beta, settings_.strength_sigma, floor) : beta;
  }
  start_rng_ = rng.save();
}

std::optional<base::Json> GetupEnv::save_state() const {
  if (step_index() == 0) return base::Json{{"episode_start", {{"rng", start_rng_}, {"strength", strength_}}}};
  base::Json state = *CharacterEnv::save_state();
  state["strength_hat"] = strength_;
  return state;
}

void GetupEnv::load_state(const base::Json& state) {
  try {
    if (state.contains("episode_start")) {
      strength_ = state.at("episode_start").at("strength").get<double>();
      rng().load(state.at("episode_start").at("rng").get<std::string>());
      replaying_ = true;
      std::vector<double> observation;
      reset(observation);  // the same fall, from the same generator state
      replaying_ = false;
      return;
    }
    strength_ = state.at("strength_hat").get<double>();
  } catch (const base::Json::exception& e) {
    replaying_ = false;
    throw base::UserError(std::string("getup env state: ") + e.what());
  }
  CharacterEnv::load_state(state);
}

}  // namespace podium::tasks::getup
