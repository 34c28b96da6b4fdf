#include "slower_env.h"

#include <algorithm>
#include <cmath>

#include "podium/base/error.h"
#include "podium/character/actions.h"
#include "podium/character/observations.h"

namespace podium::tasks::getup {

using base::Json;

namespace {

std::vector<double> to_vector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }
Eigen::VectorXd to_eigen(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

template <class V>
V lerp(const std::vector<V>& frames, double index) {
  const auto last = static_cast<double>(frames.size() - 1);
  index = std::clamp(index, 0.0, last);
  const auto i = static_cast<std::size_t>(std::floor(index));
  if (i + 1 >= frames.size()) return frames.back();
  const double w = index - static_cast<double>(i);
  return (1.0 - w) * frames[i] + w * frames[i + 1];
}

class SlowerStart final : public character::Start {
 public:
  void begin(character::CharacterEnv& env, base::Rng& rng) const override { static_cast<SlowerEnv&>(env).begin_episode(rng); }
};

// s_slow = [s_weak without β, ŝ'_{t+1}, ŝ'_{t+5}] (§6), ŝ' = [joint pose, h_com, o_torso].
character::CharacterEnvParts slower_parts(const EnvSettings& e, const SlowerSettings& s, const sim::ModelPtr& model) {
  using namespace character;
  CharacterEnvParts p;
  p.model = model;
  p.world.sim_hz = s.sim_hz;  // π_slow's rate; its teacher runs at π_weak's (e.sim_hz)
  p.world.control_hz = e.control_hz;
  p.world.passive_joints = e.passive_joints;
  // The longest episode: τ_fast's cap at the slowest κ, then the standing phase (the reward
  // truncates each episode at its own T/κ + balance_steps).
  p.episode_steps = static_cast<int>(std::ceil(s.max_rise_steps / s.kappa_low)) + s.balance_steps + 1;
  p.action = std::make_unique<ResidualActions>(model, sim::Control::pd, s.residual_bound_rad);
  add_weak_observation(p.observation, model);
  const auto bridge = std::make_shared<PoseBridge>(model);
  const std::size_t frame = bridge->size() + 4;
  p.observation.push_back(
      std::make_unique<TaskScalars>(2 * frame, [bridge, frame](const CharacterEnv& env, std::span<double> out) {
        const SlowReference& ref = static_cast<const SlowerEnv&>(env).reference_motion();
        std::size_t at = 0;
        for (const int ahead : {1, 5}) {
          const double t = env.reference_time_s() + ahead * env.control_dt_s();
          const std::vector<double> pose = bridge->pose(ref.clip()->sample(t));
          std::copy(pose.begin(), pose.end(), out.begin() + static_cast<std::ptrdiff_t>(at));
          out[at + pose.size()] = ref.com_height_m(t);
          const Eigen::Vector3d up = ref.torso_up(t);
          for (int k = 0; k < 3; ++k) out[at + pose.size() + 1 + static_cast<std::size_t>(k)] = up(k);
          at += frame;
        }
      }));
  p.start = std::make_unique<SlowerStart>();
  p.reward = [](const CharacterEnv& env, std::span<const double>, learn::StepResult& out) {
    static_cast<const SlowerEnv&>(env).score(out);
  };
  return p;
}

}  // namespace

std::vector<std::pair<std::string, double>> seed_standing_pose() {
  // tianxintao/get_up_control env.py STANDING_POSE, in humanoid_static.xml's joint order.
  return {{"abdomen_z", 0.0},           {"abdomen_y", -0.11665},       {"abdomen_x", 0.0},
          {"hip_x_right", -0.03601},    {"hip_z_right", -0.03219},     {"hip_y_right", 0.05025},
          {"knee_right", -0.39803},     {"ankle_y_right", -0.30198},   {"ankle_x_right", 0.13615},
          {"hip_x_left", -0.03601},     {"hip_z_left", -0.03219},      {"hip_y_left", 0.05025},
          {"knee_left", -0.39803},      {"ankle_y_left", -0.30198},    {"ankle_x_left", -0.13615},
          {"shoulder1_right", 0.40763}, {"shoulder2_right", -0.41967}, {"elbow_right", -1.5795},
          {"shoulder1_left", -0.40763}, {"shoulder2_left", 0.41967},   {"elbow_left", -1.5795}};
}

Json FastRollout::to_json() const {
  Json j = {{"q", Json::array()}, {"qd", Json::array()}, {"com_height_m", com_height_m}, {"torso_up", Json::array()}};
  for (std::size_t i = 0; i < q.size(); ++i) {
    j["q"].push_back(to_vector(q[i]));
    j["qd"].push_back(to_vector(qd[i]));
    j["torso_up"].push_back({torso_up[i](0), torso_up[i](1), torso_up[i](2)});
  }
  return j;
}

FastRollout FastRollout::from_json(const Json& j) {
  FastRollout f;
  try {
    for (const auto& v : j.at("q")) f.q.push_back(to_eigen(v.get<std::vector<double>>()));
    for (const auto& v : j.at("qd")) f.qd.push_back(to_eigen(v.get<std::vector<double>>()));
    f.com_height_m = j.at("com_height_m").get<std::vector<double>>();
    for (const auto& v : j.at("torso_up"))
      f.torso_up.emplace_back(v.at(0).get<double>(), v.at(1).get<double>(), v.at(2).get<double>());
  } catch (const Json::exception& e) {
    throw base::UserError(std::string("getup slower: saved τ_fast: ") + e.what());
  }
  if (f.q.size() < 2 || f.qd.size() != f.q.size() || f.com_height_m.size() != f.q.size() || f.torso_up.size() != f.q.size())
    throw base::UserError("getup slower: saved τ_fast: frames of unequal counts or fewer than 2");
  return f;
}

SlowReference::SlowReference(FastRollout fast, double kappa, double control_dt_s, const sim::ModelPtr& model,
                             const Eigen::VectorXd& standing_q, double standing_com_m)
    : fast_(std::move(fast)), kappa_(kappa), dt_(control_dt_s), standing_com_(standing_com_m) {
  if (fast_.steps() < 1) throw base::UserError("getup slower: τ_fast has no step");
  if (!(kappa_ > 0.0)) throw base::UserError("getup slower: κ " + std::to_string(kappa_) + " is not > 0");
  character::Clip clip{model, {}, fast_.q, false};
  for (int i = 0; i <= fast_.steps(); ++i) clip.times_s.push_back(i * dt_);
  character::Clip slow = character::retime(clip, kappa_);  // §6: T/κ long, through every frame of τ_fast
  rise_s_ = slow.duration_s();
  Eigen::VectorXd standing = standing_q;
  standing.head<7>() = slow.poses.back().head<7>();  // the root is no PD target; keep it where the rise ended
  slow.times_s.push_back(rise_s_ + dt_);
  slow.poses.push_back(standing);
  clip_ = std::make_shared<const character::Clip>(std::move(slow));
  hip_right_ = model->link("hip_y_right").v_index;
  hip_left_ = model->link("hip_y_left").v_index;
}

double SlowReference::fast_index(double t_s) const { return t_s * kappa_ / dt_; }

double SlowReference::com_height_m(double t_s) const {
  return t_s > rise_s_ + 1e-9 ? standing_com_ : lerp(fast_.com_height_m, fast_index(t_s));
}

Eigen::Vector3d SlowReference::torso_up(double t_s) const {
  return t_s > rise_s_ + 1e-9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d(lerp(fast_.torso_up, fast_index(t_s)));
}

Eigen::Vector2d SlowReference::hip_velocity(double t_s) const {
  if (t_s > rise_s_ + 1e-9) return Eigen::Vector2d::Zero();
  const Eigen::VectorXd qd = lerp(fast_.qd, fast_index(t_s));
  return kappa_ * Eigen::Vector2d(qd(hip_right_), qd(hip_left_));
}

std::pair<Eigen::VectorXd, Eigen::VectorXd> SlowReference::state(double t_s) const {
  return {clip_->sample(std::min(t_s, rise_s_)), kappa_ * lerp(fast_.qd, fast_index(t_s))};
}

std::int64_t rsi_start_step(base::Rng& rng, std::int64_t rise_steps, double epsilon) {
  if (rise_steps < 1 || rng.uniform() < epsilon) return 0;
  return rng.integer(0, rise_steps - 1);
}

SlowerEnv::SlowerEnv(const EnvSettings& env, const SlowerSettings& slower, std::shared_ptr<const learn::FrozenPolicy> weak,
                     double weak_strength, std::optional<double> fixed_kappa)
    : SlowerEnv(env, slower, sim::edit_model(sim::load_shipped_model(env.model), variant_edits(env.variant)), std::move(weak),
                weak_strength, fixed_kappa) {}

SlowerEnv::SlowerEnv(const EnvSettings& env, const SlowerSettings& slower, const sim::ModelPtr& model,
                     std::shared_ptr<const learn::FrozenPolicy> weak, double weak_strength, std::optional<double> fixed_kappa)
    : CharacterEnv(slower_parts(env, slower, model)),
      settings_(slower),
      weak_(std::move(weak)),
      teacher_strength_(std::make_shared<double>(weak_strength)),
      fixed_kappa_(fixed_kappa),
      readings_(BodyReadings::of(*model)) {
  if (!weak_) throw base::UserError("getup slower: no π_weak");
  if (!(settings_.kappa_low > 0.0) || settings_.kappa_high < settings_.kappa_low)
    throw base::UserError("getup slower: κ range [" + std::to_string(settings_.kappa_low) + ", " +
                          std::to_string(settings_.kappa_high) + "] is empty or not > 0");
  teacher_ = std::make_unique<GetupEnv>(env, teacher_strength_, false);
  check_policy_fits(*weak_, *teacher_, "getup slower: π_weak");
  // App. D: PD with k_p = the torque limit (per rad), k_d = k_p/10 over the rise, k_p/5 standing
  // (the seed repository's env.py substep); the full torque limits (its slow env runs at strength
  // 1 while its teacher is weak).
  rise_gains_ = {model->torque_limits(), model->torque_limits() / settings_.rise_kd_ratio};
  standing_gains_ = {model->torque_limits(), model->torque_limits() / settings_.standing_kd_ratio};
  world().set_gains(rise_gains_);
  // The standing pose q̂ (§6: "a single standing pose"; the seed repository's) and h'_com.
  standing_q_ = model->standing_pose();
  const sim::ModelPtr unedited = sim::load_shipped_model(env.model);
  for (const auto& [joint, angle] : settings_.seed_standing ? settings_.standing_pose : decltype(settings_.standing_pose){}) {
    if (const int link = model->find_link(joint); link >= 0) {
      standing_q_(model->links()[static_cast<std::size_t>(link)].q_index) = angle;
    } else if (unedited->find_link(joint) < 0) {
      throw base::UserError("getup slower: standing_pose names joint \"" + joint + "\", which " + env.model + " lacks");
    }
  }
  standing_com_m_ = settings_.standing_com_m;
  if (!settings_.seed_standing) {  // the model's pose, its COM height by one observation
    world().reset(standing_q_, Eigen::VectorXd::Zero(model->nv()));
    standing_com_m_ = world().observe().com.z();
  }
  for (const sim::Link& l : model->links())
    if (l.joint == sim::JointType::revolute && !l.locked) free_joints_.push_back(l.q_index);
  hip_right_ = model->link("hip_y_right").v_index;
  hip_left_ = model->link("hip_y_left").v_index;
}

FastRollout SlowerEnv::rise(base::Rng& rng) {
  std::vector<double> observation, action(teacher_->action_space().size());
  learn::StepResult step;
  for (int attempt = 0; attempt < settings_.rise_attempts; ++attempt) {
    FastRollout fast;
    const auto keep = [&] {
      fast.q.push_back(teacher_->world().data().q);
      fast.qd.push_back(teacher_->world().data().qd);
      fast.com_height_m.push_back(teacher_->features().com.z());
      fast.torso_up.push_back(teacher_->features().torso_up);
    };
    teacher_->seed(rng.next());
    teacher_->reset(observation);  // a fresh fall
    keep();
    int passed_at = -1;  // the first step with the head origin above reference_end_m
    for (int k = 0; k < settings_.max_rise_steps + settings_.reference_end_extra_steps; ++k) {
      if (passed_at < 0 && k >= settings_.max_rise_steps) break;
      weak_->act(observation, action, teacher_->action_scale());
      teacher_->step(action, step);
      if (step.terminated) break;  // a blown-up state
      keep();
      // The seed repository's env.py: the head origin (not its top) past the height, then one more step.
      if (passed_at < 0 && teacher_->weak().head_height_m - readings_.head_top_m > settings_.reference_end_m) passed_at = k;
      if (passed_at >= 0 && k - passed_at >= settings_.reference_end_extra_steps) return fast;
      observation.swap(step.observation);
    }
  }
  throw base::UserError("getup slower: π_weak never lifted the head origin above " + std::to_string(settings_.reference_end_m) +
                        " m within " + std::to_string(settings_.max_rise_steps) + " control steps in " +
                        std::to_string(settings_.rise_attempts) + " falls in a row (at strength " +
                        std::to_string(*teacher_strength_) + "): Slower imitates a policy that gets up");
}

void SlowerEnv::build_reference(FastRollout fast, double kappa) {
  reference_ =
      std::make_unique<SlowReference>(std::move(fast), kappa, control_dt_s(), world().model_ptr(), standing_q_, standing_com_m_);
  set_reference(reference_->clip());
  com_error_sum_ = 0.0;
  rise_steps_ = 0;
  end_com_gap_m_ = 0.0;
}

double SlowerEnv::tracked_fraction() const {
  const auto rise_steps = static_cast<double>(reference_->rise_steps());
  return rise_steps > 0 ? std::min(1.0, rise_steps_ / rise_steps) : 1.0;
}

void SlowerEnv::begin_episode(base::Rng& rng) {
  FastRollout fast = rise(rng);
  if (edit_) fast = edit_(std::move(fast));
  const double kappa = fixed_kappa_ ? *fixed_kappa_ : rng.uniform(settings_.kappa_low, settings_.kappa_high);
  build_reference(std::move(fast), kappa);
  // ε-RSI (§6); a test always starts at the beginning.
  const std::int64_t k = fixed_kappa_ ? 0 : rsi_start_step(rng, reference_->rise_steps(), settings_.rsi_epsilon);
  const double t0 = static_cast<double>(k) * control_dt_s();
  if (k == 0) {
    world().reset(reference_->fast().q.front(), reference_->fast().qd.front());  // the fall's end, exactly
  } else {
    const auto [q, qd] = reference_->state(t0);
    world().reset(q, qd);
  }
  set_reference_time(t0);
}

void SlowerEnv::step(std::span<const double> action, learn::StepResult& out) {
  // The seed repository's env.py substep: k_d = k_p/10 while the step starts inside τ_slow's rise,
  // k_p/5 once it tracks the standing pose.
  world().set_gains(standing_phase() ? standing_gains_ : rise_gains_);
  CharacterEnv::step(action, out);
}

void SlowerEnv::score(learn::StepResult& out) const {
  const double t = reference_time_s();
  const sim::Observation& f = features();
  const double h = f.com.z();
  if (t <= reference_->rise_s() + 1e-9) {  // R_slow (eq. 3)
    SlowState s;
    s.com_height_error_m = h - reference_->com_height_m(t);
    s.torso_up_error = f.torso_up - reference_->torso_up(t);
    const Eigen::VectorXd& qd = world().data().qd;
    const Eigen::Vector2d hips(qd(hip_right_), qd(hip_left_));
    s.hip_velocity_error = hips - reference_->hip_velocity(t);
    out.reward = reward_slow(s);
    com_error_sum_ += std::abs(s.com_height_error_m);
    ++rise_steps_;
    end_com_gap_m_ = -s.com_height_error_m;
    out.terminated = std::abs(s.com_height_error_m) > settings_.track_limit_m;
    return;
  }
  BalanceState b;  // R_balance (eq. 4) after T/κ
  b.com_velocity_xy = f.com_vel.head<2>();
  b.torso_up_z = f.torso_up.z();
  b.com_height_m = h;
  b.com_height_error_m = h - standing_com_m_;
  const Eigen::VectorXd& q = world().data().q;
  for (int i : free_joints_) b.pose_squared_error += (q(i) - standing_q_(i)) * (q(i) - standing_q_(i));
  out.reward = reward_balance(b);
  out.terminated = h < settings_.fall_limit_m;
  out.truncated = t >= reference_->rise_s() + settings_.balance_steps * control_dt_s() - 1e-9;
}

std::optional<Json> SlowerEnv::save_state() const {
  Json state = *CharacterEnv::save_state();
  if (reference_)
    state["slower"] = {{"fast", reference_->fast().to_json()},
                       {"kappa", reference_->kappa()},
                       {"com_error_sum", com_error_sum_},
                       {"rise_steps", rise_steps_},
                       {"end_com_gap", end_com_gap_m_}};
  return state;
}

void SlowerEnv::load_state(const Json& state) {
  CharacterEnv::load_state(state);
  if (!state.contains("slower")) return;
  try {
    const Json& s = state.at("slower");
    build_reference(FastRollout::from_json(s.at("fast")), s.at("kappa").get<double>());
    com_error_sum_ = s.at("com_error_sum").get<double>();
    rise_steps_ = s.at("rise_steps").get<int>();
    end_com_gap_m_ = s.at("end_com_gap").get<double>();
  } catch (const Json::exception& e) {
    throw base::UserError(std::string("getup slower env state: ") + e.what());
  }
}

}  // namespace podium::tasks::getup
