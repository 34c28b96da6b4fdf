// World: a CharacterModel as a Bullet btMultiBody in a btCollisionWorld with terrain, and motor
// control (torque, PD, SPD dense/MABA) applied every simulation step. Bullet finds contacts;
// ContactSolver advances velocities (free motion, contacts, joint limits); integrate() moves q.
#include "podium/sim/world.h"

#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCapsuleShape.h>
#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "bullet_character.h"
#include "contact_solver.h"
#include "internal.h"
#include "podium/base/error.h"

namespace podium::sim {

namespace {

// Self-collision filter: pairs of links of our character collide only if the model allows it.
struct SelfCollisionFilter : btOverlapFilterCallback {
  const CharacterModel* model = nullptr;
  bool self_collision = true;
  bool needBroadphaseCollision(btBroadphaseProxy* a, btBroadphaseProxy* b) const override {
    if (!(a->m_collisionFilterGroup & b->m_collisionFilterMask) || !(b->m_collisionFilterGroup & a->m_collisionFilterMask)) return false;
    auto* ca = btMultiBodyLinkCollider::upcast(static_cast<btCollisionObject*>(a->m_clientObject));
    auto* cb = btMultiBodyLinkCollider::upcast(static_cast<btCollisionObject*>(b->m_clientObject));
    if (ca && cb && ca->m_multiBody == cb->m_multiBody) return self_collision && model->links_collide(ca->m_link + 1, cb->m_link + 1);
    return true;
  }
};

std::unique_ptr<btCollisionShape> make_shape(const Geom& g) {
  switch (g.type) {
    case ShapeType::sphere: return std::make_unique<btSphereShape>(g.radius);
    case ShapeType::capsule: return std::make_unique<btCapsuleShapeZ>(g.radius, 2.0 * g.half_length);
    case ShapeType::box: return std::make_unique<btBoxShape>(to_bt(g.half_extents));
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

// Bullet's default pools (4096 manifolds of 1.5 kB each in double precision, 4096 algorithms) are
// allocated and touched on every reset; one character needs far fewer, and Bullet falls back to
// the heap if they run out.
btDefaultCollisionConstructionInfo small_pools() {
  btDefaultCollisionConstructionInfo info;
  info.m_defaultMaxPersistentManifoldPoolSize = 256;
  info.m_defaultMaxCollisionAlgorithmPoolSize = 256;
  return info;
}

// Contact points farther apart than this are not touching: observe() does not report them and the
// solver gets no rows for them (Bullet keeps manifold points up to its contact-breaking distance).
constexpr double kTouchingM = 1e-3;

// Contact error reduction per step (Baumgarte) such that penetration decays with the time constant
// of MuJoCo's contacts in humanoid.xml (solref 0.015 s), which MuJoCo clamps to ≥ 2Δt: erp =
// Δt/max(τ, 2Δt). Bullet's fixed 0.2 gives a decay time of 5Δt instead: 83 ms at 60 Hz, where
// bodies stayed up to 10 cm deep for several steps after landing.
double contact_erp(double dt_s) {
  constexpr double kContactTimeConstantS = 0.015;
  return dt_s / std::max(kContactTimeConstantS, 2.0 * dt_s);
}

}  // namespace

struct World::Bullet {
  btDefaultCollisionConfiguration collision_config{small_pools()};
  btCollisionDispatcher dispatcher{&collision_config};
  btDbvtBroadphase broadphase;
  // Declared before the world, which points to them.
  std::unique_ptr<BulletCharacter> character;
  std::unique_ptr<ContactSolver> solver;
  SelfCollisionFilter filter;
  std::unique_ptr<btCollisionWorld> world;
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btCollisionObject>> objects;  // colliders and terrain
  std::vector<std::vector<int>> child_body;  // per link: body of each compound child
  btAlignedObjectArray<btQuaternion> scratch_q;  // for updateCollisionObjectWorldTransforms
  btAlignedObjectArray<btVector3> scratch_m;

  ~Bullet() {
    for (auto& o : objects) world->removeCollisionObject(o.get());
  }

  void add_static(std::unique_ptr<btCollisionShape> shape, const btTransform& pose, double friction) {
    auto obj = std::make_unique<btCollisionObject>();
    obj->setCollisionShape(shape.get());
    obj->setWorldTransform(pose);
    obj->setFriction(friction);
    obj->setRestitution(0.0);
    world->addCollisionObject(obj.get(), btBroadphaseProxy::StaticFilter, btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter);
    shapes.push_back(std::move(shape));
    objects.push_back(std::move(obj));
  }
};

World::World(ModelPtr model, const WorldConfig& config)
    : model_(std::move(model)), config_(config), terrain_(config.terrain), data_(*model_), gains_(Gains::from_model(*model_)),
      limits_(model_->nv()) {
  const double ratio = config_.sim_hz / config_.control_hz;
  if (!(config_.sim_hz > 0) || !(config_.control_hz > 0) || std::abs(ratio - std::round(ratio)) > 1e-9 || ratio < 1)
    throw base::UserError("sim: control_hz " + std::to_string(config_.control_hz) + " does not divide sim_hz " + std::to_string(config_.sim_hz) +
                          " (need sim_hz = k · control_hz, k ≥ 1)");
  substeps_ = static_cast<int>(std::lround(ratio));
  data_.gravity = config_.gravity;
  build_bullet();
  set_state(model_->standing_pose(), Eigen::VectorXd::Zero(model_->nv()));
}

World::~World() = default;

void World::build_bullet() {
  bullet_ = std::make_unique<Bullet>();
  Bullet& b = *bullet_;
  b.character = std::make_unique<BulletCharacter>(*model_);
  // The ground plane is the solver's (no Bullet object): it generates those contacts itself.
  const TerrainConfig& t = config_.terrain;
  ContactSolverConfig contacts;
  if (t.kind == TerrainConfig::Kind::slope) contacts.ground_normal = Eigen::Vector3d(-std::sin(t.slope_rad), 0.0, std::cos(t.slope_rad));
  contacts.friction = config_.friction;  // the character's μ times the ground's 1.0
  contacts.joint_limits = config_.joint_limits;
  contacts.erp = contact_erp(dt_s());
  contacts.touching_m = kTouchingM;
  b.solver = std::make_unique<ContactSolver>(*model_, b.character->body(), contacts);
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
    if (l.geoms.empty()) continue;
    const Eigen::Quaterniond P = b.character->principal(static_cast<int>(i));
    // Geom poses in Bullet's link frame (at the COM, along principal axes).
    auto local = [&](const Geom& g) {
      return btTransform(to_bt(Eigen::Quaterniond(P.conjugate() * g.rot)), to_bt(Eigen::Vector3d(P.conjugate() * (g.pos - l.com))));
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
    b.world->addCollisionObject(collider.get(), btBroadphaseProxy::DefaultFilter, btBroadphaseProxy::AllFilter);
    if (i == 0) body.setBaseCollider(collider.get());
    else body.getLink(static_cast<int>(i) - 1).m_collider = collider.get();
    b.shapes.push_back(std::move(shape));
    b.objects.push_back(std::move(collider));
  }

  // Props: tiles, boxes.
  if (t.kind == TerrainConfig::Kind::rough) {
    const int n = t.tiles_per_side;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        const double h = terrain_.tile_height(i, j);
        if (h <= 0) continue;
        const double cx = (i - n / 2.0 + 0.5) * t.tile_size_m, cy = (j - n / 2.0 + 0.5) * t.tile_size_m;
        b.add_static(std::make_unique<btBoxShape>(btVector3(t.tile_size_m / 2, t.tile_size_m / 2, h / 2)),
                     btTransform(btQuaternion::getIdentity(), btVector3(cx, cy, h / 2)), 1.0);
      }
    }
  }
  for (const BoxProp& box : t.boxes) {
    b.add_static(std::make_unique<btBoxShape>(to_bt(box.half_extents)), btTransform(btQuaternion(btVector3(0, 0, 1), box.yaw_rad), to_bt(box.center)),
                 box.friction);
  }
}

void World::reset(const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  build_bullet();
  step_count_ = 0;
  set_state(q, qd);
}

void World::set_state(const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  if (q.size() != model_->nq() || qd.size() != model_->nv())
    throw base::UserError("sim: set_state: q has " + std::to_string(q.size()) + " entries and qd " + std::to_string(qd.size()) + " but model " +
                          model_->name() + " has nq " + std::to_string(model_->nq()) + " and nv " + std::to_string(model_->nv()));
  bullet_->character->set_state(q, qd);
  bullet_->character->body().updateCollisionObjectWorldTransforms(bullet_->scratch_q, bullet_->scratch_m);
  bullet_->character->get_state(data_.q, data_.qd);
  forward_kinematics(*model_, data_);
  failure_ = StepReport{};
}

void World::set_state_world(const Eigen::VectorXd& q, const Eigen::Vector3d& root_omega_world, const Eigen::Vector3d& root_vel_world,
                            const Eigen::VectorXd& joint_qd) {
  if (joint_qd.size() != model_->nv() - 6)
    throw base::UserError("sim: set_state_world: joint_qd has " + std::to_string(joint_qd.size()) + " entries, model needs nv − 6 = " +
                          std::to_string(model_->nv() - 6));
  const Eigen::Matrix3d R = Eigen::Quaterniond(q(3), q(4), q(5), q(6)).normalized().toRotationMatrix();
  Eigen::VectorXd qd(model_->nv());
  qd.head<3>() = R.transpose() * root_omega_world;
  qd.segment<3>(3) = R.transpose() * root_vel_world;
  qd.tail(model_->nv() - 6) = joint_qd;
  set_state(q, qd);
}

void World::set_gains(const Gains& gains) {
  if (gains.kp.size() != model_->nv() || gains.kd.size() != model_->nv())
    throw base::UserError("sim: gains: kp has " + std::to_string(gains.kp.size()) + " entries and kd " + std::to_string(gains.kd.size()) +
                          " but model nv is " + std::to_string(model_->nv()));
  gains_ = gains;
}

StepReport World::sim_step(Control mode, const Eigen::VectorXd& command) {
  if (!failure_.ok) return failure_;
  const int expected = mode == Control::torque ? model_->nv() : model_->nq();
  if (command.size() != expected)
    throw base::UserError("sim: command has " + std::to_string(command.size()) + " entries but " +
                          (mode == Control::torque ? "torque control needs nv = " : "PD control needs nq = ") + std::to_string(expected));
  switch (mode) {
    case Control::torque: data_.tau = command; break;
    case Control::pd: pd_torques(*model_, data_, gains_, command); break;
    case Control::spd_dense: stable_pd_dense(*model_, data_, gains_, command, dt_s()); break;
    // data_ is posed: set_state and every step end with forward_kinematics.
    case Control::spd_maba: internal::stable_pd_maba_posed(*model_, data_, gains_, command, dt_s()); break;
  }
  if (mode == Control::torque) data_.tau.head<6>().setZero();
  if (config_.torque_limits) {
    limits_ = model_->torque_limits() * config_.strength;
    const int nj = model_->nv() - 6;  // the root servo (if any) is not a motor: no limit
    data_.tau.tail(nj) = data_.tau.tail(nj).cwiseMax(-limits_.tail(nj)).cwiseMin(limits_.tail(nj));
  }
  Bullet& b = *bullet_;
  b.world->performDiscreteCollisionDetection();  // contacts at the pose the step starts from
  b.solver->step(data_, dt_s(), b.world->getDispatcher());
  // Positions in our coordinates: Bullet keeps base velocities in world frame at the COM, and a
  // round trip through them loses the ω × v and ω × (ω × c) terms of a step (measured: ragdolls
  // gained hundreds of joules). Bullet gets the new pose for collision detection only.
  integrate(*model_, data_.q, data_.qd, dt_s());
  b.character->set_state(data_.q, data_.qd);
  b.character->body().updateCollisionObjectWorldTransforms(b.scratch_q, b.scratch_m);
  ++step_count_;
  for (int i = 0; i < model_->nv(); ++i) {
    if (!std::isfinite(data_.qd(i))) {
      failure_ = StepReport{false, i, step_count_};
      return failure_;
    }
  }
  forward_kinematics(*model_, data_);
  return failure_;
}

StepReport World::control_step(Control mode, const Eigen::VectorXd& command) {
  StepReport r;
  for (int k = 0; k < substeps_ && r.ok; ++k) r = sim_step(mode, command);
  return r;
}

double World::kinetic_energy() {
  double e = 0.0;
  Eigen::Vector3d com, com_vel;
  center_of_mass(*model_, data_, com, com_vel);  // fills link velocities
  for (std::size_t i = 0; i < model_->links().size(); ++i) e += 0.5 * data_.links[i].v.dot(data_.links[i].I_body * data_.links[i].v);
  return e;
}

Observation World::observe() {
  Observation o;
  const CharacterModel& m = *model_;
  const Eigen::Vector3d head = body_point(m, data_, m.head_body(), Eigen::Vector3d::Zero());
  o.head_height_m = head.z() - terrain_.height(head.x(), head.y());
  center_of_mass(m, data_, o.com, o.com_vel);
  const Eigen::Matrix3d& Rt = data_.links[m.bodies()[m.torso_body()].link].R;
  o.torso_up = Rt.row(2).transpose();
  o.root_quat = data_.q.segment<4>(3);
  const LinkData& root = data_.links[0];
  for (int e : m.end_effector_bodies()) o.end_effectors.push_back(root.R.transpose() * (body_point(m, data_, e, Eigen::Vector3d::Zero()) - root.p));
  // Ground contacts from the geoms; the rest from Bullet's manifolds, mapped through compound child indices to bodies.
  o.body_contacts.assign(m.bodies().size(), 0);
  internal::for_each_plane_point(m, data_, bullet_->solver->ground_normal(), [&](int, const Geom& g, int, const Eigen::Vector3d&, double distance) {
    if (distance <= kTouchingM) o.body_contacts[g.body] = 1;
  });
  btDispatcher* dispatcher = bullet_->world->getDispatcher();
  auto mark = [&](const btCollisionObject* obj, int child) {
    const auto* col = btMultiBodyLinkCollider::upcast(obj);
    if (!col || col->m_multiBody != &bullet_->character->body()) return;
    const auto& owners = bullet_->child_body[col->m_link + 1];
    if (owners.size() == 1) child = 0;  // a direct shape reports no child index
    if (child >= 0 && child < static_cast<int>(owners.size())) o.body_contacts[owners[child]] = 1;
  };
  for (int k = 0; k < dispatcher->getNumManifolds(); ++k) {
    const btPersistentManifold* mf = dispatcher->getManifoldByIndexInternal(k);
    for (int p = 0; p < mf->getNumContacts(); ++p) {
      const btManifoldPoint& pt = mf->getContactPoint(p);
      if (pt.getDistance() > kTouchingM) continue;
      mark(mf->getBody0(), pt.m_index0);
      mark(mf->getBody1(), pt.m_index1);
    }
  }
  return o;
}

}  // namespace podium::sim
