#pragma once

#include <Eigen/Core>
#include <map>
#include <vector>

class btCollisionShape;

namespace pavilion::sim {

// A vertical prism among the dynamic shapes (a robot's chassis hull) in its
// shape's frame: convex counter-clockwise polygon, z in [z0, z1).
struct RayPrism {
  std::vector<Eigen::Vector2d> polygon;
  double z0 = 0.0;
  double z1 = 0.0;
};

// The prisms of a world by their Bullet shape, for exact laser rays and
// sections of robot chassis.
using PrismRegistry = std::map<const btCollisionShape*, RayPrism>;

}  // namespace pavilion::sim
