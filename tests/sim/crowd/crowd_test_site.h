#pragma once

// The scene the crowd tests share: an empty room and Robox's outline.
#include <Eigen/Core>
#include <cmath>
#include <numbers>
#include <vector>

#include "sim/crowd/crowd.h"

namespace pavilion::sim::crowd::testing {

// An empty 20 m x 10 m room with its four walls.
inline CrowdSite EmptyRoom() {
  CrowdSite site;
  site.floor_min_m = {0, 0};
  site.floor_max_m = {20, 10};
  site.walls = {
      {{0, 0}, {20, 0}, 0}, {{20, 0}, {20, 10}, 1}, {{20, 10}, {0, 10}, 2}, {{0, 10}, {0, 0}, 3}};
  site.entrance = {{0.5, 4}, {2, 4}, {2, 6}, {0.5, 6}};
  site.exit = {{18.5, 8.5}, {19.5, 8.5}, {19.5, 9.5}, {18.5, 9.5}};
  return site;
}

// Robox's octagon (0.68 m across flats), counter-clockwise.
inline std::vector<Eigen::Vector2d> Octagon() {
  std::vector<Eigen::Vector2d> hull;
  const double r = 0.34 / std::cos(std::numbers::pi / 8);
  for (int k = 0; k < 8; ++k) {
    const double a = std::numbers::pi / 8 + k * std::numbers::pi / 4;
    hull.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  return hull;
}

}  // namespace pavilion::sim::crowd::testing
