#include "nav/planning/topology_graph.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace pavilion::nav {

TopologyGraph::TopologyGraph(const core::RobotMap& map) {
  for (const core::MapNode& node : map.nodes) {
    AddNode(node.id, node.pose.translation(), node.station);
  }
  for (const core::MapEdge& edge : map.edges) {
    const std::optional<int> from = FindIndex(edge.from);
    const std::optional<int> to = FindIndex(edge.to);
    if (!from || !to) {
      throw std::invalid_argument("map '" + map.name + "': edge " + edge.from + " - " + edge.to +
                                  " names an unknown node");
    }
    AddArc(*from, *to, edge.weight);
    AddArc(*to, *from, edge.weight);
  }
}

int TopologyGraph::AddNode(const std::string& id, const Eigen::Vector2d& position_m, bool station) {
  if (FindIndex(id)) throw std::invalid_argument("topology graph: duplicate node id '" + id + "'");
  index_of_.emplace(id, node_count());
  ids_.push_back(id);
  positions_.push_back(position_m);
  stations_.push_back(station ? 1 : 0);
  node_costs_.push_back(0.0);
  arcs_.emplace_back();
  return node_count() - 1;
}

void TopologyGraph::CheckIndex(int node, const char* what) const {
  if (node < 0 || node >= node_count()) {
    throw std::invalid_argument(std::string("topology graph: ") + what + " " +
                                std::to_string(node) + " is not a node index");
  }
}

void TopologyGraph::AddArc(int from, int to, double weight) {
  CheckIndex(from, "from");
  CheckIndex(to, "to");
  if (from == to) throw std::invalid_argument("topology graph: arc from a node to itself");
  if (!(std::isfinite(weight) && weight > 0.0)) {
    throw std::invalid_argument("topology graph: weight must be finite and > 0 (arc " + ids_[from] +
                                " -> " + ids_[to] + ")");
  }
  arcs_[from].push_back({to, weight, false});
}

void TopologyGraph::SetNodeCost(int node, double cost) {
  CheckIndex(node, "node");
  if (!(std::isfinite(cost) && cost >= 0.0)) {
    throw std::invalid_argument("topology graph: node cost must be finite and >= 0 (node " +
                                ids_[node] + ")");
  }
  node_costs_[node] = cost;
}

void TopologyGraph::SetBlocked(int from, int to, bool blocked) {
  CheckIndex(from, "from");
  CheckIndex(to, "to");
  bool found = false;
  for (const auto& [u, v] : {std::pair{from, to}, std::pair{to, from}}) {
    for (GraphArc& arc : arcs_[u]) {
      if (arc.to != v) continue;
      arc.blocked = blocked;
      found = true;
    }
  }
  if (!found) {
    throw std::invalid_argument("topology graph: no edge between " + ids_[from] + " and " +
                                ids_[to]);
  }
}

void TopologyGraph::BlockEdge(int from, int to) { SetBlocked(from, to, true); }

void TopologyGraph::UnblockEdge(int from, int to) { SetBlocked(from, to, false); }

bool TopologyGraph::Blocked(int from, int to) const {
  CheckIndex(from, "from");
  CheckIndex(to, "to");
  return std::any_of(arcs_[from].begin(), arcs_[from].end(),
                     [to](const GraphArc& arc) { return arc.to == to && arc.blocked; });
}

int TopologyGraph::arc_count() const {
  std::size_t count = 0;
  for (const std::vector<GraphArc>& out : arcs_) count += out.size();
  return static_cast<int>(count);
}

std::optional<int> TopologyGraph::FindIndex(const std::string& id) const {
  const auto it = index_of_.find(id);
  if (it == index_of_.end()) return std::nullopt;
  return it->second;
}

int TopologyGraph::IndexOf(const std::string& id) const {
  const std::optional<int> index = FindIndex(id);
  if (!index) throw std::invalid_argument("topology graph: no node '" + id + "'");
  return *index;
}

std::vector<int> TopologyGraph::ReachableFrom(int node) const {
  CheckIndex(node, "node");
  std::vector<char> seen(ids_.size(), 0);
  std::vector<int> stack{node};
  seen[node] = 1;
  while (!stack.empty()) {
    const int u = stack.back();
    stack.pop_back();
    for (const GraphArc& arc : arcs_[u]) {
      if (arc.blocked || seen[arc.to]) continue;
      seen[arc.to] = 1;
      stack.push_back(arc.to);
    }
  }
  std::vector<int> reachable;
  for (int v = 0; v < node_count(); ++v) {
    if (seen[v]) reachable.push_back(v);
  }
  return reachable;
}

}  // namespace pavilion::nav
