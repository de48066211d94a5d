#include "nav/route/route_planner.h"

#include <map>
#include <optional>
#include <stdexcept>

#include "nav/planning/graph_planner.h"
#include "nav/planning/topology_graph.h"

namespace pavilion::nav {

std::vector<std::string> ShortestRoute(const core::RobotMap& map, const std::string& from,
                                       const std::string& to) {
  const TopologyGraph graph(map);
  for (const std::string& id : {from, to}) {
    if (!graph.FindIndex(id)) {
      throw std::invalid_argument("map '" + map.name + "' has no node '" + id + "'");
    }
  }
  const std::optional<GraphPath> path =
      PlanGraphPath(graph, graph.IndexOf(from), graph.IndexOf(to));
  if (!path) {
    throw std::invalid_argument("map '" + map.name + "': no route from '" + from + "' to '" + to +
                                "'");
  }
  std::vector<std::string> route;
  for (int v : path->nodes) route.push_back(graph.id(v));
  return route;
}

std::vector<Eigen::Vector2d> TourPath(const core::RobotMap& map,
                                      const std::vector<std::string>& stops) {
  if (stops.size() < 2) throw std::invalid_argument("a tour needs at least two stops");
  std::map<std::string, Eigen::Vector2d> position;
  for (const core::MapNode& node : map.nodes) position[node.id] = node.pose.translation();
  std::vector<Eigen::Vector2d> path;
  for (std::size_t k = 0; k + 1 < stops.size(); ++k) {
    for (const std::string& id : ShortestRoute(map, stops[k], stops[k + 1])) {
      const Eigen::Vector2d& p = position.at(id);
      if (path.empty() || (path.back() - p).norm() > 1e-9) path.push_back(p);
    }
  }
  return path;
}

double PathLength(const std::vector<Eigen::Vector2d>& path) {
  double length = 0.0;
  for (std::size_t k = 1; k < path.size(); ++k) length += (path[k] - path[k - 1]).norm();
  return length;
}

}  // namespace pavilion::nav
