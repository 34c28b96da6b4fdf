// What the character touches (observe's contacts by partner) and its distance to a prop.
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkPairDetector.h>
#include <BulletCollision/NarrowPhaseCollision/btPointCollector.h>
#include <BulletCollision/NarrowPhaseCollision/btVoronoiSimplexSolver.h>

#include <algorithm>
#include <limits>
#include <string>
#include <tuple>

#include "internal.h"
#include "podium/base/error.h"
#include "podium/sim/world.h"
#include "world_bullet.h"

namespace podium::sim {

double World::prop_distance(int body, int prop) const {
  const Bullet& b = *bullet_;
  if (prop < 0 || prop >= static_cast<int>(b.prop_shapes.size()))
    throw base::UserError("sim: prop " + std::to_string(prop) + " does not exist (the terrain has " +
                          std::to_string(b.prop_shapes.size()) + " props)");
  const BoxProp& box = terrain_.config().boxes[prop];
  const btTransform prop_pose(to_bt(box.rotation.normalized()), to_bt(box.center));
  double best = std::numeric_limits<double>::infinity();
  int k = 0;
  for (const Link& l : model_->links()) {
    const LinkData& d = data_.links[&l - model_->links().data()];
    for (const Geom& g : l.geoms) {
      const btConvexShape* shape = b.geom_shapes[k++].get();
      if (g.body != body) continue;
      btVoronoiSimplexSolver simplex;
      btGjkEpaPenetrationDepthSolver epa;
      btGjkPairDetector gjk(shape, b.prop_shapes[prop], &simplex, &epa);
      btDiscreteCollisionDetectorInterface::ClosestPointInput input;
      input.m_transformA =
          btTransform(to_bt(Eigen::Quaterniond(d.R * g.rot.toRotationMatrix())), to_bt(Eigen::Vector3d(d.p + d.R * g.pos)));
      input.m_transformB = prop_pose;
      btPointCollector out;
      gjk.getClosestPoints(input, out, nullptr);
      if (out.m_hasResult) best = std::min(best, static_cast<double>(out.m_distance));
    }
  }
  return best;
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
  for (int e : m.end_effector_bodies())
    o.end_effectors.push_back(root.R.transpose() * (body_point(m, data_, e, Eigen::Vector3d::Zero()) - root.p));
  // Ground contacts from the geoms (the plane outside regions); the rest from a fresh detection,
  // mapped through compound child indices to bodies.
  o.body_contacts.assign(m.bodies().size(), 0);
  auto add = [&](int body, Contact::Partner partner, int index) {
    o.body_contacts[body] = 1;
    const Contact c{body, partner, index};
    if (std::find(o.contacts.begin(), o.contacts.end(), c) == o.contacts.end()) o.contacts.push_back(c);
  };
  internal::for_each_plane_point(m, data_, Eigen::Vector3d::UnitZ(),
                                 [&](int, const Geom& g, int, const Eigen::Vector3d& p, double distance) {
                                   if (distance <= kTouchingM && terrain_.region_at(p.x(), p.y()) < 0)
                                     add(g.body, Contact::Partner::ground, -1);
                                 });
  Bullet& b = *bullet_;
  b.detect_contacts();
  // The body a manifold point is on (-1: not the character), or the partner it stands for.
  auto body_of = [&](const btCollisionObject* obj, int child) {
    const ObjectInfo& what = b.info[obj->getUserIndex()];
    if (what.kind != ObjectInfo::Kind::link) return -1;
    const auto& owners = b.child_body[what.index];
    if (owners.size() == 1) child = 0;  // a direct shape reports no child index
    return child >= 0 && child < static_cast<int>(owners.size()) ? owners[child] : -1;
  };
  auto report = [&](int body, const btCollisionObject* other, int other_child) {
    if (body < 0) return;
    const ObjectInfo& what = b.info[other->getUserIndex()];
    if (what.kind == ObjectInfo::Kind::prop) add(body, Contact::Partner::prop, what.index);
    else if (what.kind == ObjectInfo::Kind::piece) add(body, Contact::Partner::ground, terrain_.pieces()[what.index].region);
    else if (const int partner = body_of(other, other_child); partner >= 0) add(body, Contact::Partner::body, partner);
  };
  btDispatcher* dispatcher = b.world->getDispatcher();
  for (int k = 0; k < dispatcher->getNumManifolds(); ++k) {
    const btPersistentManifold* mf = dispatcher->getManifoldByIndexInternal(k);
    for (int p = 0; p < mf->getNumContacts(); ++p) {
      const btManifoldPoint& pt = mf->getContactPoint(p);
      if (pt.getDistance() > kTouchingM) continue;
      report(body_of(mf->getBody0(), pt.m_index0), mf->getBody1(), pt.m_index1);
      report(body_of(mf->getBody1(), pt.m_index1), mf->getBody0(), pt.m_index0);
    }
  }
  std::sort(o.contacts.begin(), o.contacts.end(), [](const Contact& x, const Contact& y) {
    return std::tie(x.body, x.partner, x.index) < std::tie(y.body, y.partner, y.index);
  });
  return o;
}

bool Observation::touches(int body, Contact::Partner partner, int index) const {
  return std::any_of(contacts.begin(), contacts.end(),
                     [&](const Contact& c) { return c.body == body && c.partner == partner && (index < 0 || c.index == index); });
}

}  // namespace podium::sim
