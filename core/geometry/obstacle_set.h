#pragma once

// Obstacles of the plane as segments and circles, and the clearance of a
// straight path from them: what edge checks of a roadmap need.

#include <Eigen/Core>
#include <vector>

namespace pavilion::core {

struct ObstacleSet {
  struct Segment {
    Eigen::Vector2d a_m;
    Eigen::Vector2d b_m;
  };
  struct Circle {
    Eigen::Vector2d center_m;
    double radius_m = 0.0;  // >= 0; 0 is a point
  };
  std::vector<Segment> segments;
  std::vector<Circle> circles;

  // Smallest distance from the segment a-b to any obstacle (m); +inf when none.
  double Clearance(const Eigen::Vector2d& a_m, const Eigen::Vector2d& b_m) const;
};

}  // namespace pavilion::core
