#include "sim/world/contact_tracker.h"

#include <btBulletDynamicsCommon.h>

#include <algorithm>

namespace pavilion::sim {

void ContactTracker::Update(btCollisionDispatcher& dispatcher,
                            std::vector<ContactChange>* changes) {
  std::set<std::pair<int, int>> now;
  std::vector<ContactChange> begins;
  const int manifolds = dispatcher.getNumManifolds();
  for (int m = 0; m < manifolds; ++m) {
    const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
    int a = manifold->getBody0()->getUserIndex();
    int b = manifold->getBody1()->getUserIndex();
    if (a == 0 || b == 0) continue;  // the floor
    double impulse = 0.0;
    bool touching_now = false;
    btVector3 point(0, 0, 0);
    for (int p = 0; p < manifold->getNumContacts(); ++p) {
      const btManifoldPoint& cp = manifold->getContactPoint(p);
      if (cp.getDistance() < kContactDistanceM) {
        touching_now = true;
        if (cp.getAppliedImpulse() >= impulse) {
          impulse = cp.getAppliedImpulse();
          point = cp.getPositionWorldOnA();
        }
      }
    }
    if (!touching_now) continue;
    if (a > b) std::swap(a, b);
    if (!now.insert({a, b}).second) continue;
    if (!touching_.contains({a, b})) {
      begins.push_back({true, a, b, {point.x(), point.y(), point.z()}, impulse});
    }
  }
  // Deterministic order: ends then begins, each sorted by element pair.
  for (const auto& pair : touching_) {
    if (!now.contains(pair)) changes->push_back({false, pair.first, pair.second, {0, 0, 0}, 0.0});
  }
  std::sort(begins.begin(), begins.end(), [](const ContactChange& x, const ContactChange& y) {
    return std::pair(x.a, x.b) < std::pair(y.a, y.b);
  });
  changes->insert(changes->end(), begins.begin(), begins.end());
  touching_ = std::move(now);
}

std::vector<Eigen::Vector2d> TouchPoints(const btCollisionDispatcher& dispatcher,
                                         const btCollisionObject* object,
                                         const btTransform& frame_from_world) {
  std::vector<Eigen::Vector2d> points;
  const int manifolds = dispatcher.getNumManifolds();
  for (int k = 0; k < manifolds; ++k) {
    const btPersistentManifold* manifold =
        const_cast<btCollisionDispatcher&>(dispatcher).getManifoldByIndexInternal(k);
    const bool object_is_a = manifold->getBody0() == object;
    if (!object_is_a && manifold->getBody1() != object) continue;
    const btCollisionObject* other = object_is_a ? manifold->getBody1() : manifold->getBody0();
    if (other->getUserIndex() == 0) continue;  // the floor
    for (int p = 0; p < manifold->getNumContacts(); ++p) {
      const btManifoldPoint& cp = manifold->getContactPoint(p);
      if (cp.getDistance() >= kContactDistanceM) continue;
      const btVector3 q =
          frame_from_world * (object_is_a ? cp.getPositionWorldOnA() : cp.getPositionWorldOnB());
      points.emplace_back(q.x(), q.y());
    }
  }
  return points;
}

}  // namespace pavilion::sim
