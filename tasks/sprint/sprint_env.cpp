// The sprint environment (sprint seed §2: state, action, base reward, domain randomisation; §3.2's
// phase terms with the preset's weights).
#include "sprint_env.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <numbers>
#include <utility>

#include "podium/base/error.h"
#include "podium/base/json.h"
#include "podium/character/actions.h"
#include "podium/character/frames.h"
#include "podium/character/observations.h"
#include "sprint_rewards.h"

namespace podium::tasks::sprint {

using character::CharacterEnv;

namespace {

// A step is a touchdown on the track past the start line (x = 0). Behind it a foot in the blocks
// slides off its face and touches the track with its toe within a few control steps of the set
// position; counted, that touch was the Start's "landing" (in the blocks), or it ended the hands'
// allowance there (a fall).
bool foot_on_track_past_line(const sim::World& world, const sim::Observation& f, int foot) {
  return f.touches(foot, sim::Contact::Partner::ground) && world.body_centroid(foot).x() > 0.0;
}

// The COM relative to the root, in the root's heading frame (as com_in_heading_frame, from the
// COM the World's observation already holds).
Eigen::Vector3d com_heading(const sim::CharacterData& d, const sim::Observation& f) {
  return character::heading_rotation(character::heading_yaw(d.links[0].R)).transpose() * (f.com - d.links[0].p);
}

EpisodeDraw draw_from_json(const base::Json& json, const std::string& where) {
  try {
    EpisodeDraw d;
    d.wind_mps = json.at("wind_mps").get<double>();
    d.friction = json.at("friction").get<double>();
    if (!std::isfinite(d.wind_mps) || !(d.friction >= 0.0))
      throw base::UserError("sprint env: " + where + ": " + json.dump() + " is not a draw (finite wind, friction ≥ 0)");
    return d;
  } catch (const base::Json::exception& e) {
    throw base::UserError("sprint env: " + where + ": " + e.what());
  }
}

SprintEnv::Outcome outcome_of(const std::string& name) {
  using O = SprintEnv::Outcome;
  for (const auto o : {O::running, O::fell, O::left_lane, O::finished, O::landed, O::deviated, O::no_landing})
    if (name == to_string(o)) return o;
  throw base::UserError("sprint env state: sprint.outcome: \"" + name +
                        "\" is not running, fell, left_lane, finished, landed, deviated or no_landing");
}

bool same_props(const std::vector<sim::BoxProp>& a, const std::vector<sim::BoxProp>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].name != b[i].name || a[i].center != b[i].center || a[i].half_extents != b[i].half_extents ||
        a[i].rotation.coeffs() != b[i].rotation.coeffs() || a[i].friction != b[i].friction)
      return false;
  return true;
}

}  // namespace

std::vector<BlockSpec> default_blocks() {
  BlockSpec front, rear;
  front.name = "front_block";
  front.x_m = -0.55, front.y_m = 0.1, front.angle_rad = std::numbers::pi / 4;
  rear.name = "rear_block";
  rear.x_m = -0.85, rear.y_m = -0.1, rear.angle_rad = std::numbers::pi / 3;
  return {front, rear};
}

std::vector<sim::BoxProp> starting_blocks(const std::vector<BlockSpec>& blocks) {
  std::vector<sim::BoxProp> props;
  for (const BlockSpec& b : blocks) {
    if (!(b.length_m > 0.0 && b.width_m > 0.0 && b.thickness_m > 0.0) ||
        !(b.angle_rad >= 0.0 && b.angle_rad < 0.5 * std::numbers::pi))
      throw base::UserError("sprint: block " + b.name + ": sizes must be > 0 and the angle in [0, π/2)");
    sim::BoxProp p;
    p.name = b.name;
    p.half_extents = Eigen::Vector3d(0.5 * b.length_m, 0.5 * b.width_m, 0.5 * b.thickness_m);
    // About +y: the face's normal tilts towards +x (the runner), its length rises towards −x.
    p.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(b.angle_rad, Eigen::Vector3d::UnitY()));
    const double lift = p.half_extents.x() * std::sin(b.angle_rad) + p.half_extents.z() * std::cos(b.angle_rad);
    p.center = Eigen::Vector3d(b.x_m, b.y_m, lift);  // the lowest edge on the ground
    p.friction = 1.0;
    props.push_back(std::move(p));
  }
  return props;
}

std::vector<base::Json> load_handover_states(const std::string& path) {
  const base::Json all = base::read_json_file(path);
  if (!all.is_array()) throw base::UserError(path + ": must be a JSON array of hand-over states");
  std::vector<base::Json> states;
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (!all[i].is_object() || !all[i].contains("world"))
      throw base::UserError(path + ": [" + std::to_string(i) + "]: a hand-over state needs \"world\" (a World snapshot)");
    states.push_back(all[i]);
  }
  return states;
}

void save_handover_states(const std::string& path, const std::vector<base::Json>& states) {
  std::ofstream out(path);
  out << base::Json(states).dump() << '\n';
  if (!out) throw base::UserError(path + ": cannot write the hand-over states");
}

std::vector<std::string> sprint_env_info_names(bool start_mode) {
  std::vector<std::string> names = {"forward", "survival", "lateral",   "mass",     "diagonal",      "mirror",   "primitive",
                                    "steps",   "fell",     "left_lane", "finished", "finish_time_s", "wind_mps", "friction"};
  if (start_mode) names.insert(names.end(), {"imitation", "landed", "deviated", "reference"});
  return names;
}

const char* to_string(SprintEnv::Outcome outcome) {
  switch (outcome) {
    case SprintEnv::Outcome::running:
      return "running";
    case SprintEnv::Outcome::fell:
      return "fell";
    case SprintEnv::Outcome::left_lane:
      return "left_lane";
    case SprintEnv::Outcome::finished:
      return "finished";
    case SprintEnv::Outcome::landed:
      return "landed";
    case SprintEnv::Outcome::deviated:
      return "deviated";
    case SprintEnv::Outcome::no_landing:
      return "no_landing";
  }
  return "running";
}

// One of the settings' hand-over states, uniformly: the World as it was (state, warm starts,
// friction, forces, clock); SprintEnv::reset takes its draw and step count.
struct SprintEnv::HandoverStart final : character::Start {
  void begin(CharacterEnv& env, base::Rng& rng) const override {
    auto& sprint = static_cast<SprintEnv&>(env);
    const std::vector<base::Json>& states = sprint.settings_.handover_states;
    const auto i = static_cast<std::size_t>(rng.integer(0, static_cast<std::int64_t>(states.size()) - 1));
    sprint.handover_ = &states[i];
    if (!states[i].contains("world"))
      throw base::UserError("sprint env: handover_states[" + std::to_string(i) + "]: world: missing (a World snapshot)");
    sprint.world().restore(sim::WorldSnapshot::from_json(states[i].at("world"), sprint.world().model_ptr()));
  }
};

// The Start mode's start (§3.1): a reference drawn uniformly, its blocks, its first frame (pose
// and frame velocity, no noise), the reference clock at 0.
struct SprintEnv::ReferenceSetStart final : character::Start {
  void begin(CharacterEnv& env, base::Rng& rng) const override {
    auto& sprint = static_cast<SprintEnv&>(env);
    const std::vector<StartReference>& refs = sprint.settings_.start_references;
    sprint.reference_ = static_cast<int>(rng.integer(0, static_cast<std::int64_t>(refs.size()) - 1));
    const StartReference& ref = refs[static_cast<std::size_t>(sprint.reference_)];
    env.set_reference(ref.clip);
    const std::vector<sim::BoxProp> blocks = starting_blocks(ref.blocks);
    if (!same_props(env.world().config().terrain.boxes, blocks)) {
      sim::TerrainConfig terrain = env.world().config().terrain;
      terrain.boxes = blocks;
      env.world().set_terrain(terrain);
    }
    character::ReferenceStateStart(0.0, 0, 0).begin(env, rng);
  }
};

struct SprintEnv::Terms {
  double mass = 0.0, diagonal = 0.0, mirror = 0.0, primitive = 0.0;
};

character::CharacterEnvParts SprintEnv::make_parts(const SprintEnvSettings& s) {
  using namespace character;
  CharacterEnvParts e;
  e.model = sim::load_shipped_model(s.model);
  e.world.sim_hz = s.sim_hz;
  e.world.control_hz = s.control_hz;
  e.world.terrain.boxes = starting_blocks(s.blocks);
  e.episode_steps = std::max(1, static_cast<int>(std::ceil(s.preset.time_limit_s * s.control_hz - 1e-9)));
  e.action = std::make_unique<TargetActions>(e.model, sim::Control::spd_maba);  // §2 "Action"
  // §2 "State": link poses and velocities, the COM c_t, z_t (z last: on_step refreshes it).
  e.observation.push_back(std::make_unique<LinkStates>(LinkStates::Blocks{}, LinkStates::Frame::heading));
  e.observation.push_back(std::make_unique<TaskScalars>(3, [](const CharacterEnv& env, std::span<double> out) {
    const Eigen::Vector3d c = com_heading(env.world().data(), env.features());
    out[0] = c.x(), out[1] = c.y(), out[2] = c.z();
  }));
  e.observation.push_back(std::make_unique<CenterOfMass>());
  e.observation.push_back(
      std::make_unique<TaskScalars>(3, [centre = s.preset.track.lane_centre_y_m](const CharacterEnv& env, std::span<double> out) {
        const sim::CharacterData& d = env.world().data();
        const double yaw = heading_yaw(d.links[0].R);
        out[0] = d.q(1) - centre, out[1] = std::sin(yaw), out[2] = std::cos(yaw);
      }));
  const std::size_t references = s.start_references.size();
  if (references > 0) {  // the reference's phase and which it is, before z
    e.observation.push_back(std::make_unique<TaskScalars>(1 + references, [](const CharacterEnv& env, std::span<double> out) {
      const auto& sprint = static_cast<const SprintEnv&>(env);
      std::fill(out.begin(), out.end(), 0.0);
      out[0] = std::min(1.0, env.reference_time_s() / env.reference()->duration_s());
      if (sprint.reference_ >= 0) out[1 + static_cast<std::size_t>(sprint.reference_)] = 1.0;  // none before a reset
    }));
  }
  e.observation.push_back(std::make_unique<TaskScalars>(
      1, [](const CharacterEnv& env, std::span<double> out) { out[0] = static_cast<const SprintEnv&>(env).counter_.z(); }));
  if (references > 0) {
    double longest = 0.0;
    for (const StartReference& r : s.start_references) {
      if (!r.clip || r.clip->model->name() != e.model->name() || r.clip->size() < 2)
        throw base::UserError("sprint env: start reference " + r.name + ": needs a clip of 2 frames or more on " +
                              e.model->name());
      longest = std::max(longest, r.clip->duration_s());
    }
    e.episode_steps =
        std::min(e.episode_steps, static_cast<int>(std::ceil((longest + s.preset.start.extra_time_s) * s.control_hz)));
    e.reference = s.start_references.front().clip;
    e.start = std::make_unique<ReferenceSetStart>();
  } else if (!s.handover_states.empty()) {
    e.start = std::make_unique<HandoverStart>();
  } else if (s.start_q.size() > 0) {
    const Eigen::VectorXd qd = s.start_qd.size() > 0 ? s.start_qd : Eigen::VectorXd::Zero(e.model->nv());
    if (s.start_q.size() != e.model->nq() || qd.size() != e.model->nv())
      throw base::UserError("sprint env: start state: q has " + std::to_string(s.start_q.size()) + " entries and qd " +
                            std::to_string(qd.size()) + ", model " + e.model->name() + " has nq " +
                            std::to_string(e.model->nq()) + " and nv " + std::to_string(e.model->nv()));
    e.start = std::make_unique<StateStart>(s.start_q, qd);
  } else {
    e.start = std::make_unique<StandingStart>(s.standing);
  }
  e.reward = [](CharacterEnv& env, std::span<const double>, learn::StepResult& out) {
    static_cast<SprintEnv&>(env).on_step(out);
  };
  e.info_names = sprint_env_info_names(references > 0);
  return e;
}

SprintEnv::SprintEnv(const SprintEnvSettings& settings)
    : CharacterEnv(make_parts(settings)),
      settings_(settings),
      bodies_(SprintBodies::of(model())),
      allowance_(bodies_.ground_allowance()),
      lane_bodies_{0, bodies_.left_foot, bodies_.right_foot},
      finish_(model(), settings.preset.track),
      counter_(settings.preset.steps),
      mirror_(model()),
      drag_(world().model_ptr(), settings.preset.drag) {
  sim::CharacterData standing(model());
  standing.q = model().standing_pose();
  upright_com_ = com_in_heading_frame(model(), standing);
  z_index_ = observation_space().size() - 1;
  for (const StartReference& r : settings.start_references)
    imitations_.push_back(std::make_shared<const character::ImitationReference>(r.clip, settings.preset.start.weights));
  early_.max_com_deviation_m = settings.preset.start.max_com_deviation_m;  // falls: the sprint's own rule
  early_.min_pose_reward = settings.preset.start.min_pose_reward;
  world().set_substep_observer([this](sim::World& w) { finish_.observe(w); });
  if (settings.primitive && settings.preset.rewards.primitive != 0.0 && !start_mode()) {
    bridge_ = std::make_unique<character::PoseBridge>(world().model_ptr());
    strides_.emplace(settings.primitive->settings(), control_dt_s());
  }
}

void SprintEnv::reset(std::vector<double>& observation) {
  if (settings_.log_distances && step_index() > 0) distances_.push_back(prev_root_x_ - start_root_x_);
  handover_ = nullptr;
  reference_ = -1;
  landing_.reset();
  // Drawn every episode, whatever the start and even when a fixed draw replaces it, so that the
  // generator's later use (the start's choice) is the same under every condition.
  draw_ = draw_episode(settings_.preset, rng());
  CharacterEnv::reset(observation);
  if (settings_.fixed_draw) draw_ = *settings_.fixed_draw;
  else if (handover_ && handover_->contains("draw")) draw_ = draw_from_json(handover_->at("draw"), "hand-over state draw");
  begin_episode();
  observe(observation);  // z of this episode's counter
}

void SprintEnv::begin_episode() {
  // §2 "Initial State": the runway's μ (a hand-over state already carries its own).
  if (world().config().friction != draw_.friction) world().set_friction(draw_.friction);
  const sim::Observation& f = features();
  if (handover_ && handover_->contains("step_counter")) counter_.load_state(handover_->at("step_counter"));
  else  // the counter's own rule: a foot in the blocks is off the track, so its first touchdown past the line counts
    counter_.reset(foot_on_track_past_line(world(), f, bodies_.left_foot),
                   foot_on_track_past_line(world(), f, bodies_.right_foot));
  finish_.reset(world());
  poses_.reset();
  if (strides_) strides_->reset();
  prev_root_x_ = start_root_x_ = world().data().q(0);
  outcome_ = Outcome::running;
  apply_drag();
}

std::vector<double> SprintEnv::take_episode_distances() { return std::exchange(distances_, {}); }

std::vector<std::vector<double>> SprintEnv::take_strides() { return std::exchange(completed_, {}); }

void SprintEnv::apply_drag() { drag_.apply(world(), Eigen::Vector3d(draw_.wind_mps, 0.0, 0.0)); }  // §2, wind along +x

SprintEnv::Terms SprintEnv::phase_terms(const sim::Observation& f) {
  const RewardWeights& w = settings_.preset.rewards;
  const sim::CharacterData& d = world().data();
  Terms t;
  t.mass = mass_penalty(com_heading(d, f), upright_com_, w.mass);  // §3.2, r_mass
  if (w.diagonal > 0.0) {
    SwingAngles swing;
    swing.left_hip = sagittal_angle(model(), d, bodies_.left_thigh);
    swing.right_hip = sagittal_angle(model(), d, bodies_.right_thigh);
    swing.left_shoulder = sagittal_angle(model(), d, bodies_.left_upper_arm);
    swing.right_shoulder = sagittal_angle(model(), d, bodies_.right_upper_arm);
    t.diagonal = w.diagonal * diagonal_reward(swing, w.diagonal_k);  // §3.2, r_diag
  }
  if (w.mirror > 0.0) {
    const Eigen::VectorXd* previous = poses_.aligned_previous();
    if (previous) t.mirror = w.mirror * mirror_reward(mirror_, d.q, *previous, w.mirror_k);  // §3.2, r_mirror
    poses_.record(d.q);
  }
  if (strides_) {  // §3.2, r_primitive at each completed stride
    const double s = sagittal_angle(model(), d, bodies_.left_thigh) - sagittal_angle(model(), d, bodies_.right_thigh);
    if (auto stride = strides_->observe(stride_frame(*bridge_, d.q), s)) {
      t.primitive = w.primitive * settings_.primitive->reward(*stride);
      completed_.push_back(std::move(*stride));
    }
  }
  return t;
}

const character::ImitationReference& SprintEnv::imitation() const {
  if (reference_ < 0) throw base::UserError("sprint env: no start reference (not the Start mode, or before a reset)");
  return *imitations_[static_cast<std::size_t>(reference_)];
}

character::TrackingErrors SprintEnv::tracking_errors() const { return imitation().errors(*this); }

character::ImitationTerms SprintEnv::imitation_terms() const {
  return character::imitation_terms(tracking_errors(), imitation().weights());
}

// §3.1: λ_i·r_I, early termination, and the first landing (a counted touchdown on the ground).
double SprintEnv::start_terms(const sim::Observation& f, bool counted, bool& landed, bool& deviated) {
  const character::TrackingErrors errors = tracking_errors();
  const character::ImitationTerms terms = character::imitation_terms(errors, imitation().weights());
  deviated = character::early_termination(early_, f, errors, terms) == character::Termination::deviated;
  const int foot = counter_.last_foot() == Foot::left ? bodies_.left_foot : bodies_.right_foot;
  landed = counted && f.touches(foot, sim::Contact::Partner::ground);
  return settings_.preset.start.imitation_weight * terms.total;
}

// Whether the Start's reference (the one drawn) is over, with the preset's extra time (the caller
// asks only when the step did not land).
bool SprintEnv::start_overran() const {
  if (!start_mode() || reference_ < 0) return false;
  const StartReference& ref = settings_.start_references[static_cast<std::size_t>(reference_)];
  return reference_time_s() >= ref.clip->duration_s() + settings_.preset.start.extra_time_s - 1e-9;
}

void SprintEnv::on_step(learn::StepResult& out) {
  const sim::Observation& f = features();
  const TrackSpec& track = settings_.preset.track;
  const double x = world().data().q(0), y = world().data().q(1);
  const bool counted = counter_.observe(foot_on_track_past_line(world(), f, bodies_.left_foot),
                                        foot_on_track_past_line(world(), f, bodies_.right_foot));
  if (counted) poses_.touchdown();
  const bool fell = fallen_body(f, allowance_, counter_.steps() > 0) >= 0;
  const bool left_lane = body_outside_lane(track, world(), lane_bodies_) >= 0;
  const std::optional<double> finish = finish_.finish_time();
  // §2: r_base = r_f + r_s + r_d.
  const BaseReward base =
      base_reward(settings_.preset.rewards, prev_root_x_, x, control_dt_s(), y - track.lane_centre_y_m, track.lane_width_m, fell);
  prev_root_x_ = x;
  const Terms terms = phase_terms(f);
  bool landed = false, deviated = false;
  const double imitation = start_mode() ? start_terms(f, counted, landed, deviated) : 0.0;
  outcome_ = fell              ? Outcome::fell
             : left_lane       ? Outcome::left_lane
             : deviated        ? Outcome::deviated
             : landed          ? Outcome::landed
             : start_overran() ? Outcome::no_landing
             : finish          ? Outcome::finished
                               : Outcome::running;
  out.reward = base.total() + terms.mass + terms.diagonal + terms.mirror + terms.primitive + imitation;
  // A phase's end is a hand-over, not a failure: the landing hands the run to stage 2 and the line
  // ends the race. Both cut the episode as a time limit does (PPO bootstraps there), and a Start
  // that has not landed when its reference is over has failed (terminal, worth nothing). With the
  // landing terminal and the reference's end a time limit, the survival and imitation reward of
  // the steps left made not landing pay more, and a Start policy trained so learnt not to land.
  out.terminated = outcome_ == Outcome::fell || outcome_ == Outcome::left_lane || outcome_ == Outcome::deviated ||
                   outcome_ == Outcome::no_landing;
  out.truncated = outcome_ == Outcome::landed || outcome_ == Outcome::finished;
  out.info = {base.forward,     base.survival,         base.lateral,       terms.mass,
              terms.diagonal,   terms.mirror,          terms.primitive,    static_cast<double>(counter_.steps()),
              fell ? 1.0 : 0.0, left_lane ? 1.0 : 0.0, finish ? 1.0 : 0.0, finish.value_or(0.0),
              draw_.wind_mps,   draw_.friction};
  if (start_mode())
    out.info.insert(out.info.end(), {imitation, landed ? 1.0 : 0.0, deviated ? 1.0 : 0.0, static_cast<double>(reference_)});
  out.observation[z_index_] = counter_.z();  // the observation was written before this step counted
  apply_drag();
  if (outcome_ == Outcome::landed) landing_ = handover_state();  // with the drag the next step feels
}

base::Json SprintEnv::handover_state() const {
  return {{"world", world().snapshot().to_json()}, {"draw", draw_.to_json()}, {"step_counter", counter_.state()}};
}

base::Json SprintEnv::episode_record() const {
  const std::optional<double> finish = finish_.finish_time();
  return {{"draw", draw_.to_json()},
          {"reference", reference_ >= 0 ? base::Json(settings_.start_references[static_cast<std::size_t>(reference_)].name)
                                        : base::Json(nullptr)},
          {"outcome", to_string(outcome_)},
          {"steps", counter_.steps()},
          {"control_steps", step_index()},
          {"finish_time_s", finish ? base::Json(*finish) : base::Json(nullptr)}};
}

std::optional<base::Json> SprintEnv::save_state() const {
  base::Json state = *CharacterEnv::save_state();
  state["sprint"] = {{"draw", draw_.to_json()},
                     {"step_counter", counter_.state()},
                     {"finish_line", finish_.state()},
                     {"poses", poses_.state()},
                     {"strides", strides_ ? strides_->state() : base::Json(nullptr)},
                     {"prev_root_x", prev_root_x_},
                     {"start_root_x", start_root_x_},
                     {"outcome", to_string(outcome_)},
                     {"reference", reference_},
                     {"landing", landing_ ? *landing_ : base::Json(nullptr)}};
  return state;
}

void SprintEnv::load_state(const base::Json& state) {
  CharacterEnv::load_state(state);
  if (!state.contains("sprint")) throw base::UserError("sprint env state: sprint: missing (SprintEnv::save_state's)");
  const base::Json& s = state.at("sprint");
  try {
    draw_ = draw_from_json(s.at("draw"), "state sprint.draw");
    counter_.load_state(s.at("step_counter"));
    finish_.load_state(s.at("finish_line"));
    poses_.load_state(s.at("poses"));
    if (strides_ && s.contains("strides") && !s.at("strides").is_null()) strides_->load_state(s.at("strides"));
    prev_root_x_ = s.at("prev_root_x").get<double>();
    start_root_x_ = s.value("start_root_x", prev_root_x_);
    outcome_ = outcome_of(s.at("outcome").get<std::string>());
    reference_ = s.value("reference", -1);
    if (reference_ >= static_cast<int>(settings_.start_references.size()))
      throw base::UserError("sprint env state: sprint.reference: " + std::to_string(reference_) + " is not one of the " +
                            std::to_string(settings_.start_references.size()) + " start references");
    if (reference_ >= 0) set_reference(settings_.start_references[static_cast<std::size_t>(reference_)].clip);
    landing_.reset();
    if (s.contains("landing") && !s.at("landing").is_null()) landing_ = s.at("landing");
  } catch (const base::Json::exception& e) {
    throw base::UserError(std::string("sprint env state: sprint: ") + e.what());
  }
  handover_ = nullptr;
}

}  // namespace podium::tasks::sprint
