#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/geometry/planar_section.h"
#include "sim/world/world.h"

namespace pavilion::sim {

// The geometric half of a laser scanner: the first surface a horizontal ray
// meets. LaserScanner applies its error models (noise, dropouts, surface
// responses, mixed pixels, per-reading poses) to these hits, whichever finder
// produced them: Bullet ray casting (WorldHitFinder, the reference) or the
// planar caster (sim/raycast/planar_caster.h).
class LaserHitFinder {
 public:
  virtual ~LaserHitFinder() = default;
  // The closest hit of the ray from origin_m (its z is the beam height) along
  // the horizontal unit vector `direction`, up to max_range_m. Skips the
  // elements of ignore_group (the casting robot's parts; -1: none) and
  // laser-transparent elements. Element indices are World::elements() indices.
  virtual RayHit Cast(const Eigen::Vector3d& origin_m, const Eigen::Vector2d& direction,
                      double max_range_m, int ignore_group) const = 0;
  // Element ids and laser responses, indexed by RayHit::element.
  virtual const std::vector<core::SectionElement>& elements() const = 0;
  // True when a ray cast shorter finds exactly the hit, to the bit, that the
  // full ray finds within the shorter range. Bullet's does not (its hit is a
  // fraction of the ray's length, and grazing hits depend on that length), so
  // the scanner shortens its probes only where this holds.
  virtual bool ShortRaysAgree() const { return false; }
};

// Bullet ray casting through World::CastRay (thread-safe as that is: between steps).
class WorldHitFinder final : public LaserHitFinder {
 public:
  explicit WorldHitFinder(const World& world) : world_(world) {}

  RayHit Cast(const Eigen::Vector3d& origin_m, const Eigen::Vector2d& direction, double max_range_m,
              int ignore_group) const override {
    const Eigen::Vector3d dir(direction.x(), direction.y(), 0.0);
    return world_.CastRay(origin_m, origin_m + max_range_m * dir, ignore_group, false);
  }
  const std::vector<core::SectionElement>& elements() const override { return world_.elements(); }

 private:
  const World& world_;
};

}  // namespace pavilion::sim
