#include "jump_env.h"

#include <cmath>

#include "podium/base/error.h"
#include "podium/character/actions.h"
#include "podium/character/frames.h"
#include "podium/character/observations.h"

namespace podium::tasks::jump {

namespace {

TakeoffState reference_takeoff(const JumpSettings& s, const sim::ModelPtr& model, int foot) {
  if (s.takeoff_state.empty()) return read_takeoff_json(model, shipped_takeoff_path(), foot);
  const std::filesystem::path path = s.takeoff_state;
  const std::string ext = path.extension().string();
  if (ext == ".json") return read_takeoff_json(model, path, foot);
  if (ext == ".npy") return read_takeoff_npy(model, path, foot);
  if (ext == ".txt") return takeoff_from_clip(character::read_deepmimic_clip(model, path), foot);
  throw base::UserError("jump env: takeoff_state " + s.takeoff_state + ": not a .json, .npy or .txt file");
}

}  // namespace

std::vector<std::string> jump_info_names() {
  return {"success", "outcome", "head_first", "mean_root_speed", "mean_offset_l1", "up_angle_rad", "difficulty_m"};
}

sim::ModelEdits variation_edits(const JumpSettings& s) {
  sim::ModelEdits edits;
  edits.joints = s.joint_edits;
  edits.mass_scale = s.mass_scale;
  return edits;
}

JumpSettings read_jump_settings(base::ConfigReader& r) {
  JumpSettings s;
  s.kind = parse_jump_kind(
      r.choice("kind", jump_kind_name(s.kind), {"high_jump", "obstacle"}, "§3.6.1: bar (z = height) or box (z = width)"), "kind");
  s.model = r.string("model", s.model, "sim/models/<model>.json");
  s.takeoff_foot = r.string("takeoff_foot", s.takeoff_foot, "the body allowed on the ground (§3.6.1)");
  // A config's default is kind-independent (describe lists one), so 0 stands for the kind's z_min.
  s.difficulty_m = r.number("difficulty_m", 0.0, {.min = 0.0, .max = 5.0}, "z at the start; 0: Table 3.1's z_min for the kind");
  if (s.difficulty_m == 0.0) s.difficulty_m = difficulty_curriculum(s.kind).initial;
  s.sim_hz = r.number("sim_hz", s.sim_hz, {.min = 30.0}, "physics steps per second (§3.6.2: 600)");
  s.takeoff_state = r.file("takeoff_state", s.takeoff_state, "reference take-off state file (.json, .npy, .txt); empty: shipped");
  s.takeoff_features = r.numbers("takeoff_features", s.takeoff_features, {}, "Stage 1's x (take-off features); empty: none");
  s.layout.approach_angle_rad =
      r.number("approach_angle_rad", s.layout.approach_angle_rad, {}, "α without features (π/2: bar across the run)");
  s.layout.wall_distance_m = r.number("wall_distance_m", s.layout.wall_distance_m, {.min = 0.0}, "take-off point to the wall");
  s.layout.obstacle_distance_m =
      r.number("obstacle_distance_m", s.layout.obstacle_distance_m, {.min = 0.0}, "take-off point to the box");
  s.rules.clearance_m = r.number("clearance_m", s.rules.clearance_m, {.min = 0.0}, "§3.6.1: 0.2");
  s.rules.time_limit_s = r.number("time_limit_s", s.rules.time_limit_s, {.min = 0.0, .exclusive_min = true}, "§3.6.1: 2");
  s.latent_bound = r.number("latent_bound", s.latent_bound, {.min = 0.0, .exclusive_min = true}, "P-VAE latent box");
  s.offset_bound = r.number("offset_bound", s.offset_bound, {.min = 0.0}, "per-joint offset box, rad");
  s.novelty_threshold_rad = r.number("novelty_threshold_rad", s.novelty_threshold_rad, {.min = 0.0, .exclusive_min = true},
                                     "eq. 3.12's d_threshold (§3.6.2: π/2)");
  s.gravity_mps2 = r.number("gravity_mps2", s.gravity_mps2, {.min = 0.0, .max = 100.0},
                            "gravity's magnitude, m/s² (Earth 9.81; the thesis's Mars jump, Fig. 3.9: 3.711)");
  s.strength = r.number("strength", s.strength, {.min = 0.0, .max = 10.0, .exclusive_min = true},
                        "every torque limit × this (a weaker athlete below 1)");
  s.mass_scale = r.number("mass_scale", s.mass_scale, {.min = 0.0, .max = 10.0, .exclusive_min = true},
                          "every body's mass and inertia × this (the geometry unchanged)");
  const base::Json edits = r.raw_object("joint_edits",
                                        "per joint name, model-file keys merged into its entry (§3.7's variations, Fig. 3.8: "
                                        "{\"right_knee\": {\"lock\": -0.3}} for a cast, \"range\"/\"swing\"/\"twist\" for a "
                                        "stiffer joint, \"torque_limit\" for a weaker one; sim/README.md)");
  for (const auto& [joint, keys] : edits.items()) {
    if (!keys.is_object())
      r.fail("joint_edits", "entry \"" + joint + "\" is " + keys.dump() + ", not an object of model-file keys");
    s.joint_edits.emplace_back(joint, keys);
  }
  if (!s.joint_edits.empty() || s.mass_scale != 1.0) {
    try {
      (void)sim::edit_model(sim::load_shipped_model(s.model), variation_edits(s));
    } catch (const base::UserError& e) {
      r.fail("joint_edits", e.what());
    }
  }
  if (!s.takeoff_features.empty() && s.takeoff_features.size() != takeoff_features(s.kind).size())
    r.fail("takeoff_features", "has " + std::to_string(s.takeoff_features.size()) + " values; " + jump_kind_name(s.kind) +
                                   " explores " + std::to_string(takeoff_features(s.kind).size()));
  return s;
}

struct JumpEnv::Parts {
  character::CharacterEnvParts env;
  TakeoffState takeoff;
  int foot = -1;
  bool composite = false;
  std::size_t latent_size = 0;
  JumpSuite suite;
};

JumpEnv::JumpEnv(const JumpSettings& settings, PosePrior prior)
    : JumpEnv(settings, [&] {
        using namespace character;
        Parts p;
        const sim::ModelPtr model = sim::edit_model(sim::load_shipped_model(settings.model), variation_edits(settings));
        p.foot = model->find_body(settings.takeoff_foot);
        if (p.foot < 0)
          throw base::UserError("jump env: model " + model->name() + " has no body " + settings.takeoff_foot + " (takeoff_foot)");
        p.takeoff = reference_takeoff(settings, model, p.foot);
        if (!settings.takeoff_features.empty())
          p.takeoff = apply_takeoff_features(settings.kind, p.takeoff, settings.takeoff_features);
        SuiteLayout layout = settings.layout;
        layout.approach_angle_rad = approach_angle(settings.kind, settings.takeoff_features, layout.approach_angle_rad);
        p.suite = make_suite(settings.kind, settings.difficulty_m, layout);

        CharacterEnvParts& e = p.env;
        e.model = model;
        e.world.sim_hz = settings.sim_hz;
        e.world.control_hz = control_hz_for(difficulty_ratio(settings.kind, settings.difficulty_m), settings.sim_hz);
        e.world.terrain = p.suite.terrain;
        e.world.gravity = Eigen::Vector3d(0.0, 0.0, -settings.gravity_mps2);
        e.world.strength = settings.strength;
        // The last step reaches the time limit, where the rules end the episode (never truncated).
        e.episode_steps = static_cast<int>(std::ceil(settings.rules.time_limit_s * e.world.control_hz - 1e-9));
        if (prior.vae) {
          e.action = std::make_unique<VaeActions>(prior.vae, PoseBridge(model, prior.frame), sim::Control::spd_maba,
                                                  settings.latent_bound, settings.offset_bound);
          p.composite = true, p.latent_size = prior.vae->latent_size();
        } else {
          e.action = std::make_unique<TargetActions>(model, sim::Control::spd_maba);
        }
        e.observation.push_back(std::make_unique<LinkStates>(LinkStates::Blocks{}, LinkStates::Frame::world));
        e.observation.push_back(std::make_unique<TaskScalars>(4, [](const CharacterEnv& env, std::span<double> out) {
          const Eigen::VectorXd& q = env.world().data().q;
          out[0] = q(0), out[1] = q(1), out[2] = q(2);
          out[3] = static_cast<const JumpEnv&>(env).difficulty_m();
        }));
        e.start = std::make_unique<TakeoffStart>(p.takeoff);
        e.reward = [](CharacterEnv& env, std::span<const double> action, learn::StepResult& out) {
          static_cast<JumpEnv&>(env).on_step(action, out);
        };
        e.info_names = jump_info_names();
        return p;
      }()) {}

JumpEnv::JumpEnv(const JumpSettings& settings, Parts p)
    : CharacterEnv(std::move(p.env)),
      settings_(settings),
      takeoff_(std::move(p.takeoff)),
      foot_(p.foot),
      composite_(p.composite),
      latent_size_(p.latent_size),
      z_(settings.difficulty_m),
      c_offset_(offset_coefficient(difficulty_ratio(settings.kind, z_))),
      suite_(std::move(p.suite)),
      referee_(model(), foot_, suite_.obstacle_prop, suite_.block_prop, settings.rules),
      crossing_(suite_) {}

bool JumpEnv::set_difficulty(double z_m) {
  SuiteLayout layout = settings_.layout;
  layout.approach_angle_rad = approach_angle(settings_.kind, settings_.takeoff_features, layout.approach_angle_rad);
  suite_ = make_suite(settings_.kind, z_m, layout);
  world().set_terrain(suite_.terrain);
  crossing_ = CrossingRecorder(suite_);
  z_ = z_m;
  const double rho = difficulty_ratio(settings_.kind, z_m);
  c_offset_ = offset_coefficient(rho);
  return std::abs(control_hz_for(rho, settings_.sim_hz) - world().config().control_hz) < 1e-9;
}

void JumpEnv::reset(std::vector<double>& observation) {
  CharacterEnv::reset(observation);
  referee_.reset();
  crossing_.reset();
  sums_ = EpisodeSums{};
  terms_ = RewardTerms{};
  observe_crossing();  // the take-off state
}

void JumpEnv::observe_crossing() {
  const Eigen::VectorXd& q = world().data().q;
  crossing_.observe(features().com, character::quat_at(q, 3));
}

// After each control step: the sums for r_ω and r_naturalness, the feature, the rules; the
// reward once the episode is decided (§3.6.1: sparse).
void JumpEnv::on_step(std::span<const double> action, learn::StepResult& out) {
  double offset_l1 = 0.0;
  if (composite_)
    for (std::size_t k = latent_size_; k < action.size(); ++k) offset_l1 += std::min(std::abs(action[k]), settings_.offset_bound);
  sums_.add(world().data().qd.head<3>().norm(), offset_l1);
  observe_crossing();
  const Outcome outcome = referee_.judge(world(), features(), step_index() * control_dt_s());
  out.reward = 0.0;
  if (outcome != Outcome::in_flight) {
    out.terminated = true;
    const bool success = outcome == Outcome::success;
    const Eigen::Vector3d f = crossing_.bar_frame_rotation();
    const double novelty =
        success ? novelty_reward(std::span<const double>(f.data(), 3), known_, settings_.novelty_threshold_rad) : 1.0;
    terms_ = jump_reward(success, referee_.head_first(), sums_, c_offset_, novelty);
    out.reward = terms_.total();
  }
  out.info = {outcome == Outcome::success ? 1.0 : 0.0,
              static_cast<double>(outcome),
              referee_.head_first() ? 1.0 : 0.0,
              sums_.mean_root_speed(),
              sums_.mean_offset_l1(),
              crossing_.up_angle(),
              z_};
}

std::optional<base::Json> JumpEnv::save_state() const {
  base::Json state = *CharacterEnv::save_state();
  state["jump"] = {{"difficulty_m", z_},
                   {"referee", referee_.state()},
                   {"crossing", crossing_.state()},
                   {"sums", {sums_.steps, sums_.root_speed_sum, sums_.offset_l1_sum}},
                   {"terms", {terms_.complete, terms_.omega, terms_.safety, terms_.naturalness, terms_.novelty}}};
  return state;
}

void JumpEnv::load_state(const base::Json& state) {
  try {
    const base::Json& j = state.at("jump");
    set_difficulty(j.at("difficulty_m").get<double>());
    CharacterEnv::load_state(state);  // after the props: the snapshot's terrain is the saved one
    referee_.load_state(j.at("referee"));
    crossing_.load_state(j.at("crossing"));
    const base::Json& s = j.at("sums");
    sums_ = EpisodeSums{s.at(0).get<int>(), s.at(1).get<double>(), s.at(2).get<double>()};
    const base::Json& t = j.at("terms");
    terms_ = RewardTerms{t.at(0).get<double>(), t.at(1).get<double>(), t.at(2).get<double>(), t.at(3).get<double>(),
                         t.at(4).get<double>()};
  } catch (const base::Json::exception& e) {
    throw base::UserError(std::string("jump env state: ") + e.what());
  }
}

}  // namespace podium::tasks::jump
