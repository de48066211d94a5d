#pragma once

#include <Eigen/Core>
#include <memory>
#include <vector>

#include "core/geometry/planar_section.h"
#include "sim/world/element_table.h"
#include "sim/world/prism_registry.h"
#include "sim/world/world.h"
#include "sim/world/world_description.h"

// Bullet types are only declared here (the layer lint keeps Bullet includes out
// of every sim/ header).
class btDbvtBroadphase;

namespace pavilion::sim {

// The laser's fast path (WorldOptions::baked_static_rays): the laser-visible
// static geometry of a world in a ray world of its own, walls, boxes and
// meshes as one bounding-volume tree of triangles, cylinders and doors as
// primitive objects (outside any Bullet world) met by exact intersections.
// Rays meet it first, then the dynamic bodies of the physics world only up to
// that hit. Internal to sim::World. Cast only reads (the baked geometry and
// the broadphase, each ray walking it with a stack of its thread's): rays may
// be cast from several threads at once while nothing moves (World::CastRay).
class BakedRayWorld {
 public:
  // Bakes the static elements of `description`, whose element indices and
  // laser responses `elements` already holds (the world's static geometry).
  BakedRayWorld(const WorldDescription& description, const ElementTable& elements);
  ~BakedRayWorld();
  BakedRayWorld(const BakedRayWorld&) = delete;
  BakedRayWorld& operator=(const BakedRayWorld&) = delete;

  // Places door `door` (index into the description's doors) as `box`.
  void MoveDoor(int door, const Box& box);

  // The closest laser-visible hit from `from_m` to `to_m`: the baked tree, the
  // static primitives, then the dynamic bodies of `broadphase` except those of
  // `ignore_group`, each only up to the closest hit so far and with exact shape
  // intersections (sim/raycast/ray_shapes.h; `prisms` for robot chassis).
  RayHit Cast(const Eigen::Vector3d& from_m, const Eigen::Vector3d& to_m, int ignore_group,
              const std::vector<core::SectionElement>& elements, const PrismRegistry& prisms,
              const btDbvtBroadphase& broadphase) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace pavilion::sim
