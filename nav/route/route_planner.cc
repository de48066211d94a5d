#include "nav/route/route_planner.h"

#include <algorithm>
#include <limits>
#include <map>
#include <queue>
#include <stdexcept>

namespace pavilion::nav {

std::vector<std::string> ShortestRoute(const core::RobotMap& map, const std::string& from,
                                       const std::string& to) {
  std::map<std::string, int> index;
  for (std::size_t i = 0; i < map.nodes.size(); ++i) {
    index[map.nodes[i].id] = static_cast<int>(i);
  }
  for (const std::string& id : {from, to}) {
    if (!index.contains(id)) {
      throw std::invalid_argument("map '" + map.name + "' has no node '" + id + "'");
    }
  }
  const int n = static_cast<int>(map.nodes.size());
  std::vector<std::vector<std::pair<int, double>>> adjacent(n);
  for (const core::MapEdge& e : map.edges) {
    const auto a = index.find(e.from);
    const auto b = index.find(e.to);
    if (a == index.end() || b == index.end()) continue;  // ValidateRobotMap rejects these
    adjacent[a->second].emplace_back(b->second, e.weight);
    adjacent[b->second].emplace_back(a->second, e.weight);
  }
  const int source = index.at(from);
  const int target = index.at(to);
  std::vector<double> distance(n, std::numeric_limits<double>::infinity());
  std::vector<int> previous(n, -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> open;
  distance[source] = 0.0;
  open.emplace(0.0, source);
  while (!open.empty()) {
    const auto [d, u] = open.top();
    open.pop();
    if (d > distance[u]) continue;
    if (u == target) break;
    for (const auto& [v, w] : adjacent[u]) {
      // Ties broken by node index so that routes are deterministic.
      const double candidate = d + w;
      if (candidate < distance[v] || (candidate == distance[v] && u < previous[v])) {
        distance[v] = candidate;
        previous[v] = u;
        open.emplace(candidate, v);
      }
    }
  }
  if (!(distance[target] < std::numeric_limits<double>::infinity())) {
    throw std::invalid_argument("map '" + map.name + "': no route from '" + from + "' to '" + to +
                                "'");
  }
  std::vector<std::string> route;
  for (int v = target; v >= 0; v = previous[v]) route.push_back(map.nodes[v].id);
  std::reverse(route.begin(), route.end());
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
