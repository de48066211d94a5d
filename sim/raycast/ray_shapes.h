#pragma once

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace pavilion::sim {

// Exact double-precision intersections of a ray o + t·d (t in [0, t_max]) with
// primitive shapes in their own frame, for the laser's fast path
// (World::CastRay). A ray starting inside a shape does not hit it.
struct RayShapeHit {
  double t = 0.0;
  Eigen::Vector3d normal{0, 0, 0};  // outward unit normal at the hit, shape frame
};

std::optional<RayShapeHit> RaySphere(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                     double radius, double t_max);
// Axis-aligned box of half extents `half` centred at the origin.
std::optional<RayShapeHit> RayBox(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                  const Eigen::Vector3d& half, double t_max);
// Cylinder about z centred at the origin: radius, half height.
std::optional<RayShapeHit> RayCylinderZ(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                        double radius, double half_height, double t_max);
// Vertical prism over a convex counter-clockwise polygon, z in [z0, z1].
std::optional<RayShapeHit> RayPrismZ(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                     const std::vector<Eigen::Vector2d>& polygon, double z0,
                                     double z1, double t_max);

}  // namespace pavilion::sim
