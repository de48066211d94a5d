#include "nav/planning/graph_planner.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/geometry/segment2.h"

namespace pavilion::nav {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kMaxEntryRadiusM = 1000.0;

// A node the search starts from, with the cost of reaching it.
struct Source {
  int node = 0;
  double cost = 0.0;
};

void CheckExtraCosts(const TopologyGraph& graph, std::span<const double> extra) {
  if (extra.empty()) return;
  if (static_cast<int>(extra.size()) != graph.node_count()) {
    throw std::invalid_argument("extra_node_costs must be empty or hold one cost per node (" +
                                std::to_string(graph.node_count()) + "), got " +
                                std::to_string(extra.size()));
  }
  for (std::size_t i = 0; i < extra.size(); ++i) {
    if (!(std::isfinite(extra[i]) && extra[i] >= 0.0)) {
      throw std::invalid_argument("extra_node_costs must be finite and >= 0 (node " +
                                  graph.id(static_cast<int>(i)) + ")");
    }
  }
}

void CheckNode(const TopologyGraph& graph, int node, const char* what) {
  if (node < 0 || node >= graph.node_count()) {
    throw std::invalid_argument(std::string(what) + " must be a node index in [0, " +
                                std::to_string(graph.node_count()) + "), got " +
                                std::to_string(node));
  }
}

// Priority-first search (Dijkstra's order; binary heap with lazy deletion:
// stale entries are skipped when popped). Heap entries order by (cost, node),
// so equal costs pop the lower index first. A node's predecessor is the
// lowest-index node among its optimal predecessors; arcs cost > 0, so every
// optimal predecessor is settled before the node and the choice is final.
std::optional<GraphPath> Search(const TopologyGraph& graph, std::span<const Source> sources,
                                int target, std::span<const double> extra) {
  const int n = graph.node_count();
  std::vector<double> cost(n, kInfinity);
  std::vector<int> previous(n, -1);
  std::vector<char> settled(n, 0);
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  for (const Source& s : sources) {
    if (s.cost < cost[s.node]) {
      cost[s.node] = s.cost;
      open.emplace(s.cost, s.node);
    }
  }
  while (!open.empty()) {
    const auto [d, u] = open.top();
    open.pop();
    if (settled[u] || d > cost[u]) continue;
    settled[u] = 1;
    if (u == target) break;
    for (const GraphArc& arc : graph.arcs_from(u)) {
      if (arc.blocked || settled[arc.to]) continue;
      const double entered = graph.node_cost(arc.to) + (extra.empty() ? 0.0 : extra[arc.to]);
      const double candidate = d + arc.weight + entered;
      if (candidate < cost[arc.to]) {
        cost[arc.to] = candidate;
        previous[arc.to] = u;
        open.emplace(candidate, arc.to);
      } else if (candidate == cost[arc.to] && previous[arc.to] >= 0 && u < previous[arc.to]) {
        previous[arc.to] = u;
      }
    }
  }
  if (!settled[target]) return std::nullopt;
  GraphPath path;
  path.cost = cost[target];
  for (int v = target; v >= 0; v = previous[v]) path.nodes.push_back(v);
  std::reverse(path.nodes.begin(), path.nodes.end());
  return path;
}

}  // namespace

void GraphPlannerOptions::Validate() const {
  if (!(entry_radius_m > 0.0 && entry_radius_m <= kMaxEntryRadiusM)) {
    throw std::invalid_argument("entry_radius_m must be in (0, 1000] m");
  }
}

std::optional<GraphPath> PlanGraphPath(const TopologyGraph& graph, int from, int to,
                                       std::span<const double> extra_node_costs) {
  CheckNode(graph, from, "from");
  CheckNode(graph, to, "to");
  CheckExtraCosts(graph, extra_node_costs);
  const Source source{from, 0.0};
  return Search(graph, std::span<const Source>(&source, 1), to, extra_node_costs);
}

std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> MapWalls(const core::RobotMap& map) {
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> walls;
  for (const core::MapSegment& s : map.segments) {
    walls.emplace_back(s.first_endpoint.position_m, s.second_endpoint.position_m);
  }
  for (const core::MapMultiSegmentLine& line : map.multi_segment_lines) {
    for (const auto& [first, second] : line.segments) {
      walls.emplace_back(first.position_m, second.position_m);
    }
  }
  return walls;
}

std::optional<GraphPath> PlanFromPosition(const TopologyGraph& graph, const core::RobotMap& map,
                                          const Eigen::Vector2d& position_in_map, int goal,
                                          const GraphPlannerOptions& options,
                                          std::span<const double> extra_node_costs) {
  options.Validate();
  CheckNode(graph, goal, "goal");
  CheckExtraCosts(graph, extra_node_costs);
  if (!position_in_map.allFinite()) throw std::invalid_argument("position must be finite");
  const auto walls = MapWalls(map);
  std::vector<Source> sources;
  for (int v = 0; v < graph.node_count(); ++v) {
    const Eigen::Vector2d& node = graph.position(v);
    const double distance_m = (node - position_in_map).norm();
    if (distance_m > options.entry_radius_m) continue;
    const bool hidden = std::any_of(walls.begin(), walls.end(), [&](const auto& wall) {
      return core::SegmentsCross(position_in_map, node, wall.first, wall.second);
    });
    if (hidden) continue;
    const double entered =
        graph.node_cost(v) + (extra_node_costs.empty() ? 0.0 : extra_node_costs[v]);
    sources.push_back({v, distance_m + entered});
  }
  if (sources.empty()) return std::nullopt;
  return Search(graph, sources, goal, extra_node_costs);
}

}  // namespace pavilion::nav
