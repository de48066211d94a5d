#pragma once

// The roadmap of a robot map (thesis §6.3.1): via nodes on a grid over the
// reachable floor between the given (station and place) nodes, straight
// collision-free edges between near nodes, and bridges over the floor that
// join the graph's separate parts. Pure geometry on core types; reading a
// world into nodes, obstacles and the free-space grid is the caller's part.

#include <string>
#include <vector>

#include "core/geometry/obstacle_set.h"
#include "core/map/robot_map.h"
#include "nav/route/free_space_grid.h"

namespace pavilion::nav {

struct RoadmapOptions {
  double robot_radius_m = 0.35;  // clearance every edge keeps from every obstacle, > 0 m
  double via_spacing_m = 3.0;    // pitch of the grid that places via nodes, > 0 m
  int position_decimals = 6;     // via positions and edge lengths are rounded to these, >= 0

  void Validate() const;  // throws std::invalid_argument naming the field
};

struct Roadmap {
  std::vector<core::MapNode> nodes;  // the given nodes first, then the via nodes
  std::vector<core::MapEdge> edges;  // ordered by node index pair
};

// Builds the roadmap over `free` (reachable cells flooded already) from the
// given nodes. Via nodes are named via_001, via_002, ... skipping names taken.
// Nodes left without an edge and a graph in several parts are reported in
// `warnings` when it is given.
Roadmap BuildRoadmap(std::vector<core::MapNode> nodes, const FreeSpaceGrid& free,
                     const core::ObstacleSet& obstacles, const RoadmapOptions& options,
                     std::vector<std::string>* warnings = nullptr);

}  // namespace pavilion::nav
