#include "sim/world/contact_tracker.h"

#include <btBulletDynamicsCommon.h>

#include <algorithm>

namespace pavilion::sim {

void ContactTracker::Update(btCollisionDispatcher& dispatcher,
                            std::vector<ContactChange>* changes) {
  // The step's pairs within kContactDistanceM: their smallest distance, their
  // largest (normal, non-negative) impulse and where it acted (the closest
  // point when none did).
  struct Step {
    double min_distance_m = kContactDistanceM;
    double impulse_ns = 0.0;
    btVector3 point{0, 0, 0};
  };
  std::map<std::pair<int, int>, Step> now;
  const int manifolds = dispatcher.getNumManifolds();
  for (int m = 0; m < manifolds; ++m) {
    const btPersistentManifold* manifold = dispatcher.getManifoldByIndexInternal(m);
    int a = manifold->getBody0()->getUserIndex();
    int b = manifold->getBody1()->getUserIndex();
    if (a == 0 || b == 0) continue;  // the floor
    if (a > b) std::swap(a, b);
    for (int p = 0; p < manifold->getNumContacts(); ++p) {
      const btManifoldPoint& cp = manifold->getContactPoint(p);
      const double distance = cp.getDistance();
      if (distance >= kContactDistanceM) continue;
      Step& step = now[{a, b}];
      const double impulse = cp.getAppliedImpulse();
      if (impulse > step.impulse_ns || (step.impulse_ns == 0.0 && distance < step.min_distance_m)) {
        step.point = cp.getPositionWorldOnA();
      }
      step.impulse_ns = std::max(step.impulse_ns, impulse);
      step.min_distance_m = std::min(step.min_distance_m, distance);
    }
  }
  // Ends first, sorted by element pair.
  for (auto it = episodes_.begin(); it != episodes_.end();) {
    if (now.contains(it->first)) {
      ++it;
      continue;
    }
    ContactChange end{
        ContactPhase::kEnd,        it->first.first,   it->first.second, {0, 0, 0}, 0.0,
        it->second.min_distance_m, it->second.touched};
    changes->push_back(end);
    it = episodes_.erase(it);
  }
  // Then begins and touches, in pair order (std::map), a begin before its touch.
  for (const auto& [pair, step] : now) {
    const ContactChange here{ContactPhase::kBegin,
                             pair.first,
                             pair.second,
                             {step.point.x(), step.point.y(), step.point.z()},
                             step.impulse_ns,
                             step.min_distance_m,
                             false};
    auto [episode, began] = episodes_.try_emplace(pair, Episode{false, step.min_distance_m});
    if (began) changes->push_back(here);
    episode->second.min_distance_m = std::min(episode->second.min_distance_m, step.min_distance_m);
    if (!episode->second.touched && (step.min_distance_m <= 0.0 || step.impulse_ns > 0.0)) {
      episode->second.touched = true;
      ContactChange touch = here;
      touch.phase = ContactPhase::kTouch;
      touch.touched = true;
      changes->push_back(touch);
    }
  }
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
