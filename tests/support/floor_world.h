#pragma once

// A bare test world for robot tests: a square floor (material "floor",
// friction 0.8) and, optionally, a wall across the way at x = 3 m.

#include "sim/world/world_description.h"

namespace pavilion::testing {

// The floor spans [-half_extent_m, half_extent_m] in x and y. The wall, when
// asked for, runs from (3, -4) to (3, 4): 0.2 m thick, 2 m tall.
inline sim::WorldDescription FloorWorld(double half_extent_m, bool wall) {
  sim::WorldDescription w;
  w.name = "floor";
  w.materials["floor"] = sim::Material{0.8, 0.0, {0.5, 0.5, 0.5, 1}, core::LaserResponse::kNormal};
  w.floor = {{-half_extent_m, -half_extent_m}, {half_extent_m, half_extent_m}, "floor", {}};
  if (wall) {
    sim::Wall x;
    x.id = "wall";
    x.points_m = {{3, -4}, {3, 4}};
    x.thickness_m = 0.2;
    x.height_m = 2.0;
    x.material = "floor";
    w.walls.push_back(x);
  }
  return w;
}

}  // namespace pavilion::testing
