#pragma once

// The map's topology as the weighted directed graph of thesis §6.3.1: station
// and via nodes, arcs with positive weights, node costs (§6.3.2: fixed for one
// robot; the variable multi-robot costs of §6.3.5 are passed to the planner per
// query). Nodes are addressed by index (0 .. node_count()-1, the map's order);
// IndexOf maps an id to its index.
//
// Direction: today's map edges are undirected (a corridor is traversable both
// ways), so each map edge becomes two arcs, u->v and v->u, of the edge's weight.
// A one-way arc (e.g. a visitor-flow rule: the exit corridor only outwards) is
// added with AddArc.

#include <Eigen/Core>
#include <optional>
#include <span>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/map/robot_map.h"

namespace pavilion::nav {

// One directed arc out of a node.
struct GraphArc {
  int to = 0;
  double weight = 1.0;   // > 0, finite
  bool blocked = false;  // set by BlockEdge: the planner does not use the arc
};

class TopologyGraph {
 public:
  TopologyGraph() = default;
  // The map's nodes (in order, cost 0) and two arcs per map edge. Throws
  // std::invalid_argument on a duplicate node id, an edge naming an unknown
  // node, or a weight that is not finite and > 0 (ValidateRobotMap rejects these).
  explicit TopologyGraph(const core::RobotMap& map);

  // Appends a node (cost 0) and returns its index; throws on a duplicate id.
  int AddNode(const std::string& id, const Eigen::Vector2d& position_m, bool station = false);
  // Adds the one-way arc from -> to. Throws std::invalid_argument on an unknown
  // index, from == to, or a weight that is not finite and > 0.
  void AddArc(int from, int to, double weight);
  // The fixed cost of entering `node` (§6.3.2), finite and >= 0.
  void SetNodeCost(int node, double cost);

  // Blocks (or unblocks) both arcs between `from` and `to`, e.g. an edge through
  // a closed door. Throws std::invalid_argument when no arc joins the two nodes.
  void BlockEdge(int from, int to);
  void UnblockEdge(int from, int to);
  // True when an arc from -> to exists and is blocked.
  bool Blocked(int from, int to) const;

  int node_count() const { return static_cast<int>(ids_.size()); }
  int arc_count() const;
  // The index of the node `id`; throws std::invalid_argument if there is none.
  int IndexOf(const std::string& id) const;
  std::optional<int> FindIndex(const std::string& id) const;
  const std::string& id(int node) const { return ids_.at(node); }
  const Eigen::Vector2d& position(int node) const { return positions_.at(node); }
  bool station(int node) const { return stations_.at(node) != 0; }
  double node_cost(int node) const { return node_costs_.at(node); }
  // The arcs leaving `node`, in insertion order.
  std::span<const GraphArc> arcs_from(int node) const { return arcs_.at(node); }

  // The nodes reachable from `node` over unblocked arcs, `node` included, in
  // ascending index order. Throws std::invalid_argument on an unknown index.
  std::vector<int> ReachableFrom(int node) const;

 private:
  void CheckIndex(int node, const char* what) const;
  void SetBlocked(int from, int to, bool blocked);

  std::vector<std::string> ids_;
  std::unordered_map<std::string, int> index_of_;
  std::vector<Eigen::Vector2d> positions_;
  std::vector<char> stations_;
  std::vector<double> node_costs_;
  std::vector<std::vector<GraphArc>> arcs_;
};

}  // namespace pavilion::nav
