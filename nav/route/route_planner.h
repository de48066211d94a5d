#pragma once

// Shortest routes over a robot map's topology (the graph of station and via
// nodes of §6.3.1) by id: a thin wrapper over the global planner
// (nav/planning/graph_planner.h) on the map's edges, both ways, node costs 0.
// It gives the localization scenarios their routes.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/map/robot_map.h"

namespace pavilion::nav {

// The nodes (ids) of a shortest route from `from` to `to`, both included.
// Throws std::invalid_argument naming an unknown node, or when no route exists.
std::vector<std::string> ShortestRoute(const core::RobotMap& map, const std::string& from,
                                       const std::string& to);

// A tour through `stops` in order: the shortest routes between consecutive
// stops joined into one polyline of node positions (repeated nodes dropped).
// Throws as ShortestRoute; requires at least two stops.
std::vector<Eigen::Vector2d> TourPath(const core::RobotMap& map,
                                      const std::vector<std::string>& stops);

// Length of a polyline (m).
double PathLength(const std::vector<Eigen::Vector2d>& path);

}  // namespace pavilion::nav
