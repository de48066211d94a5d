// The topology graph: arcs from map edges, one-way arcs, node costs, blocked
// edges and reachability.
#include "nav/planning/topology_graph.h"

#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

namespace pavilion::nav {
namespace {

// a - b - c in a row and d hanging off b.
core::RobotMap Map() {
  core::RobotMap map;
  map.name = "row";
  map.nodes = {{"a", {0, 0, 0}, true},
               {"b", {1, 0, 0}, false},
               {"c", {2, 0, 0}, true},
               {"d", {1, 1, 0}, false}};
  map.edges = {{"a", "b", 1.0}, {"b", "c", 2.0}, {"b", "d", 1.5}};
  return map;
}

// Confirms each map edge gives two arcs of its weight and ids map to indices in map order.
TEST(TopologyGraphTest, BuildsTwoArcsPerMapEdge) {
  const TopologyGraph graph(Map());
  ASSERT_EQ(graph.node_count(), 4);
  EXPECT_EQ(graph.arc_count(), 6);
  EXPECT_EQ(graph.IndexOf("c"), 2);
  EXPECT_EQ(graph.id(3), "d");
  EXPECT_TRUE(graph.station(0));
  EXPECT_FALSE(graph.station(1));
  EXPECT_TRUE(graph.position(3).isApprox(Eigen::Vector2d(1, 1)));
  EXPECT_EQ(graph.node_cost(2), 0.0);
  ASSERT_EQ(graph.arcs_from(2).size(), 1u);
  EXPECT_EQ(graph.arcs_from(2)[0].to, 1);
  EXPECT_EQ(graph.arcs_from(2)[0].weight, 2.0);
  EXPECT_FALSE(graph.FindIndex("zz").has_value());
  EXPECT_THROW(graph.IndexOf("zz"), std::invalid_argument);
}

// Confirms a one-way arc is followed in its direction only.
TEST(TopologyGraphTest, OneWayArcReachesOnlyForward) {
  TopologyGraph graph(Map());
  const int e = graph.AddNode("e", {3, 0});
  EXPECT_EQ(graph.ReachableFrom(e), (std::vector<int>{e}));
  graph.AddArc(graph.IndexOf("c"), e, 1.0);  // exit only outwards
  EXPECT_EQ(graph.ReachableFrom(0), (std::vector<int>{0, 1, 2, 3, e}));
  EXPECT_EQ(graph.ReachableFrom(e), (std::vector<int>{e}));
}

// Confirms BlockEdge removes both directions from reachability and UnblockEdge restores them.
TEST(TopologyGraphTest, BlockedEdgeCutsBothDirections) {
  TopologyGraph graph(Map());
  graph.BlockEdge(graph.IndexOf("c"), graph.IndexOf("b"));
  EXPECT_TRUE(graph.Blocked(1, 2));
  EXPECT_TRUE(graph.Blocked(2, 1));
  EXPECT_FALSE(graph.Blocked(0, 1));
  EXPECT_EQ(graph.ReachableFrom(0), (std::vector<int>{0, 1, 3}));
  EXPECT_EQ(graph.ReachableFrom(2), (std::vector<int>{2}));
  graph.UnblockEdge(1, 2);
  EXPECT_EQ(graph.ReachableFrom(2), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_THROW(graph.BlockEdge(0, 2), std::invalid_argument);  // no edge a - c
}

// Confirms bad nodes, arcs and costs are rejected with std::invalid_argument.
TEST(TopologyGraphTest, RejectsBadInput) {
  TopologyGraph graph(Map());
  EXPECT_THROW(graph.AddNode("a", {5, 5}), std::invalid_argument);
  EXPECT_THROW(graph.AddArc(0, 0, 1.0), std::invalid_argument);
  EXPECT_THROW(graph.AddArc(0, 9, 1.0), std::invalid_argument);
  EXPECT_THROW(graph.AddArc(0, 2, 0.0), std::invalid_argument);
  EXPECT_THROW(graph.AddArc(0, 2, std::numeric_limits<double>::infinity()), std::invalid_argument);
  EXPECT_THROW(graph.SetNodeCost(1, -1.0), std::invalid_argument);
  EXPECT_THROW(graph.ReachableFrom(-1), std::invalid_argument);
  graph.SetNodeCost(1, 2.5);
  EXPECT_EQ(graph.node_cost(1), 2.5);
  core::RobotMap broken = Map();
  broken.edges.push_back({"a", "nowhere", 1.0});
  EXPECT_THROW(TopologyGraph{broken}, std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::nav
