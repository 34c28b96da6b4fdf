#pragma once
/// World: one character (a Bullet btMultiBody, double precision, for collision detection) with
/// terrain, contacts, joint limits, and motor control stepped at a simulation and a control
/// frequency; the step's dynamics are ours (sim/README.md "Stepping"). One World per
/// rollout thread; many Worlds may share one ModelPtr. Bullet types stay behind the pimpl.
#include <Eigen/Core>
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
};

struct WorldConfig {
  double sim_hz = 800.0;      ///< physics steps per second (get-up seed: 800)
  double control_hz = 40.0;   ///< control steps per second (get-up seed: 40); must divide sim_hz
  double friction = 1.0;      ///< Coulomb μ between character and ground (seed: 1.0)
  bool self_collision = true;  ///< character links collide with each other (model filter applies)
  bool joint_limits = true;    ///< enforce revolute angle limits
  bool torque_limits = true;   ///< clamp torques to strength × model limits
  double strength = 1.0;       ///< global torque-limit multiplier (the Weaker curriculum's β^i)
  Eigen::Vector3d gravity{0.0, 0.0, -9.81};
  TerrainConfig terrain;
};

/// What one control step did.
struct StepReport {
  bool ok = true;        ///< false once the state held a NaN/Inf (the trial should end failed)
  int bad_dof = -1;      ///< first non-finite velocity DoF, when !ok
  long long bad_step = -1;  ///< simulation step at which it appeared
};

/// Task-level features of the current state (get-up seed App. C; curves get-up paper).
struct Observation {
  double head_height_m = 0.0;             ///< head above the ground below it
  Eigen::Vector3d com = Eigen::Vector3d::Zero();       ///< centre of mass, world, m
  Eigen::Vector3d com_vel = Eigen::Vector3d::Zero();   ///< COM velocity, world, m/s
  Eigen::Vector3d torso_up = Eigen::Vector3d::Zero();  ///< z components of the torso's x, y, z axes
  Eigen::Vector4d root_quat = Eigen::Vector4d::Zero(); ///< root orientation (w, x, y, z)
  std::vector<Eigen::Vector3d> end_effectors;          ///< in the root frame, m (model order)
  std::vector<char> body_contacts;                     ///< per body: touching anything
};

class World {
 public:
  World(ModelPtr model, const WorldConfig& config);
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
  /// Gains for pd / spd_* (defaults to the model's).
  void set_gains(const Gains& gains);

  /// One control period: substeps() simulation steps with the same command.
  StepReport control_step(Control mode, const Eigen::VectorXd& command);
  /// One simulation step.
  StepReport sim_step(Control mode, const Eigen::VectorXd& command);

  Observation observe();
  /// Kinetic energy of the character, J.
  double kinetic_energy();

 private:
  struct Bullet;
  void build_bullet();
  ModelPtr model_;
  WorldConfig config_;
  Terrain terrain_;
  CharacterData data_;
  Gains gains_;
  Eigen::VectorXd limits_;  // torque limits × strength scratch (nv)
  std::unique_ptr<Bullet> bullet_;
  int substeps_ = 1;
  long long step_count_ = 0;
  StepReport failure_;
};

}  // namespace podium::sim
