#include "runup_env.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "podium/base/error.h"
#include "podium/character/actions.h"
#include "podium/character/observations.h"
#include "podium/sim/dynamics.h"
#include "takeoff.h"

namespace podium::tasks::jump {

using character::Termination;

std::vector<std::string> runup_info_names() {
  return {"imitation",     "handed_over",   "task_reward",        "fell", "deviated", "omega_error_x",
          "omega_error_y", "omega_error_z", "lateral_speed_error"};
}

RunupSettings read_runup_settings(base::ConfigReader& r, const RunupSettings& jump) {
  RunupSettings s = jump;
  s.other_foot = s.takeoff_foot;  // the take-off foot's partner
  if (const auto at = s.other_foot.find("right"); at != std::string::npos) s.other_foot.replace(at, 5, "left");
  else if (const auto left = s.other_foot.find("left"); left != std::string::npos) s.other_foot.replace(left, 4, "right");
  s.motion = r.file("runup_motion", s.motion,
                    "the reference run of the run-up stage (DeepMimic format; §3.6.1: a curved sprint for the high jump, "
                    "arpspoof/Jump's data/motions/beyond/VC5_sprint__curves_03.txt, a straight one for the obstacle jump, "
                    "VC5_Run_jumpToBox_01.txt); \"\": none (the stage then fails with this key's name)");
  s.control_hz =
      r.number("runup_control_hz", s.control_hz, {.min = 1.0}, "the run-up's control rate (DeepMimic: 30 Hz); divides sim_hz");
  s.takeoff_time_s = r.number("runup_takeoff_time_s", s.takeoff_time_s, {.min = 0.0},
                              "the take-off on the reference's clock; 0: its last single support on takeoff_foot");
  s.lead_s = r.number("runup_lead_s", s.lead_s, {.min = 0.0},
                      "how long before the take-off the run-up begins, s (its first frame and RSI's range); 0: the "
                      "reference's first frame, the thesis's whole run");
  s.handover_window_s = r.number("runup_window_s", s.handover_window_s, {.min = 0.0},
                                 "how early before the take-off time a step on takeoff_foot alone hands over to the jump");
  s.start_noise_rad = r.number("runup_start_noise", s.start_noise_rad, {.min = 0.0}, "RSI joint noise, rad");
  s.actions = r.choice(
      "runup_actions", s.actions, {"residual", "targets"},
      "residual: the reference pose + a per-joint offset (the default); targets: the PD targets themselves (DeepMimic's)");
  s.offset_bound_rad = r.number("runup_offset_bound", s.offset_bound_rad, {.min = 0.0, .exclusive_min = true},
                                "the residual action's per-joint offset bound, rad");
  s.max_com_deviation_m = r.number("runup_max_com_deviation_m", s.max_com_deviation_m, {.min = 0.0, .exclusive_min = true},
                                   "early termination when the COM is this far from the reference's");
  s.warm_start = r.existing_file("runup_warm_start", s.warm_start,
                                 "a run-up trial's training.ckpt to train on from (the same target, reference and networks; its "
                                 "steps count towards total_samples); empty: from scratch");
  return s;
}

std::shared_ptr<const character::Clip> load_reference_run(const RunupSettings& s) {
  if (s.motion.empty()) throw base::UserError("jump runup: runup_motion: no reference run given (a DeepMimic-format clip)");
  const sim::ModelPtr model = sim::load_shipped_model(s.model);
  character::Clip clip = character::resample(character::read_deepmimic_clip(model, s.motion), 1.0 / s.control_hz);
  // Lowered (or raised) so that the lowest point of any geom over the clip is on the ground.
  sim::CharacterData d(*model);
  double low = std::numeric_limits<double>::infinity();
  for (const Eigen::VectorXd& q : clip.poses) {
    d.q = q;
    sim::forward_kinematics(*model, d);
    low = std::min(low, sim::lowest_geom_point(*model, d));
  }
  for (Eigen::VectorXd& q : clip.poses) q(2) -= low;
  clip.loop = false;
  return std::make_shared<const character::Clip>(std::move(clip));
}

struct RunupEnv::Parts {
  character::CharacterEnvParts env;
  std::shared_ptr<const character::ImitationReference> imitation;
  TakeoffCondition condition;
  int foot = -1, other = -1;
};

namespace {

// The run-up's first frame: lead_s before the take-off (rounded down to a frame), or the first.
int first_frame(const RunupSettings& s, double takeoff_time_s) {
  if (s.lead_s <= 0.0) return 0;
  return std::max(0, static_cast<int>(std::floor((takeoff_time_s - s.lead_s) * s.control_hz + 1e-9)));
}

int body_of(const sim::CharacterModel& model, const std::string& name, const char* key) {
  const int b = model.find_body(name);
  if (b < 0) throw base::UserError("jump runup: model " + model.name() + " has no body " + name + " (" + key + ")");
  return b;
}

}  // namespace

RunupEnv::RunupEnv(const RunupSettings& settings, std::shared_ptr<const character::Clip> reference, bool from_start)
    : RunupEnv(settings, [&] {
        using namespace character;
        Parts p;
        if (!reference) throw base::UserError("jump runup: no reference run");
        const sim::ModelPtr model = reference->model;
        p.foot = body_of(*model, settings.takeoff_foot, "takeoff_foot");
        p.other = body_of(*model, settings.other_foot, "the other foot");
        p.imitation = std::make_shared<const ImitationReference>(reference);
        p.condition.window_s = settings.handover_window_s;
        p.condition.takeoff_time_s = settings.takeoff_time_s > 0
                                         ? settings.takeoff_time_s
                                         : reference_takeoff_time(*model, reference->times_s, reference->poses, p.foot);
        if (p.condition.takeoff_time_s > reference->duration_s() + 1e-9)
          throw base::UserError("jump runup: runup_takeoff_time_s " + std::to_string(p.condition.takeoff_time_s) +
                                " is after the reference run's end " + std::to_string(reference->duration_s()) + " s");
        CharacterEnvParts& e = p.env;
        e.model = model;
        e.world.sim_hz = settings.sim_hz;
        e.world.control_hz = settings.control_hz;
        e.episode_steps = static_cast<int>(std::ceil(p.condition.takeoff_time_s * settings.control_hz - 1e-9)) + 1;
        if (settings.actions == "residual")
          e.action = std::make_unique<ResidualActions>(model, sim::Control::spd_maba, settings.offset_bound_rad);
        else e.action = std::make_unique<TargetActions>(model, sim::Control::spd_maba);
        e.observation.push_back(std::make_unique<LinkStates>(LinkStates::Blocks{}, LinkStates::Frame::heading));
        e.observation.push_back(std::make_unique<TaskScalars>(
            1, [](const CharacterEnv& env, std::span<double> out) { out[0] = env.world().data().q(2); }));
        e.observation.push_back(std::make_unique<ReferencePhase>(p.imitation));
        // RSI over the frames from the run-up's first to the take-off's: a start at or after the
        // take-off would hand over at once.
        const int last = std::max(0, static_cast<int>(std::floor(p.condition.takeoff_time_s * settings.control_hz + 1e-9)) - 1);
        const int first = std::clamp(first_frame(settings, p.condition.takeoff_time_s), 0, last);
        if (from_start) e.start = std::make_unique<ReferenceStateStart>(0.0, first, first);
        else e.start = std::make_unique<ReferenceStateStart>(settings.start_noise_rad, first, last);
        e.reward = [](CharacterEnv& env, std::span<const double>, learn::StepResult& out) {
          static_cast<RunupEnv&>(env).on_step(out);
        };
        e.info_names = runup_info_names();
        e.reference = reference;
        return p;
      }()) {}

RunupEnv::RunupEnv(const RunupSettings& settings, Parts p)
    : CharacterEnv(std::move(p.env)),
      settings_(settings),
      imitation_(std::move(p.imitation)),
      condition_(p.condition),
      target_(runup_target(settings.kind, settings.takeoff_features)),
      foot_(p.foot),
      other_(p.other) {
  early_.fall_bodies = character::fall_bodies_except(model(), {settings.takeoff_foot, settings.other_foot});
  early_.max_com_deviation_m = settings.max_com_deviation_m;
  start_time_s_ = std::min(first_frame(settings, condition_.takeoff_time_s) / settings.control_hz, condition_.takeoff_time_s);
  full_steps_ = std::max(1, static_cast<int>(std::lround((condition_.takeoff_time_s - start_time_s_) * settings.control_hz)));
}

void RunupEnv::reset(std::vector<double>& observation) {
  CharacterEnv::reset(observation);
  handed_over_ = false;
  termination_ = Termination::none;
  end_ = RootMotion{};
  task_reward_ = 0.0;
}

void RunupEnv::on_step(learn::StepResult& out) {
  const character::TrackingErrors errors = imitation_->errors(*this);
  const character::ImitationTerms terms = character::imitation_terms(errors, imitation_->weights());
  out.reward = settings_.imitation_weight * terms.total;
  termination_ = character::early_termination(early_, features(), errors, terms);
  const bool foot_down = features().touches(foot_, sim::Contact::Partner::ground);
  const bool other_down = features().touches(other_, sim::Contact::Partner::ground);
  if (termination_ == Termination::none && takeoff_reached(condition_, reference_time_s(), foot_down, other_down)) {
    handed_over_ = true;
    end_ = root_motion(world().data().q, world().data().qd);
    task_reward_ = runup_task_reward(target_, end_);
    out.reward += settings_.task_weight * full_steps_ * task_reward_;
  }
  out.terminated = handed_over_ || termination_ != Termination::none;
  const Eigen::Vector3d dw = handed_over_ ? Eigen::Vector3d(end_.omega - target_.root_omega) : Eigen::Vector3d::Zero();
  const double dv = handed_over_ && settings_.kind == JumpKind::high_jump ? end_.velocity.y() - target_.lateral_speed : 0.0;
  out.info = {terms.total,
              handed_over_ ? 1.0 : 0.0,
              task_reward_,
              termination_ == Termination::fell ? 1.0 : 0.0,
              termination_ == Termination::deviated ? 1.0 : 0.0,
              dw.x(),
              dw.y(),
              dw.z(),
              dv};
}

std::optional<base::Json> RunupEnv::save_state() const {
  base::Json state = *CharacterEnv::save_state();
  state["runup"] = {
      {"handed_over", handed_over_},
      {"termination", static_cast<int>(termination_)},
      {"end", {end_.omega.x(), end_.omega.y(), end_.omega.z(), end_.velocity.x(), end_.velocity.y(), end_.velocity.z()}},
      {"task_reward", task_reward_}};
  return state;
}

void RunupEnv::load_state(const base::Json& state) {
  CharacterEnv::load_state(state);
  try {
    const base::Json& s = state.at("runup");
    handed_over_ = s.at("handed_over").get<bool>();
    termination_ = static_cast<Termination>(s.at("termination").get<int>());
    const auto e = s.at("end").get<std::vector<double>>();
    end_.omega = Eigen::Vector3d(e.at(0), e.at(1), e.at(2));
    end_.velocity = Eigen::Vector3d(e.at(3), e.at(4), e.at(5));
    task_reward_ = s.at("task_reward").get<double>();
  } catch (const base::Json::exception& e) {
    throw base::UserError(std::string("jump runup env state: ") + e.what());
  }
}

}  // namespace podium::tasks::jump
