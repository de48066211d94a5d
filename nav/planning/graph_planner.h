#pragma once

// Global path planning over the map's topology (thesis §6.3.2): a priority-first
// search (Sedgewick 1988) with costs on arcs and nodes. The cost of a path is
// the sum of its arc weights plus the costs of the nodes it enters (the start's
// own cost is not counted): a node's cost is its fixed cost in the graph plus
// an optional per-query extra cost (the multi-robot "topological potential
// field" of §6.3.5: nodes near other robots cost more).

#include <Eigen/Core>
#include <optional>
#include <span>
#include <vector>

#include "core/map/robot_map.h"
#include "nav/planning/topology_graph.h"

namespace pavilion::nav {

struct GraphPath {
  std::vector<int> nodes;  // node indices, start (or entry node) to goal
  double cost = 0.0;       // arc weights + costs of the nodes entered
};

struct GraphPlannerOptions {
  // Largest distance from a free position to a node it may enter the graph at,
  // m, (0, 1000].
  double entry_radius_m = 6.0;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// The least-cost path from `from` to `to` over unblocked arcs, or none when `to`
// is unreachable. `extra_node_costs` is empty or holds one finite cost >= 0 per
// node. Among equal-cost paths the one whose every node has the lowest-index
// optimal predecessor is returned (deterministic). from == to gives {from}, 0.
// Throws std::invalid_argument on an unknown index or bad extra costs.
std::optional<GraphPath> PlanGraphPath(const TopologyGraph& graph, int from, int to,
                                       std::span<const double> extra_node_costs = {});

// Planning from a free position (e.g. the robot's pose estimate): the position
// is joined to every node within options.entry_radius_m whose straight line
// from the position crosses no wall of `map` (its segments and multi-segment
// line members, core::SegmentsCross; infinite lines are not walls), at a cost
// of the distance, then searched as PlanGraphPath. The path's nodes start at
// the entry node; its cost includes the straight leg and the entry node's
// cost. None when no node is visible within the radius or `goal` is
// unreachable from all of them.
std::optional<GraphPath> PlanFromPosition(const TopologyGraph& graph, const core::RobotMap& map,
                                          const Eigen::Vector2d& position_in_map, int goal,
                                          const GraphPlannerOptions& options = {},
                                          std::span<const double> extra_node_costs = {});

// The walls PlanFromPosition tests lines of sight against: the map's segments
// and multi-segment line members, as endpoint pairs in the map frame.
std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> MapWalls(const core::RobotMap& map);

}  // namespace pavilion::nav
