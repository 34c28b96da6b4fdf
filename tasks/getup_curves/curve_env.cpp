#include "curve_env.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>
#include <utility>

#include "podium/base/error.h"
#include "podium/character/actions.h"
#include "podium/character/frames.h"
#include "podium/character/observations.h"
#include "podium/character/starts.h"
#include "podium/sim/dynamics.h"

namespace podium::tasks::getup_curves {

namespace {

constexpr double kMapSpacingM = 0.25;  // §3.2: a 1 m × 1 m grid at 25 cm
constexpr int kDropAttempts = 10;
constexpr std::array<double, 4> kAheadS{0.0, 0.1, 0.2, 0.3};  // §3.3.2: targets 0, 100, 200, 300 ms ahead

const CurveGetupEnv& curve_env(const character::CharacterEnv& env) { return static_cast<const CurveGetupEnv&>(env); }

// §3.3.1's q: every body's rotation in the heading frame as a unit quaternion (w, x, y, z), the
// sign chosen with w ≥ 0 (a quaternion and its negative are one rotation).
class LinkQuaternions final : public character::ObservationPart {
 public:
  std::size_t size(const sim::CharacterModel& model) const override { return 4 * model.bodies().size(); }
  void write(const character::CharacterEnv& env, std::span<double> out) const override {
    const sim::CharacterData& d = env.world().data();
    const Eigen::Matrix3d to_heading = character::heading_rotation(character::heading_yaw(d.links[0].R)).transpose();
    std::size_t at = 0;
    for (const sim::Body& body : env.model().bodies()) {
      Eigen::Quaterniond r(Eigen::Matrix3d(to_heading * d.links[static_cast<std::size_t>(body.link)].R));
      r.normalize();
      if (r.w() < 0.0) r.coeffs() = -r.coeffs();
      out[at++] = r.w(), out[at++] = r.x(), out[at++] = r.y(), out[at++] = r.z();
    }
  }
};

// §3.3.1's w.
void write_features(const character::CharacterEnv& env, std::span<double> out) {
  const StyleFeatures w = curve_env(env).achieved();
  for (int f = 0; f < 3; ++f) out[static_cast<std::size_t>(f)] = w(f);
}

// §3.3.2's t = [t_h t_θx t_θz], each at the four times ahead.
void write_targets(const character::CharacterEnv& env, std::span<double> out) {
  const CurveGetupEnv& e = curve_env(env);
  for (std::size_t k = 0; k < kAheadS.size(); ++k) {
    const StyleFeatures p = e.curve().target(e.curve_time_s() + kAheadS[k]);
    for (std::size_t f = 0; f < 3; ++f) out[f * kAheadS.size() + k] = p(static_cast<Eigen::Index>(f));
  }
}

// §3.3.1's y_{t−1}: the filter's value as the step left it (y_0 after a reset).
void write_previous_action(const character::CharacterEnv& env, std::span<double> out) {
  const Eigen::VectorXd& y = curve_env(env).filtered_action();
  for (Eigen::Index k = 0; k < y.size(); ++k) out[static_cast<std::size_t>(k)] = y(k);
}

// How a filtered action becomes PD targets (§3.4).
std::unique_ptr<character::ActionMap> make_action_map(const CurveEnvSettings& s, const sim::ModelPtr& model) {
  if (s.actions == "targets") return std::make_unique<character::TargetActions>(model, s.control);
  if (s.actions != "cvae") throw base::UserError("curve get-up env: actions \"" + s.actions + "\" is not one of: targets, cvae");
  if (!s.cvae) throw base::UserError("curve get-up env: actions \"cvae\" needs a trained C-VAE (a pose_cvae trial's pose_cvae)");
  const character::PoseBridge bridge(model);
  if (s.cvae->pose_size() != bridge.size() || (s.cvae->condition_size() != 3 && s.cvae->condition_size() != 0))
    throw base::UserError("curve get-up env: the C-VAE decodes " + std::to_string(s.cvae->pose_size()) + " pose entries from " +
                          std::to_string(s.cvae->condition_size()) + " conditions; " + model->name() + " needs " +
                          std::to_string(bridge.size()) + " from 3 (h, θ_x, θ_z), or from none (§6.4's unconditional VAE)");
  // §3.4: c = (p_h, p_θx, p_θz) at the current s.
  return std::make_unique<character::VaeActions>(s.cvae, bridge, s.control, s.latent_bound, s.offset_bound,
                                                 [](const character::CharacterEnv& env) { return curve_env(env).condition(); });
}

int control_steps(double seconds, double control_hz) { return std::max(1, static_cast<int>(std::lround(seconds * control_hz))); }

// Control steps of an episode on `curve`: round((T + T_stand)·control rate).
int curve_episode_steps(const StyleCurve& curve, const CurveEnvSettings& s) {
  return control_steps(curve.duration_s + s.stand_s, s.control_hz);
}

const CurveSet& checked(const std::shared_ptr<const CurveSet>& set) {
  if (!set || set->curves.empty()) throw base::UserError("curve get-up env: no curves");
  if (!set->model) throw base::UserError("curve get-up env: the curve set has no model");
  if (set->clips.size() != set->curves.size())
    throw base::UserError("curve get-up env: the curve set has " + std::to_string(set->clips.size()) + " start clips for " +
                          std::to_string(set->curves.size()) + " curves");
  for (std::size_t k = 0; k < set->curves.size(); ++k)
    if (set->curves[k].start.kind == CurveStart::Kind::clip && !set->clips[k])
      throw base::UserError("curve get-up env: curve \"" + set->curves[k].name + "\" starts in a clip the set has not read");
  return *set;
}

}  // namespace

// The env's Start: draws the episode's curve and begins its start (CurveGetupEnv::begin_episode).
class CurveEpisodeStart final : public character::Start {
 public:
  void begin(character::CharacterEnv& env, base::Rng& rng) const override { static_cast<CurveGetupEnv&>(env).begin_episode(rng); }
};

std::vector<std::string> curve_env_info_names() {
  std::vector<std::string> names{"r_h", "r_theta", "alpha", "r_v", "r_p", "r_task", "r_natural"};  // eqs. 3–9
  for (const char* n : {"h", "theta_x", "theta_z", "target_h", "target_theta_x", "target_theta_z"}) names.emplace_back(n);
  for (const char* n : {"head_on_ground", "low_task_steps", "head_down_steps", "success", "level"}) names.emplace_back(n);
  return names;
}

namespace {

using ClipCache = std::map<std::filesystem::path, std::shared_ptr<const character::Clip>>;

// Appends `curve` and its start clip (read once per file however many curves start in it; a
// relative path resolves against `base_dir`) to `set`.
void add_curve(CurveSet& set, StyleCurve curve, const std::filesystem::path& base_dir, ClipCache& read) {
  std::shared_ptr<const character::Clip> clip;
  if (curve.start.kind == CurveStart::Kind::clip) {
    const std::filesystem::path file = std::filesystem::path(curve.start.clip).is_absolute() || base_dir.empty()
                                           ? std::filesystem::path(curve.start.clip)
                                           : base_dir / curve.start.clip;
    const std::string where = "curve \"" + curve.name + "\": start.clip: \"" + curve.start.clip + "\"";
    if (!std::filesystem::is_regular_file(file)) throw base::UserError(where + " is not a file (" + file.string() + ")");
    auto& slot = read[file];
    if (!slot) slot = std::make_shared<const character::Clip>(character::read_deepmimic_clip(set.model, file));
    clip = slot;
    if (curve.start.frame >= static_cast<int>(clip->size()))
      throw base::UserError("curve \"" + curve.name + "\": start.frame: " + std::to_string(curve.start.frame) +
                            " is past the last frame " + std::to_string(clip->size() - 1) + " of " + file.string());
  }
  set.clips.push_back(std::move(clip));
  set.curves.push_back(std::move(curve));
}

}  // namespace

std::shared_ptr<const CurveSet> make_curve_set(std::vector<StyleCurve> curves, const sim::ModelPtr& model,
                                               const std::filesystem::path& base_dir) {
  if (!model) throw base::UserError("curve set: no model");
  auto set = std::make_shared<CurveSet>();
  set->model = model;
  ClipCache read;
  for (StyleCurve& curve : curves) add_curve(*set, std::move(curve), base_dir, read);
  return set;
}

std::shared_ptr<const CurveSet> load_curve_set(const std::vector<std::filesystem::path>& files, const sim::ModelPtr& model) {
  if (files.empty()) throw base::UserError("curve set: no curve files");
  if (!model) throw base::UserError("curve set: no model");
  auto set = std::make_shared<CurveSet>();
  set->model = model;
  ClipCache read;  // across files: curves authored on one clip share it
  for (const std::filesystem::path& file : files) {
    try {
      add_curve(*set, load_style_curve(file), file.parent_path(), read);
    } catch (const base::ConfigError&) {
      throw;  // already "<file>: <JSON path>: <value> ..."
    } catch (const base::UserError& e) {
      throw base::UserError(file.string() + ": " + e.what());
    }
  }
  return set;
}

struct CurveGetupEnv::Parts {
  character::CharacterEnvParts env;
  std::vector<ObservationBlock> blocks;
};

CurveGetupEnv::Parts CurveGetupEnv::make_parts(const CurveEnvSettings& s, const CurveSet& set) {
  Parts p;
  character::CharacterEnvParts& e = p.env;
  const sim::ModelPtr& model = set.model;
  e.model = model;
  e.world.sim_hz = s.sim_hz;
  e.world.control_hz = s.control_hz;
  e.world.terrain = terrain_config(s.terrain);  // §3.2: flat, then the harder regions
  // The longest curve's length; each episode ends at its own curve's (on_step).
  e.episode_steps = 1;
  for (const StyleCurve& c : set.curves) e.episode_steps = std::max(e.episode_steps, curve_episode_steps(c, s));
  e.action = make_action_map(s, model);
  const auto add = [&](std::string name, std::unique_ptr<character::ObservationPart> part) {
    const std::size_t at = p.blocks.empty() ? 0 : p.blocks.back().offset + p.blocks.back().size;
    p.blocks.push_back({std::move(name), at, part->size(*model)});
    e.observation.push_back(std::move(part));
  };
  add("q", std::make_unique<LinkQuaternions>());
  add("p_v_omega", std::make_unique<character::LinkStates>(
                       character::LinkStates::Blocks{.positions = true, .rotations = false, .velocities = true}));
  add("w", std::make_unique<character::TaskScalars>(3, write_features));
  add("height_map", std::make_unique<character::HeightMap>(kMapSpacingM));
  add("targets", std::make_unique<character::TaskScalars>(3 * kAheadS.size(), write_targets));
  add("previous_action", std::make_unique<character::TaskScalars>(e.action->space(*model).size(), write_previous_action));
  e.start = std::make_unique<CurveEpisodeStart>();
  e.reward = [](character::CharacterEnv& env, std::span<const double> y, learn::StepResult& out) {
    static_cast<CurveGetupEnv&>(env).on_step(y, out);
  };
  e.info_names = curve_env_info_names();
  return p;
}

CurveGetupEnv::CurveGetupEnv(const CurveEnvSettings& settings, const std::shared_ptr<const CurveSet>& curves)
    : CurveGetupEnv(settings, curves, make_parts(settings, checked(curves))) {}

CurveGetupEnv::CurveGetupEnv(const CurveEnvSettings& settings, std::shared_ptr<const CurveSet> curves, Parts parts)
    : CharacterEnv(std::move(parts.env)),
      settings_(settings),
      curves_(std::move(curves)),
      features_reader_(model()),
      bridge_(curves_->model),
      filter_(static_cast<Eigen::Index>(action_space().size()), settings.filter_beta),
      termination_(control_dt_s()),
      blocks_(std::move(parts.blocks)),
      success_steps_(control_steps(settings.success_window_s, settings.control_hz)) {
  if (!(settings.stand_s >= 0.0))
    throw base::UserError("curve get-up env: stand_s " + std::to_string(settings.stand_s) + " is not ≥ 0");
  episode_length_ = curve_episode_steps(curve(), settings_);
  set_standing_share(settings.standing_share);
  if (!(settings.standing_tail_s >= 0.0))
    throw base::UserError("curve get-up env: standing tail " + std::to_string(settings.standing_tail_s) + " s is not ≥ 0");
  for (const auto& clip : curves_->clips)
    if (clip && std::find(standing_clips_.begin(), standing_clips_.end(), clip) == standing_clips_.end())
      standing_clips_.push_back(clip);
  if (!(settings.curve_filter_rad >= 0.0))
    throw base::UserError("curve get-up env: curve filter " + std::to_string(settings.curve_filter_rad) + " rad is not ≥ 0");
}

void CurveGetupEnv::use_curve(int index) {
  if (index < -1 || index >= static_cast<int>(curves_->curves.size()))
    throw base::UserError("curve get-up env: curve " + std::to_string(index) + " is not one of the " +
                          std::to_string(curves_->curves.size()) + " curves (−1: drawn)");
  fixed_curve_ = index;
}

void CurveGetupEnv::set_open_levels(int n) {
  if (n < 1 || n > settings_.terrain.levels)
    throw base::UserError("curve get-up env: " + std::to_string(n) + " open levels of " +
                          std::to_string(settings_.terrain.levels));
  open_levels_ = n;
}

void CurveGetupEnv::use_level(int level) {
  if (level < -1 || level >= settings_.terrain.levels)
    throw base::UserError("curve get-up env: level " + std::to_string(level) + " is not one of the " +
                          std::to_string(settings_.terrain.levels) + " (−1: drawn)");
  fixed_level_ = level;
}

std::vector<std::pair<int, bool>> CurveGetupEnv::take_finished() { return std::exchange(finished_, {}); }

void CurveGetupEnv::set_standing_share(double share) {
  if (!(share >= 0.0 && share <= 1.0))
    throw base::UserError("curve get-up env: standing share " + std::to_string(share) + " is not in [0, 1]");
  standing_share_ = share;
}

// §5.2: "curves are filtered to have angles less than 30° from the initial orientation of the
// torso": after a drop, the drawn curve is kept when its p_θx(0) and p_θz(0) are both within the
// filter's angle of the torso's; else one of the curves that are is drawn (none: it is kept).
void CurveGetupEnv::filter_curve(base::Rng& rng) {
  const StyleFeatures w = achieved();
  const auto near = [&](const StyleCurve& c) {
    const StyleFeatures p = c.at(0.0);
    return std::abs(p(1) - w(1)) <= settings_.curve_filter_rad && std::abs(p(2) - w(2)) <= settings_.curve_filter_rad;
  };
  if (fixed_curve_ >= 0 || near(curve())) return;
  std::vector<int> eligible;
  for (std::size_t k = 0; k < curves_->curves.size(); ++k)
    if (curves_->curves[k].start.kind == CurveStart::Kind::drop && near(curves_->curves[k]))
      eligible.push_back(static_cast<int>(k));
  if (eligible.empty()) return;
  curve_ = eligible[static_cast<std::size_t>(rng.integer(0, static_cast<std::int64_t>(eligible.size()) - 1))];
  episode_length_ = curve_episode_steps(curve(), settings_);
}

namespace {

// The terrain's surface normal under (x, y): from the height's slope over ±1 cm; a step steeper
// than 40° is a rough tile's edge, whose tops are level, so the normal is vertical there.
Eigen::Vector3d surface_normal(const sim::Terrain& terrain, double x, double y) {
  constexpr double d = 0.01;
  const double gx = (terrain.height(x + d, y) - terrain.height(x - d, y)) / (2 * d);
  const double gy = (terrain.height(x, y + d) - terrain.height(x, y - d)) / (2 * d);
  if (std::hypot(gx, gy) > std::tan(40.0 * std::numbers::pi / 180.0)) return Eigen::Vector3d::UnitZ();
  return Eigen::Vector3d(-gx, -gy, 1.0).normalized();
}

// The eight corners of a link's box geoms in the world (forward kinematics done on `d`).
std::vector<Eigen::Vector3d> box_corners(const sim::CharacterModel& model, const sim::CharacterData& d, int link) {
  std::vector<Eigen::Vector3d> corners;
  for (const sim::Geom& g : model.links()[static_cast<std::size_t>(link)].geoms) {
    if (g.type != sim::ShapeType::box) continue;
    for (int k = 0; k < 8; ++k) {
      const Eigen::Vector3d c((k & 1 ? 1 : -1) * g.half_extents.x(), (k & 2 ? 1 : -1) * g.half_extents.y(),
                              (k & 4 ? 1 : -1) * g.half_extents.z());
      const auto& l = d.links[static_cast<std::size_t>(link)];
      corners.push_back(l.p + l.R * (g.pos + g.rot * c));
    }
  }
  return corners;
}

}  // namespace

// §5.2 (ii) off flat: each foot turned about its ankle so that its sole lies along the surface under
// the foot's centre, then the character lifted so that no foot corner is below the surface (the
// lower foot touches it; on rough tiles the other may hover by a tile's step).
void CurveGetupEnv::place_feet(Eigen::VectorXd& q) {
  const sim::CharacterModel& m = model();
  const sim::Terrain& terrain = world().terrain();
  sim::CharacterData d(m);
  d.q = q;
  sim::forward_kinematics(m, d);
  for (const char* ankle : {"right_ankle", "left_ankle"}) {
    const int link = m.find_link(ankle);
    const sim::Link& l = m.links()[static_cast<std::size_t>(link)];
    const auto& foot = d.links[static_cast<std::size_t>(link)];
    const Eigen::Vector3d centre = foot.p + foot.R * l.geoms.front().pos;
    const Eigen::Vector3d up = foot.R.col(2);  // the sole's normal: links are parallel to the world at q = 0
    const Eigen::Quaterniond tilt = Eigen::Quaterniond::FromTwoVectors(up, surface_normal(terrain, centre.x(), centre.y()));
    const Eigen::Matrix3d& parent = d.links[static_cast<std::size_t>(l.parent)].R;
    const Eigen::Quaterniond joint = character::quat_at(q, l.q_index);
    character::set_quat(q, l.q_index,
                        (Eigen::Quaterniond(parent.transpose() * tilt.toRotationMatrix() * parent) * joint).normalized());
  }
  d.q = q;
  sim::forward_kinematics(m, d);
  double lift = -std::numeric_limits<double>::infinity();
  for (const char* ankle : {"right_ankle", "left_ankle"})
    for (const Eigen::Vector3d& c : box_corners(m, d, m.find_link(ankle)))
      lift = std::max(lift, terrain.height(c.x(), c.y()) - c.z());
  q(2) += lift;
}

// §5.2 (ii): a standing start, entered at the curve's standing part (s = 1 from the first step)
// for T_stand. On flat, "a standing pose selected from one of the reference motion clips": a clip
// drawn uniformly among the set's, a time uniform in its last standing_tail_s, its pose (with a
// clip start's joint noise) and velocities. Otherwise (off flat, no clip, or a tail of 0) the
// model's standing pose turned uniformly: on flat at the origin, on a harder level at a drop site
// with its feet on the surface (place_feet; the seed: "the feet of the character are re-oriented
// to match the local terrain slope").
void CurveGetupEnv::begin_standing(base::Rng& rng) {
  time_offset_s_ = curve().duration_s;
  episode_length_ = control_steps(settings_.stand_s, settings_.control_hz);
  if (level_ == 0 && settings_.standing_tail_s > 0.0 && !standing_clips_.empty()) {
    const auto& clip =
        standing_clips_[static_cast<std::size_t>(rng.integer(0, static_cast<std::int64_t>(standing_clips_.size()) - 1))];
    const double end = clip->duration_s();
    set_reference(clip);
    character::ReferenceStart(settings_.clip_start_noise_rad, false,
                              rng.uniform(std::max(0.0, end - settings_.standing_tail_s), end))
        .begin(*this, rng);
    set_reference(curves_->clips[static_cast<std::size_t>(curve_)]);
    return;
  }
  Eigen::VectorXd q = model().standing_pose();
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(rng.uniform(-std::numbers::pi, std::numbers::pi), Eigen::Vector3d::UnitZ()));
  const Eigen::Quaterniond root = turn * Eigen::Quaterniond(q(3), q(4), q(5), q(6));
  q(0) = q(1) = 0.0;
  q(3) = root.w(), q(4) = root.x(), q(5) = root.y(), q(6) = root.z();
  if (level_ > 0) {
    const DropSite site = drop_site(settings_.terrain, level_, rng);
    q(0) = site.x_m, q(1) = site.y_m;
    place_feet(q);
  }
  world().set_state(q, Eigen::VectorXd::Zero(model().nv()));
}

void CurveGetupEnv::begin_episode(base::Rng& rng) {
  const int n = static_cast<int>(curves_->curves.size());
  curve_ = fixed_curve_ >= 0 ? fixed_curve_ : static_cast<int>(rng.integer(0, n - 1));
  // §5.4: a level among the open ones (nothing drawn while only flat is open); §5.2: a clip start on flat.
  level_ = fixed_level_ >= 0 ? fixed_level_ : open_levels_ > 1 ? static_cast<int>(rng.integer(0, open_levels_ - 1)) : 0;
  if (curve().start.kind == CurveStart::Kind::clip) level_ = 0;
  // §5.2 (ii): a standing start, on any level (nothing drawn with a share of 0).
  standing_ = standing_share_ > 0.0 && rng.uniform(0.0, 1.0) < standing_share_;
  episode_length_ = curve_episode_steps(curve(), settings_);
  time_offset_s_ = 0.0;
  termination_.reset();
  standing_steps_ = 0;
  success_ = false;
  terms_ = StyleRewardTerms{};
  const CurveStart& start = curve().start;
  const std::shared_ptr<const character::Clip>& clip = curves_->clips[static_cast<std::size_t>(curve_)];
  set_reference(clip);
  if (standing_) {
    begin_standing(rng);
  } else if (start.kind == CurveStart::Kind::clip) {
    // §5.5: "the initial posture of each reference motion is used to initialize the character".
    character::ReferenceStart(settings_.clip_start_noise_rad, false, clip->times_s.at(static_cast<std::size_t>(start.frame)))
        .begin(*this, rng);
  } else {
    // §5.2: a passive rag-doll dropped prone or supine. A drop whose random pose blows up (at
    // 600 Hz, 1 of 30 seeds each way) is drawn again; should every attempt fail, the first step
    // ends the episode as CharacterEnv does for any non-finite state.
    sim::RagdollStart fall = settings_.drop;
    fall.lying = start.supine ? sim::RagdollStart::Lying::supine : sim::RagdollStart::Lying::prone;
    const DropSite site = drop_site(settings_.terrain, level_, rng);  // §5.2: at a random location of the region
    fall.x_m = site.x_m, fall.y_m = site.y_m;
    for (int attempt = 0; attempt < kDropAttempts; ++attempt)
      if (sim::ragdoll_start(world(), rng, fall).ok) break;
    if (settings_.curve_filter_rad > 0.0) {
      filter_curve(rng);
      set_reference(curves_->clips[static_cast<std::size_t>(curve_)]);
    }
  }
  // y_0: the action that holds the start's pose ("targets": its pose; "cvae": its encoding, Δq = 0), within the box.
  std::vector<double> pose = bridge_.pose(world().data().q);
  if (settings_.cvae && settings_.actions == "cvae") {
    std::vector<double> z = settings_.cvae->encode(pose, condition());
    z.resize(action_space().size(), 0.0);
    pose = std::move(z);
  }
  const learn::BoxSpace box = action_space();
  Eigen::VectorXd y(static_cast<Eigen::Index>(pose.size()));
  for (std::size_t k = 0; k < pose.size(); ++k) y(static_cast<Eigen::Index>(k)) = std::clamp(pose[k], box.low[k], box.high[k]);
  filter_.set_value(y);
}

void CurveGetupEnv::step(std::span<const double> action, learn::StepResult& out) {
  if (action.size() != action_space().size()) {
    CharacterEnv::step(action, out);  // throws, naming both sizes
    return;
  }
  const Eigen::VectorXd& y =
      filter_.step(Eigen::Map<const Eigen::VectorXd>(action.data(), static_cast<Eigen::Index>(action.size())));
  CharacterEnv::step(std::span<const double>(y.data(), static_cast<std::size_t>(y.size())), out);
}

double CurveGetupEnv::ground_height_m() const {
  const sim::LinkData& root = world().data().links[0];
  const auto map = world().terrain().height_map(root.p.x(), root.p.y(), character::heading_yaw(root.R), kMapSpacingM, 0.0);
  double sum = 0.0;
  for (double z : map) sum += z;
  return sum / static_cast<double>(map.size());
}

StyleFeatures CurveGetupEnv::achieved() const { return features_reader_(world().data(), ground_height_m()); }

double CurveGetupEnv::angular_speed_norm() const {
  std::vector<Eigen::Vector3d> omega, velocity;
  character::link_velocities(model(), world().data(), omega, velocity);
  double squared = 0.0;
  for (const Eigen::Vector3d& w : omega) squared += w.squaredNorm();
  return std::sqrt(squared);
}

double CurveGetupEnv::offset_l1(std::span<const double> y) const {
  if (settings_.actions != "cvae") return 0.0;  // "targets": no Δq
  double sum = 0.0;
  for (std::size_t k = settings_.cvae->latent_size(); k < y.size(); ++k) sum += std::abs(y[k]);
  return sum;
}

std::vector<double> CurveGetupEnv::condition() const {
  if (settings_.cvae && settings_.cvae->condition_size() == 0) return {};  // §6.4's unconditional pose VAE
  const StyleFeatures p = curve().target(curve_time_s());
  return {p(0), p(1), p(2)};
}

std::vector<double> CurveGetupEnv::target_pose(std::span<const double> y) const {
  if (settings_.actions == "cvae") return learn::pose_action_to_target(*settings_.cvae, y, condition());
  std::vector<double> pose(y.begin(), y.end());
  for (std::size_t k = 0; k < pose.size(); ++k) pose[k] = std::clamp(pose[k], bridge_.lower()[k], bridge_.upper()[k]);
  return pose;
}

void CurveGetupEnv::on_step(std::span<const double> y, learn::StepResult& out) {
  const StyleCurve& c = curve();
  StyleRewardInput in;
  in.achieved = achieved();
  in.target = c.target(curve_time_s());  // eq. 1 with t0 = the episode's start
  in.final_target_h = c.at(1.0)(0);
  in.angular_speed_norm = angular_speed_norm();
  in.rotation_distance_sum = joint_rotation_distance(model(), world().data().q, model().standing_pose());
  in.offset_l1 = offset_l1(y);
  in.offset_scale = settings_.offset_scale;
  terms_ = style_rewards(in);  // eqs. 2–9
  const bool head_down = features().touches(model().head_body(), sim::Contact::Partner::ground);
  const bool ended = termination_.step(terms_.task, head_down);  // §5.3
  standing_steps_ = in.achieved(0) >= settings_.success_height_fraction * in.final_target_h ? standing_steps_ + 1 : 0;
  out.reward = terms_.total;
  out.terminated = settings_.early_termination && ended;
  const bool last = step_index() >= episode_length_;
  out.truncated = last;  // CharacterEnv keeps it only when not terminated
  success_ = last && !out.terminated && standing_steps_ >= success_steps_;
  if ((out.terminated || last) && !standing_) finished_.emplace_back(level_, success_);  // the curriculum counts get-ups
  out.info = {terms_.height, terms_.torso, terms_.alpha, terms_.velocity, terms_.pose, terms_.task, terms_.natural};
  for (int f = 0; f < 3; ++f) out.info.push_back(in.achieved(f));
  for (int f = 0; f < 3; ++f) out.info.push_back(in.target(f));
  out.info.push_back(head_down ? 1.0 : 0.0);
  out.info.push_back(termination_.low_reward_steps());
  out.info.push_back(termination_.head_down_steps());
  out.info.push_back(success_ ? 1.0 : 0.0);
  out.info.push_back(level_);
}

std::optional<base::Json> CurveGetupEnv::save_state() const {
  base::Json state = *CharacterEnv::save_state();
  const Eigen::VectorXd& y = filter_.value();
  state["curve_env"] = {{"curve", curve_},
                        {"filter", std::vector<double>(y.data(), y.data() + y.size())},
                        {"low_task_steps", termination_.low_reward_steps()},
                        {"head_down_steps", termination_.head_down_steps()},
                        {"standing_steps", standing_steps_},
                        {"success", success_},
                        {"level", level_},
                        {"open_levels", open_levels_},
                        {"standing", standing_},
                        {"time_offset_s", time_offset_s_}};
  return state;
}

void CurveGetupEnv::load_state(const base::Json& state) {
  int index = 0, low = 0, head = 0, standing_steps = 0, level = 0, open = 1;
  bool standing = false;
  double offset = 0.0;
  std::vector<double> y;
  bool success = false;
  try {
    const base::Json& s = state.at("curve_env");
    index = s.at("curve").get<int>();
    y = s.at("filter").get<std::vector<double>>();
    low = s.at("low_task_steps").get<int>();
    head = s.at("head_down_steps").get<int>();
    standing_steps = s.at("standing_steps").get<int>();
    success = s.at("success").get<bool>();
    level = s.value("level", 0), open = s.value("open_levels", 1);
    standing = s.value("standing", false), offset = s.value("time_offset_s", 0.0);
  } catch (const base::Json::exception& e) {
    throw base::UserError(std::string("curve get-up env state: ") + e.what());
  }
  if (index < 0 || index >= static_cast<int>(curves_->curves.size()))
    throw base::UserError("curve get-up env state: curve_env.curve: " + std::to_string(index) + " is not one of the " +
                          std::to_string(curves_->curves.size()) + " curves");
  if (y.size() != action_space().size())
    throw base::UserError("curve get-up env state: curve_env.filter: " + std::to_string(y.size()) + " values, the action has " +
                          std::to_string(action_space().size()));
  if (level < 0 || level >= settings_.terrain.levels || open < 1 || open > settings_.terrain.levels)
    throw base::UserError("curve get-up env state: curve_env.level " + std::to_string(level) + " or open_levels " +
                          std::to_string(open) + " outside the " + std::to_string(settings_.terrain.levels) + " levels");
  CharacterEnv::load_state(state);
  curve_ = index;
  episode_length_ = curve_episode_steps(curve(), settings_);
  set_reference(curves_->clips[static_cast<std::size_t>(curve_)]);
  filter_.set_value(Eigen::Map<const Eigen::VectorXd>(y.data(), static_cast<Eigen::Index>(y.size())));
  termination_.restore(low, head);
  standing_steps_ = standing_steps;
  success_ = success;
  standing_ = standing, time_offset_s_ = offset;
  if (standing_) episode_length_ = control_steps(settings_.stand_s, settings_.control_hz);
  level_ = level, open_levels_ = open;
}

}  // namespace podium::tasks::getup_curves
