// World: a CharacterModel as a Bullet btMultiBody in a btCollisionWorld with terrain, and motor
// control (torque, PD, SPD dense/MABA) applied every simulation step. Bullet finds contacts;
// ContactSolver advances velocities (free motion, contacts, joint limits); integrate() moves q.
// Also: terrain and friction changes, snapshots. Forces: world_forces.cpp; contacts as
// observed: world_contacts.cpp; the Bullet side: world_bullet.h.
#include "podium/sim/world.h"

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCapsuleShape.h>
#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "internal.h"
#include "podium/base/error.h"
#include "shapes.h"
#include "world_bullet.h"

namespace podium::sim {

namespace {

constexpr double kBlownUpSpeed = 1e3;  // m/s or rad/s

std::unique_ptr<btConvexShape> make_shape(const Geom& g) {
  switch (g.type) {
    case ShapeType::sphere:
      return std::make_unique<btSphereShape>(g.radius);
    case ShapeType::capsule:
      return std::make_unique<btCapsuleShapeZ>(g.radius, 2.0 * g.half_length);
    case ShapeType::box:
      return std::make_unique<btBoxShape>(to_bt(g.half_extents));
  }
  return nullptr;
}

// A lone sphere, or capsule along a principal axis, centred on the link's COM needs no compound
// wrapper (which costs a child-algorithm layer per pair and step); nullptr otherwise.
std::unique_ptr<btCollisionShape> make_direct_shape(const Geom& g, const btTransform& local) {
  if (local.getOrigin().length() > 1e-9) return nullptr;
  if (g.type == ShapeType::sphere) return std::make_unique<btSphereShape>(g.radius);
  if (g.type != ShapeType::capsule) return nullptr;
  const btVector3 axis = local.getBasis().getColumn(2);
  const double height = 2.0 * g.half_length;
  if (std::abs(axis.x()) > 1 - 1e-12) return std::make_unique<btCapsuleShapeX>(g.radius, height);
  if (std::abs(axis.y()) > 1 - 1e-12) return std::make_unique<btCapsuleShape>(g.radius, height);  // along y
  if (std::abs(axis.z()) > 1 - 1e-12) return std::make_unique<btCapsuleShapeZ>(g.radius, height);
  return nullptr;
}

// Contact error reduction per step (Baumgarte) such that penetration decays with the time constant
// of MuJoCo's contacts in humanoid.xml (solref 0.015 s), which MuJoCo clamps to ≥ 2Δt: erp =
// Δt/max(τ, 2Δt). Bullet's fixed 0.2 gives a decay time of 5Δt instead: 83 ms at 60 Hz, where
// bodies stayed up to 10 cm deep for several steps after landing.
double contact_erp(double dt_s) {
  constexpr double kContactTimeConstantS = 0.015;
  return dt_s / std::max(kContactTimeConstantS, 2.0 * dt_s);
}

}  // namespace

World::World(const ModelPtr& model, const WorldConfig& config)
    : model_(edit_model(model, config.edits)),
      config_(config),
      terrain_(config.terrain),
      data_(*model_),
      gains_(Gains::from_model(*model_)),
      limits_(model_->nv()),
      implicit_(Eigen::VectorXd::Zero(model_->nv())),
      qd_before_(Eigen::VectorXd::Zero(model_->nv())) {
  const double ratio = config_.sim_hz / config_.control_hz;
  if (!(config_.sim_hz > 0) || !(config_.control_hz > 0) || std::abs(ratio - std::round(ratio)) > 1e-9 || ratio < 1)
    throw base::UserError("sim: control_hz " + std::to_string(config_.control_hz) + " does not divide sim_hz " +
                          std::to_string(config_.sim_hz) + " (need sim_hz = k · control_hz, k ≥ 1)");
  substeps_ = static_cast<int>(std::lround(ratio));
  data_.gravity = config_.gravity;
  forces_.assign(model_->bodies().size(), Eigen::Vector3d::Zero());
  tau_external_ = Eigen::VectorXd::Zero(model_->nv());
  if (config_.passive_joints)
    for (std::size_t i = 0; i < model_->links().size(); ++i) {
      const Link& l = model_->links()[i];
      if (l.joint == JointType::revolute && !l.locked && (l.damping > 0 || l.stiffness > 0))
        passive_links_.push_back(static_cast<int>(i));
    }
  // Body centroids: volume-weighted geom centres in the carrying link's frame (else the body origin).
  centroids_.resize(model_->bodies().size());
  std::vector<double> volume(model_->bodies().size(), 0.0);
  for (std::size_t b = 0; b < centroids_.size(); ++b) centroids_[b] = model_->bodies()[b].offset;
  for (const Link& l : model_->links()) {
    for (const Geom& g : l.geoms) {
      if (volume[g.body] == 0.0) centroids_[g.body].setZero();
      centroids_[g.body] += geom_volume(g) * g.pos;
      volume[g.body] += geom_volume(g);
    }
  }
  for (std::size_t b = 0; b < centroids_.size(); ++b)
    if (volume[b] > 0) centroids_[b] /= volume[b];
  build_bullet();
  set_state(model_->standing_pose(), Eigen::VectorXd::Zero(model_->nv()));
}

World::~World() = default;

ScopedSubstepObserver::ScopedSubstepObserver(World& world, std::function<void(World&)> observer)
    : world_(world), previous_(world.substep_observer()) {
  if (!previous_) {
    world.set_substep_observer(std::move(observer));
    return;
  }
  world.set_substep_observer([first = previous_, then = std::move(observer)](World& w) {
    first(w);
    then(w);
  });
}

void World::build_bullet() {
  bullet_ = std::make_unique<Bullet>();
  Bullet& b = *bullet_;
  b.character = std::make_unique<BulletCharacter>(*model_);
  // The ground plane is the solver's (no Bullet object): it generates those contacts itself.
  ContactSolverConfig contacts;
  contacts.friction = config_.friction;  // the character's μ times the ground's 1.0
  contacts.joint_limits = config_.joint_limits;
  contacts.erp = contact_erp(dt_s());
  contacts.touching_m = kTouchingM;
  b.solver = std::make_unique<ContactSolver>(*model_, b.character->body(), terrain_, contacts);
  b.world = std::make_unique<btCollisionWorld>(&b.dispatcher, &b.broadphase, &b.collision_config);
  b.filter.model = model_.get();
  b.filter.self_collision = config_.self_collision;
  b.world->getPairCache()->setOverlapFilterCallback(&b.filter);

  // Character.
  btMultiBody& body = b.character->body();
  body.setHasSelfCollision(config_.self_collision);
  const auto& links = model_->links();
  b.child_body.resize(links.size());
  for (std::size_t i = 0; i < links.size(); ++i) {
    const Link& l = links[i];
    for (const Geom& g : l.geoms) b.geom_shapes.push_back(make_shape(g));
    if (l.geoms.empty()) continue;
    const Eigen::Quaterniond P = b.character->principal(static_cast<int>(i));
    // Geom poses in Bullet's link frame (at the COM, along principal axes).
    auto local = [&](const Geom& g) {
      return btTransform(to_bt(Eigen::Quaterniond(P.conjugate() * g.rot)),
                         to_bt(Eigen::Vector3d(P.conjugate() * (g.pos - l.com))));
    };
    std::unique_ptr<btCollisionShape> shape = l.geoms.size() == 1 ? make_direct_shape(l.geoms[0], local(l.geoms[0])) : nullptr;
    if (!shape) {
      auto compound = std::make_unique<btCompoundShape>();
      for (const Geom& g : l.geoms) {
        auto child = make_shape(g);
        compound->addChildShape(local(g), child.get());
        b.shapes.push_back(std::move(child));
      }
      shape = std::move(compound);
    }
    for (const Geom& g : l.geoms) b.child_body[i].push_back(g.body);
    auto collider = std::make_unique<btMultiBodyLinkCollider>(&body, static_cast<int>(i) - 1);
    collider->setCollisionShape(shape.get());
    collider->setFriction(config_.friction);
    collider->setRestitution(0.0);
    if (i == 0) body.setBaseCollider(collider.get());
    else body.getLink(static_cast<int>(i) - 1).m_collider = collider.get();
    b.shapes.push_back(std::move(shape));
    b.add_object(std::move(collider), {ObjectInfo::Kind::link, static_cast<int>(i)}, btBroadphaseProxy::DefaultFilter,
                 btBroadphaseProxy::AllFilter);
  }

  // Terrain regions (boxes), then props.
  const auto& pieces = terrain_.pieces();
  for (std::size_t k = 0; k < pieces.size(); ++k)
    b.add_static(std::make_unique<btBoxShape>(to_bt(pieces[k].half_extents)),
                 btTransform(to_bt(pieces[k].rotation), to_bt(pieces[k].center)), 1.0,
                 {ObjectInfo::Kind::piece, static_cast<int>(k)});
  const auto& boxes = terrain_.config().boxes;
  for (std::size_t k = 0; k < boxes.size(); ++k)
    b.add_static(std::make_unique<btBoxShape>(to_bt(boxes[k].half_extents)),
                 btTransform(to_bt(boxes[k].rotation.normalized()), to_bt(boxes[k].center)), boxes[k].friction,
                 {ObjectInfo::Kind::prop, static_cast<int>(k)});
}

void World::rebuild_keeping_state() {
  build_bullet();
  bullet_->character->set_state(data_.q, data_.qd);
  bullet_->character->body().updateCollisionObjectWorldTransforms(bullet_->scratch_q, bullet_->scratch_m);
}

void World::set_friction(double mu) {
  if (!(mu >= 0)) throw base::UserError("sim: friction " + std::to_string(mu) + " is not ≥ 0");
  config_.friction = mu;
  rebuild_keeping_state();
}

void World::set_terrain(const TerrainConfig& terrain) {
  terrain_ = Terrain(terrain);  // validates first: a bad config leaves the World as it was
  config_.terrain = terrain;
  rebuild_keeping_state();
}

WorldSnapshot World::snapshot() const {
  WorldSnapshot s(data_);
  s.model = model_;
  s.config = config_;
  s.gains = gains_;
  s.step_count = step_count_;
  s.failure = failure_;
  s.forces = forces_;
  s.warm = std::make_shared<const WarmStarts>(bullet_->solver->warm_starts());
  return s;
}

void World::restore(const WorldSnapshot& s) {
  // The same model: the same object, or one built from the same file and edits.
  if (s.model != model_ && s.model->source() != model_->source())
    throw base::UserError("sim: restore: the snapshot is of another model (" + s.model->name() + ") than this World's (" +
                          model_->name() + ")");
  if (s.config.sim_hz != config_.sim_hz || s.config.control_hz != config_.control_hz)
    throw base::UserError("sim: restore: the snapshot steps at " + std::to_string(s.config.sim_hz) + " / " +
                          std::to_string(s.config.control_hz) + " Hz, this World at " + std::to_string(config_.sim_hz) + " / " +
                          std::to_string(config_.control_hz) + " Hz");
  terrain_ = Terrain(s.config.terrain);
  config_ = s.config;
  data_ = s.data;
  gains_ = s.gains;
  step_count_ = s.step_count;
  failure_ = s.failure;
  for (std::size_t k = 0; k < forces_.size(); ++k) set_external_force(static_cast<int>(k), s.forces[k]);
  rebuild_keeping_state();
  bullet_->solver->set_warm_starts(*s.warm);
}

void World::reset(const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  build_bullet();
  step_count_ = 0;
  set_state(q, qd);
}

void World::set_state(const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  if (q.size() != model_->nq() || qd.size() != model_->nv())
    throw base::UserError("sim: set_state: q has " + std::to_string(q.size()) + " entries and qd " + std::to_string(qd.size()) +
                          " but model " + model_->name() + " has nq " + std::to_string(model_->nq()) + " and nv " +
                          std::to_string(model_->nv()));
  bullet_->character->set_state(q, qd);
  bullet_->character->body().updateCollisionObjectWorldTransforms(bullet_->scratch_q, bullet_->scratch_m);
  bullet_->character->get_state(data_.q, data_.qd);
  forward_kinematics(*model_, data_);
  failure_ = StepReport{};
}

void World::set_state_world(const Eigen::VectorXd& q, const Eigen::Vector3d& root_omega_world,
                            const Eigen::Vector3d& root_vel_world, const Eigen::VectorXd& joint_qd) {
  if (joint_qd.size() != model_->nv() - 6)
    throw base::UserError("sim: set_state_world: joint_qd has " + std::to_string(joint_qd.size()) +
                          " entries, model needs nv − 6 = " + std::to_string(model_->nv() - 6));
  const Eigen::Matrix3d R = Eigen::Quaterniond(q(3), q(4), q(5), q(6)).normalized().toRotationMatrix();
  Eigen::VectorXd qd(model_->nv());
  qd.head<3>() = R.transpose() * root_omega_world;
  qd.segment<3>(3) = R.transpose() * root_vel_world;
  qd.tail(model_->nv() - 6) = joint_qd;
  set_state(q, qd);
}

void World::set_gains(const Gains& gains) {
  if (gains.kp.size() != model_->nv() || gains.kd.size() != model_->nv())
    throw base::UserError("sim: gains: kp has " + std::to_string(gains.kp.size()) + " entries and kd " +
                          std::to_string(gains.kd.size()) + " but model nv is " + std::to_string(model_->nv()));
  gains_ = gains;
}

StepReport World::sim_step(Control mode, const Eigen::VectorXd& command) {
  if (!failure_.ok) return failure_;
  const int expected = mode == Control::torque ? model_->nv() : model_->nq();
  if (command.size() != expected)
    throw base::UserError("sim: command has " + std::to_string(command.size()) + " entries but " +
                          (mode == Control::torque ? "torque control needs nv = " : "PD control needs nq = ") +
                          std::to_string(expected));
  switch (mode) {
    case Control::torque:
      data_.tau = command;
      break;
    case Control::pd:
      pd_torques(*model_, data_, gains_, command);
      break;
    case Control::spd_dense:
      stable_pd_dense(*model_, data_, gains_, command, dt_s());
      break;
    // data_ is posed: set_state and every step end with forward_kinematics.
    case Control::spd_maba:
      internal::stable_pd_maba_posed(*model_, data_, gains_, command, dt_s());
      break;
    case Control::spd_implicit:
      implicit_pd(command);
      break;
  }
  if (mode == Control::torque) data_.tau.head<6>().setZero();
  if (config_.torque_limits && mode != Control::spd_implicit) {
    limits_ = model_->torque_limits() * config_.strength;
    const int nj = model_->nv() - 6;  // the root servo (if any) is not a motor: no limit
    data_.tau.tail(nj) = data_.tau.tail(nj).cwiseMax(-limits_.tail(nj)).cwiseMin(limits_.tail(nj));
  }
  const bool extra = has_forces_ || !passive_links_.empty();
  if (extra) {
    tau_external_.setZero();
    for (int i : passive_links_) {
      const Link& l = model_->links()[i];
      tau_external_(l.v_index) = -l.damping * data_.qd(l.v_index) - l.stiffness * data_.q(l.q_index);
    }
    for (std::size_t k = 0; k < forces_.size(); ++k)
      if (!forces_[k].isZero(0.0))
        internal::add_point_force(*model_, data_, model_->bodies()[k].link, body_centroid(static_cast<int>(k)), forces_[k],
                                  tau_external_);
  }
  Bullet& b = *bullet_;
  b.detect_contacts();  // at the pose the step starts from
  const bool implicit = mode == Control::spd_implicit;
  if (implicit) qd_before_ = data_.qd;
  b.solver->step(data_, dt_s(), b.world->getDispatcher(), extra ? &tau_external_ : nullptr, implicit ? &implicit_ : nullptr);
  if (implicit) data_.tau -= implicit_.cwiseProduct(data_.qd - qd_before_) / dt_s();  // the torque the springs applied
  // Positions in our coordinates: Bullet keeps base velocities in world frame at the COM, and a
  // round trip through them loses the ω × v and ω × (ω × c) terms of a step (measured: ragdolls
  // gained hundreds of joules). Bullet gets the new pose for collision detection only.
  integrate(*model_, data_.q, data_.qd, dt_s());
  b.character->set_state(data_.q, data_.qd);
  b.character->body().updateCollisionObjectWorldTransforms(b.scratch_q, b.scratch_m);
  ++step_count_;
  for (int i = 0; i < model_->nv(); ++i) {
    // A speed no body reaches (1000 m/s or rad/s) is a blown-up state as much as a NaN is: left
    // running, it overflows observation statistics downstream (a get-up SAC run diverged so).
    if (!(std::abs(data_.qd(i)) < kBlownUpSpeed)) {
      failure_ = StepReport{false, i, step_count_};
      return failure_;
    }
  }
  forward_kinematics(*model_, data_);
  return failure_;
}

// Control::spd_implicit: the spring-damper term Q = −Kp(q + Δt q̇ − q̄) − Kd q̇ (thesis eq. 2.20) as
// the explicit torque and Δt(Kd + Δt Kp) on M's diagonal, so that the solve applies
// Q − Δt(Kd + Δt Kp) q̈ = −Kp(q + Δt q̇⁺ − q̄) − Kd q̇⁺ with the contacts in q̈. Under torque limits, a
// joint whose contact-free stable-PD torque passes its limit gets that torque clamped and nothing
// implicit (an implicit spring cannot be bounded inside the solve).
void World::implicit_pd(const Eigen::VectorXd& target) {
  const double dt = dt_s();
  implicit_.noalias() = dt * (gains_.kd + dt * gains_.kp);
  if (config_.torque_limits) {
    internal::stable_pd_maba_posed(*model_, data_, gains_, target, dt);  // data_.tau: the contact-free SPD torque
    limits_ = model_->torque_limits() * config_.strength;
    for (int i = 6; i < model_->nv(); ++i)
      if (std::abs(data_.tau(i)) > limits_(i)) data_.Q(i) = std::clamp(data_.tau(i), -limits_(i), limits_(i)), implicit_(i) = 0.0;
  } else {
    internal::spd_spring_term(*model_, data_, gains_, target, dt);
  }
  data_.tau = data_.Q;
}

StepReport World::control_step(Control mode, const Eigen::VectorXd& command) {
  StepReport r;
  for (int k = 0; k < substeps_ && r.ok; ++k) {
    r = sim_step(mode, command);
    if (substep_observer_) substep_observer_(*this);
  }
  return r;
}

double World::kinetic_energy() {
  double e = 0.0;
  Eigen::Vector3d com, com_vel;
  center_of_mass(*model_, data_, com, com_vel);  // fills link velocities
  for (std::size_t i = 0; i < model_->links().size(); ++i)
    e += 0.5 * data_.links[i].v.dot(data_.links[i].I_body * data_.links[i].v);
  return e;
}

}  // namespace podium::sim
