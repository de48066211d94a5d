#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/geometry/planar_section.h"
#include "sim/world/world.h"

// Bullet types are only declared here (the layer lint keeps Bullet includes out
// of every sim/ header).
class btDiscreteDynamicsWorld;

namespace pavilion::sim {

// The reference ray path of sim::World::CastRay: Bullet's ray test of every
// primitive of the physics world, skipping the elements of `ignore_group` and,
// unless `hit_transparent`, laser-transparent ones. `elements` by element index.
RayHit CastPhysicsRay(const btDiscreteDynamicsWorld& dynamics,
                      const std::vector<core::SectionElement>& elements,
                      const Eigen::Vector3d& from_m, const Eigen::Vector3d& to_m, int ignore_group,
                      bool hit_transparent);

}  // namespace pavilion::sim
