#include "sim/raycast/physics_ray.h"

#include <btBulletDynamicsCommon.h>

#include <Eigen/Geometry>

#include "sim/world/bullet_conversions.h"

namespace pavilion::sim {
namespace {

// Closest hit that skips one element and, optionally, transparent elements.
class FilteredClosestRay : public btCollisionWorld::ClosestRayResultCallback {
 public:
  FilteredClosestRay(const btVector3& from, const btVector3& to,
                     const std::vector<core::SectionElement>& elements, int ignore,
                     bool hit_transparent)
      : ClosestRayResultCallback(from, to),
        elements_(elements),
        ignore_(ignore),
        hit_transparent_(hit_transparent) {}

  bool needsCollision(btBroadphaseProxy* proxy) const override {
    const auto* object = static_cast<const btCollisionObject*>(proxy->m_clientObject);
    const int element = object->getUserIndex();
    if (element >= 0) {
      const core::SectionElement& e = elements_[element];
      if (ignore_ >= 0 && e.group == ignore_) return false;
      if (!hit_transparent_ && e.laser == core::LaserResponse::kTransparent) return false;
    }
    return ClosestRayResultCallback::needsCollision(proxy);
  }

  // Called for each hit closer than the closest so far; the last call wins.
  btScalar addSingleResult(btCollisionWorld::LocalRayResult& result,
                           bool normal_in_world_space) override {
    element_ = result.m_collisionObject->getUserIndex();
    // A compound (a robot's chassis): a child whose shape carries an element
    // as its user index is that element (a marker).
    const btCollisionShape* shape = result.m_collisionObject->getCollisionShape();
    if (shape->isCompound() && result.m_localShapeInfo != nullptr) {
      const auto* compound = static_cast<const btCompoundShape*>(shape);
      const int child = result.m_localShapeInfo->m_triangleIndex;
      if (child >= 0 && child < compound->getNumChildShapes() &&
          compound->getChildShape(child)->getUserIndex() >= 0) {
        element_ = compound->getChildShape(child)->getUserIndex();
      }
    }
    return ClosestRayResultCallback::addSingleResult(result, normal_in_world_space);
  }

  int element() const { return element_; }

 private:
  const std::vector<core::SectionElement>& elements_;
  int ignore_;
  bool hit_transparent_;
  int element_ = -1;
};

}  // namespace

RayHit CastPhysicsRay(const btDiscreteDynamicsWorld& dynamics,
                      const std::vector<core::SectionElement>& elements,
                      const Eigen::Vector3d& from_m, const Eigen::Vector3d& to_m, int ignore_group,
                      bool hit_transparent) {
  const btVector3 from = ToBt(from_m), to = ToBt(to_m);
  FilteredClosestRay all(from, to, elements, ignore_group, hit_transparent);
  dynamics.rayTest(from, to, all);
  RayHit hit;
  if (!all.hasHit()) return hit;
  const FilteredClosestRay& result = all;
  hit.hit = true;
  hit.point_m = {result.m_hitPointWorld.x(), result.m_hitPointWorld.y(),
                 result.m_hitPointWorld.z()};
  hit.distance_m = (hit.point_m - from_m).norm();
  Eigen::Vector3d n(result.m_hitNormalWorld.x(), result.m_hitNormalWorld.y(),
                    result.m_hitNormalWorld.z());
  if (n.dot(to_m - from_m) > 0) n = -n;
  hit.normal = n.normalized();
  hit.element = result.element();
  return hit;
}

}  // namespace pavilion::sim
