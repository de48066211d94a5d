#pragma once
// Robox's 0.68 m octagon (robots/robox/robot.yaml), counter-clockwise, its
// sides facing the axes: turning on the spot, its corners sweep a circle
// 2.8 cm wider than its sides.
#include <Eigen/Core>
#include <cmath>
#include <numbers>
#include <vector>

namespace pavilion::testing {

inline std::vector<Eigen::Vector2d> RoboxOctagon() {
  const double r = 0.34 / std::cos(std::numbers::pi / 8.0);
  std::vector<Eigen::Vector2d> hull;
  for (int k = 0; k < 8; ++k) {
    const double a = std::numbers::pi / 8.0 + k * std::numbers::pi / 4.0;
    hull.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return hull;
}

}  // namespace pavilion::testing
