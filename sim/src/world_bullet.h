#pragma once
// World's Bullet side (private to world*.cpp): the collision world, the character's colliders,
// terrain pieces and props, and what each collision object stands for.
#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletCollision/CollisionShapes/btConvexShape.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <memory>
#include <vector>

#include "bullet_character.h"
#include "contact_solver.h"
#include "podium/sim/world.h"

namespace podium::sim {

// Contact points farther apart than this are not touching: observe() does not report them and the
// solver gets no rows for them (Bullet keeps manifold points up to its contact-breaking distance).
inline constexpr double kTouchingM = 1e-3;

// Self-collision filter: pairs of links of our character collide only if the model allows it.
struct SelfCollisionFilter : btOverlapFilterCallback {
  const CharacterModel* model = nullptr;
  bool self_collision = true;
  bool needBroadphaseCollision(btBroadphaseProxy* a, btBroadphaseProxy* b) const override {
    if (!(a->m_collisionFilterGroup & b->m_collisionFilterMask) || !(b->m_collisionFilterGroup & a->m_collisionFilterMask))
      return false;
    auto* ca = btMultiBodyLinkCollider::upcast(static_cast<btCollisionObject*>(a->m_clientObject));
    auto* cb = btMultiBodyLinkCollider::upcast(static_cast<btCollisionObject*>(b->m_clientObject));
    if (ca && cb && ca->m_multiBody == cb->m_multiBody)
      return self_collision && model->links_collide(ca->m_link + 1, cb->m_link + 1);
    return true;
  }
};

// Bullet's default pools (4096 manifolds of 1.5 kB each in double precision, 4096 algorithms) are
// allocated and touched on every reset; one character needs far fewer, and Bullet falls back to
// the heap if they run out.
inline btDefaultCollisionConstructionInfo small_pools() {
  btDefaultCollisionConstructionInfo info;
  info.m_defaultMaxPersistentManifoldPoolSize = 256;
  info.m_defaultMaxCollisionAlgorithmPoolSize = 256;
  return info;
}

// What each collision object is (its user index is its position in World::Bullet::objects).
struct ObjectInfo {
  enum class Kind { link, piece, prop } kind = Kind::link;
  int index = 0;  // link, terrain piece or prop
};

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
  std::vector<std::unique_ptr<btCollisionObject>> objects;  // colliders, terrain pieces, props
  std::vector<ObjectInfo> info;                             // per object
  std::vector<std::vector<int>> child_body;                 // per link: body of each compound child
  std::vector<std::unique_ptr<btConvexShape>> geom_shapes;  // per geom in model order (distance queries)
  std::vector<const btConvexShape*> prop_shapes;            // per prop
  btAlignedObjectArray<btQuaternion> scratch_q;             // for updateCollisionObjectWorldTransforms
  btAlignedObjectArray<btVector3> scratch_m;

  ~Bullet() {
    for (auto& o : objects) world->removeCollisionObject(o.get());
  }

  void add_object(std::unique_ptr<btCollisionObject> obj, ObjectInfo what, int group, int mask) {
    obj->setUserIndex(static_cast<int>(objects.size()));
    world->addCollisionObject(obj.get(), group, mask);
    objects.push_back(std::move(obj));
    info.push_back(what);
  }

  void add_static(std::unique_ptr<btConvexShape> shape, const btTransform& pose, double friction, ObjectInfo what) {
    auto obj = std::make_unique<btCollisionObject>();
    obj->setCollisionShape(shape.get());
    obj->setWorldTransform(pose);
    obj->setFriction(friction);
    obj->setRestitution(0.0);
    if (what.kind == ObjectInfo::Kind::prop) prop_shapes.push_back(shape.get());
    add_object(std::move(obj), what, btBroadphaseProxy::StaticFilter,
               btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter);
    shapes.push_back(std::move(shape));
  }

  // Bullet's points of the last detection only: the step's contacts depend on the pose alone.
  void detect_contacts() {
    for (int k = 0; k < dispatcher.getNumManifolds(); ++k) dispatcher.getManifoldByIndexInternal(k)->clearManifold();
    world->performDiscreteCollisionDetection();
  }
};

}  // namespace podium::sim
