#pragma once
/// World: one character (a Bullet btMultiBody, double precision, for collision detection) with
/// terrain, contacts, joint limits, and motor control stepped at a simulation and a control
/// frequency; the step's dynamics are ours (sim/README.md "Stepping"). One World per
/// rollout thread; many Worlds may share one ModelPtr. Bullet types stay behind the pimpl.
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <vector>

#include "podium/sim/data.h"
#include "podium/sim/dynamics.h"
#include "podium/sim/model.h"
#include "podium/sim/terrain.h"

namespace podium::sim {

/// How a control command becomes joint torques each simulation step.
enum class Control {
  torque,     ///< command = joint torques (nv; root entries ignored), N·m
  pd,         ///< command = targets q̄ (nq); explicit PD
  spd_dense,  ///< command = targets q̄ (nq); stable PD by dense factorisation
  spd_maba,   ///< command = targets q̄ (nq); stable PD by MABA
  /// command = targets q̄ (nq); the PD inside the velocity solve: the springs and dampers implicit
  /// with the contacts and limits (as Vortex's joint motors and MuJoCo's implicit damping):
  /// τ = −Kp(q + Δt q̇⁺ − q̄) − Kd q̇⁺ with q̇⁺ the step's new velocity, i.e. the contact solve runs
  /// on M + Δt Kd + Δt² Kp. A joint whose stable-PD torque (spd_maba's, without contacts) passes its
  /// limit gets that torque clamped, explicitly. data().tau reports the torque applied.
  spd_implicit,
};

struct WorldConfig {
  double sim_hz = 800.0;       ///< physics steps per second (get-up seed: 800)
  double control_hz = 40.0;    ///< control steps per second (get-up seed: 40); must divide sim_hz
  double friction = 1.0;       ///< Coulomb μ of the character (ground: μ; a prop: μ × its friction); set_friction changes it
  bool self_collision = true;  ///< character links collide with each other (model filter applies)
  bool joint_limits = true;    ///< enforce revolute angle limits
  bool torque_limits = true;   ///< clamp torques to strength × model limits
  double strength = 1.0;       ///< global torque-limit multiplier (the Weaker curriculum's β^i)
  /// Apply the model's passive joint damping and stiffness (Link::damping, stiffness) every
  /// simulation step, in every control mode (SPD's implicit step does not see them).
  bool passive_joints = false;
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};
  TerrainConfig terrain;  ///< set_terrain changes it between episodes
  ModelEdits edits;       ///< applied to the model when the World is built (World::model() is the edited one)
};

/// What one control step did.
struct StepReport {
  bool ok = true;           ///< false once a velocity was NaN/Inf or beyond 1000 m/s or rad/s (a blown-up state)
  int bad_dof = -1;         ///< first such velocity DoF, when !ok
  long long bad_step = -1;  ///< simulation step at which it appeared
};

/// What a body touches. `index`: the prop (TerrainConfig::boxes), the other body, or for the
/// ground the terrain region (−1: the plane outside all regions).
struct Contact {
  enum class Partner { ground, prop, body };
  int body = 0;
  Partner partner = Partner::ground;
  int index = -1;
  bool operator==(const Contact&) const = default;
};

/// Wind drag on a body (F = ½ ρ C_d A |v_rel| v_rel, v_rel = wind − the body centroid's velocity,
/// A = the area of the body's geoms projected on the plane normal to v_rel, overlaps counted twice).
struct Wind {
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();  ///< m/s, world
  double air_density = 1.2;                            ///< ρ, kg/m³ (sea level, 20 °C)
  double drag_coefficient = 1.0;                       ///< C_d (a sprinter's body ≈ 1.0–1.2)
};

struct WorldSnapshot;

/// Task-level features of the current state (get-up seed App. C; curves get-up paper).
struct Observation {
  double head_height_m = 0.0;                           ///< head above the ground below it
  Eigen::Vector3d com = Eigen::Vector3d::Zero();        ///< centre of mass, world, m
  Eigen::Vector3d com_vel = Eigen::Vector3d::Zero();    ///< COM velocity, world, m/s
  Eigen::Vector3d torso_up = Eigen::Vector3d::Zero();   ///< z components of the torso's x, y, z axes
  Eigen::Vector4d root_quat = Eigen::Vector4d::Zero();  ///< root orientation (w, x, y, z)
  std::vector<Eigen::Vector3d> end_effectors;           ///< in the root frame, m (model order)
  std::vector<char> body_contacts;                      ///< per body: touching anything
  std::vector<Contact> contacts;                        ///< each (body, partner, index) touching, once, sorted
  /// Whether `body` touches `partner` (index −1: any of that kind).
  bool touches(int body, Contact::Partner partner, int index = -1) const;
};

class World {
 public:
  World(const ModelPtr& model, const WorldConfig& config);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  const CharacterModel& model() const { return *model_; }
  const ModelPtr& model_ptr() const { return model_; }
  const WorldConfig& config() const { return config_; }
  const Terrain& terrain() const { return terrain_; }
  /// State mirror (q, qd) after the last step, and the last applied torques (tau).
  const CharacterData& data() const { return data_; }
  int substeps() const { return substeps_; }
  double dt_s() const { return 1.0 / config_.sim_hz; }
  double time_s() const { return static_cast<double>(step_count_) / config_.sim_hz; }

  /// Starts an episode: rebuilds the Bullet world (contact caches, warm starts, pair order) and
  /// sets the state, so what follows depends only on (q, qd), not on earlier episodes.
  void reset(const Eigen::VectorXd& q, const Eigen::VectorXd& qd);
  /// Sets the full state (q: nq, qd: nv in the model's coordinates; see sim/README.md); keeps
  /// Bullet's contact caches (cheap; for kinematic replay and mid-episode edits).
  void set_state(const Eigen::VectorXd& q, const Eigen::VectorXd& qd);
  /// Sets the state from world-frame root velocities (ω, v of the root origin) and joint rates.
  void set_state_world(const Eigen::VectorXd& q, const Eigen::Vector3d& root_omega_world, const Eigen::Vector3d& root_vel_world,
                       const Eigen::VectorXd& joint_qd);
  void set_strength(double strength) { config_.strength = strength; }
  /// Per-episode friction μ (takes effect at once; contact warm starts restart).
  void set_friction(double mu);
  /// Moves, resizes, adds or removes props and regions (e.g. a bar-height curriculum); keeps the
  /// character's state; contact warm starts restart. Throws base::UserError for a bad config.
  void set_terrain(const TerrainConfig& terrain);
  /// An external force (N, world) on `body` at its centroid (geom volumes), applied every
  /// simulation step in every control mode until changed; SPD's implicit step does not see it.
  void set_external_force(int body, const Eigen::Vector3d& force_world);
  const Eigen::Vector3d& external_force(int body) const { return forces_.at(body); }
  /// Sets every body's external force to its wind drag at the current state (call per control step).
  void apply_wind(const Wind& wind);
  Eigen::Vector3d wind_force(int body, const Wind& wind);
  /// World position (m) and velocity (m/s) of a body's centroid.
  Eigen::Vector3d body_centroid(int body) const;
  Eigen::Vector3d body_centroid_velocity(int body);
  /// Distance (m) between a body's geoms and prop `prop` (negative: penetration depth).
  double prop_distance(int body, int prop) const;

  /// Everything the following steps depend on (state, contact warm starts, friction, strength,
  /// gains, forces, terrain); contact detection keeps no memory between steps, so a restored
  /// World steps bitwise as the original did. Restoring rebuilds the collision world; it needs the
  /// same model (and edits) and rates, else base::UserError.
  WorldSnapshot snapshot() const;
  void restore(const WorldSnapshot& snapshot);
  /// Gains for pd / spd_* (defaults to the model's).
  void set_gains(const Gains& gains);
  const Gains& gains() const { return gains_; }

  /// One control period: substeps() simulation steps with the same command.
  StepReport control_step(Control mode, const Eigen::VectorXd& command);
  /// Called by control_step after each of its simulation steps (e.g. a recorder taking the states
  /// between control steps); it must not change the World. Not part of a snapshot; empty: none.
  void set_substep_observer(std::function<void(World&)> observer) { substep_observer_ = std::move(observer); }
  /// The observer set now (empty: none).
  const std::function<void(World&)>& substep_observer() const { return substep_observer_; }
  /// One simulation step.
  StepReport sim_step(Control mode, const Eigen::VectorXd& command);

  /// Features and contacts at the current pose (runs contact detection; does not change what the
  /// next step does).
  Observation observe();
  /// Kinetic energy of the character, J.
  double kinetic_energy();

 private:
  struct Bullet;
  void build_bullet();
  void rebuild_keeping_state();  // after a config change: fresh Bullet world at data_'s pose
  ModelPtr model_;
  WorldConfig config_;
  Terrain terrain_;
  CharacterData data_;
  Gains gains_;
  Eigen::VectorXd limits_;                // torque limits × strength scratch (nv)
  Eigen::VectorXd implicit_, qd_before_;  // spd_implicit: the diagonal added to M, q̇ at the step's start (nv)
  void implicit_pd(const Eigen::VectorXd& target);
  std::unique_ptr<Bullet> bullet_;
  int substeps_ = 1;
  long long step_count_ = 0;
  StepReport failure_;
  std::vector<Eigen::Vector3d> forces_;     // per body, world, N
  std::vector<Eigen::Vector3d> centroids_;  // per body, in its link's frame
  Eigen::VectorXd tau_external_;            // passive joint torques + Jᵀ F over all bodies (nv)
  bool has_forces_ = false;
  std::vector<int> passive_links_;  // revolute links with damping or stiffness, when applied
  std::function<void(World&)> substep_observer_;
};

struct WarmStarts;  // the contact solver's (src/contact_solver.h)

/// What World::restore needs, by value (opaque; copy it freely, restore it into any World of the
/// same model and rates).
struct WorldSnapshot {
  /// The snapshot as JSON, exact: finite doubles as numbers (nlohmann writes the shortest text
  /// that reads back to the same bits), non-finite ones as "nan", "inf", "-inf"; the model as its
  /// name and a fingerprint of its model-file JSON. For checkpoints that resume across processes.
  base::Json to_json() const;
  /// Reads to_json's output for a World of `model` (the World's own, World::model_ptr()). The
  /// caches are recomputed from the state (forward kinematics), as every step leaves them.
  /// Throws base::UserError naming the field, or when the snapshot is of another model.
  static WorldSnapshot from_json(const base::Json& json, const ModelPtr& model);

 private:
  friend class World;
  explicit WorldSnapshot(const CharacterData& d) : data(d) {}
  ModelPtr model;
  WorldConfig config;
  CharacterData data;
  Gains gains;
  long long step_count = 0;
  StepReport failure;
  std::vector<Eigen::Vector3d> forces;
  std::shared_ptr<const WarmStarts> warm;
};

/// Adds an observer after the world's own for its lifetime (e.g. a recorder over an episode, while
/// a task's finish line keeps observing), then puts the world's back. The world must outlive it.
class ScopedSubstepObserver {
 public:
  ScopedSubstepObserver(World& world, std::function<void(World&)> observer);
  ~ScopedSubstepObserver() { world_.set_substep_observer(std::move(previous_)); }
  ScopedSubstepObserver(const ScopedSubstepObserver&) = delete;
  ScopedSubstepObserver& operator=(const ScopedSubstepObserver&) = delete;

 private:
  World& world_;
  std::function<void(World&)> previous_;
};

}  // namespace podium::sim
