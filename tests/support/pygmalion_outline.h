#pragma once
// Pygmalion's navigation outline as RobotDescription::OutlineWithWheels drew
// it while the articulated wheels' spheres touched walls: the 45 cm square and
// those spheres as 16-gon discs (7.5 cm at y = ±0.19), hubs that bulge 4 cm
// from its sides — an outline with corners a post can press between.
// Counter-clockwise.
#include <Eigen/Core>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/geometry/polygon.h"

namespace pavilion::testing {

inline std::vector<Eigen::Vector2d> PygmalionWheeledOutline() {
  std::vector<Eigen::Vector2d> points = {
      {-0.225, -0.225}, {0.225, -0.225}, {0.225, 0.225}, {-0.225, 0.225}};
  const double outer = 0.075 / std::cos(std::numbers::pi / 16.0);
  for (const double y : {-0.19, 0.19}) {
    for (int k = 0; k < 16; ++k) {
      const double a = 2.0 * std::numbers::pi * k / 16.0;
      points.emplace_back(outer * std::cos(a), y + outer * std::sin(a));
    }
  }
  return core::ConvexHull(std::move(points));
}

}  // namespace pavilion::testing
