// The global planner over the topology graph (§6.3.2): optimality against
// brute force, node costs, blocked edges, deterministic ties and the entry
// from a free position through the map's walls.
#include "nav/planning/graph_planner.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/random/random_stream.h"

namespace pavilion::nav {
namespace {

constexpr double kCostTolerance = 1e-9;  // sums of <= 8 terms of O(10): rounding only

// A node id: the prefix and the index (built by append: GCC 12's -Wrestrict
// misfires on `"n" + std::to_string(i)`).
std::string NodeId(const char* prefix, int index) {
  std::string id(prefix);
  id.append(std::to_string(index));
  return id;
}

// Least cost over all simple paths from `from` to `to` (depth-first
// enumeration; optimal paths are simple because every arc costs > 0).
void Enumerate(const TopologyGraph& g, int u, int to, std::span<const double> extra,
               std::vector<char>& on_path, double cost, double& best) {
  if (u == to) {
    best = std::min(best, cost);
    return;
  }
  for (const GraphArc& arc : g.arcs_from(u)) {
    if (arc.blocked || on_path[arc.to]) continue;
    on_path[arc.to] = 1;
    const double entered = g.node_cost(arc.to) + (extra.empty() ? 0.0 : extra[arc.to]);
    Enumerate(g, arc.to, to, extra, on_path, cost + arc.weight + entered, best);
    on_path[arc.to] = 0;
  }
}

std::optional<double> BruteForceCost(const TopologyGraph& g, int from, int to,
                                     std::span<const double> extra) {
  std::vector<char> on_path(g.node_count(), 0);
  on_path[from] = 1;
  double best = std::numeric_limits<double>::infinity();
  Enumerate(g, from, to, extra, on_path, 0.0, best);
  if (!std::isfinite(best)) return std::nullopt;
  return best;
}

// The cost of `nodes` walked over the cheapest unblocked arc of each step, or
// none when a step has no unblocked arc.
std::optional<double> WalkCost(const TopologyGraph& g, const std::vector<int>& nodes,
                               std::span<const double> extra) {
  double cost = 0.0;
  for (std::size_t k = 1; k < nodes.size(); ++k) {
    double weight = std::numeric_limits<double>::infinity();
    for (const GraphArc& arc : g.arcs_from(nodes[k - 1])) {
      if (arc.to == nodes[k] && !arc.blocked) weight = std::min(weight, arc.weight);
    }
    if (!std::isfinite(weight)) return std::nullopt;
    cost += weight + g.node_cost(nodes[k]) + (extra.empty() ? 0.0 : extra[nodes[k]]);
  }
  return cost;
}

// A random graph of 2..8 nodes: two-way edges, one-way arcs, blocked edges,
// node costs; sparse enough that some pairs are unreachable.
TopologyGraph RandomGraph(core::RandomStream& rng) {
  TopologyGraph g;
  const int n = static_cast<int>(rng.UniformInt(2, 8));
  for (int i = 0; i < n; ++i) {
    g.AddNode(NodeId("n", i), {rng.Uniform(0, 10), rng.Uniform(0, 10)});
    if (rng.Uniform() < 0.5) g.SetNodeCost(i, rng.Uniform(0.0, 3.0));
  }
  for (int u = 0; u < n; ++u) {
    for (int v = u + 1; v < n; ++v) {
      const double kind = rng.Uniform();
      if (kind < 0.25) {
        const double w = rng.Uniform(0.1, 5.0);
        g.AddArc(u, v, w);
        g.AddArc(v, u, w);
        if (rng.Uniform() < 0.15) g.BlockEdge(u, v);
      } else if (kind < 0.4) {
        g.AddArc(u, v, rng.Uniform(0.1, 5.0));  // one way, up
      } else if (kind < 0.5) {
        g.AddArc(v, u, rng.Uniform(0.1, 5.0));  // one way, down
      }
    }
  }
  return g;
}

// Confirms the planner's cost equals the brute-force optimum on 300 random
// graphs (all ordered pairs), its path walks unblocked arcs at that cost, and
// it returns none exactly when brute force finds no path.
TEST(GraphPlannerTest, MatchesBruteForceOnRandomGraphs) {
  core::RandomStream rng(14, core::RandomStream::StreamId("graph_planner_test"));
  int solved = 0;
  int unreachable = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const TopologyGraph g = RandomGraph(rng);
    std::vector<double> extra;
    if (trial % 2 == 1) {
      for (int i = 0; i < g.node_count(); ++i) extra.push_back(rng.Uniform(0.0, 2.0));
    }
    for (int s = 0; s < g.node_count(); ++s) {
      for (int t = 0; t < g.node_count(); ++t) {
        const std::optional<double> best = BruteForceCost(g, s, t, extra);
        const std::optional<GraphPath> path = PlanGraphPath(g, s, t, extra);
        ASSERT_EQ(best.has_value(), path.has_value()) << "trial " << trial << " " << s << "->" << t;
        if (!best) {
          ++unreachable;
          continue;
        }
        ++solved;
        ASSERT_EQ(path->nodes.front(), s);
        ASSERT_EQ(path->nodes.back(), t);
        EXPECT_NEAR(path->cost, *best, kCostTolerance) << "trial " << trial;
        const std::optional<double> walked = WalkCost(g, path->nodes, extra);
        ASSERT_TRUE(walked.has_value()) << "trial " << trial;
        EXPECT_NEAR(*walked, path->cost, kCostTolerance);
      }
    }
  }
  EXPECT_GT(solved, 1000);
  EXPECT_GT(unreachable, 300);
}

// 0 -> 1 -> 3 and 0 -> 2 -> 3 at equal cost: a square.
TopologyGraph Square(bool reversed_insertion) {
  TopologyGraph g;
  for (int i = 0; i < 4; ++i) g.AddNode(NodeId("s", i), {0, 0});
  const std::vector<std::pair<int, int>> edges =
      reversed_insertion ? std::vector<std::pair<int, int>>{{2, 3}, {0, 2}, {1, 3}, {0, 1}}
                         : std::vector<std::pair<int, int>>{{0, 1}, {1, 3}, {0, 2}, {2, 3}};
  for (const auto& [u, v] : edges) {
    g.AddArc(u, v, 1.0);
    g.AddArc(v, u, 1.0);
  }
  return g;
}

// Confirms equal-cost paths resolve to the lower-index predecessor whatever the arc order.
TEST(GraphPlannerTest, BreaksTiesTowardsLowerIndices) {
  for (bool reversed : {false, true}) {
    EXPECT_EQ(PlanGraphPath(Square(reversed), 0, 3)->nodes, (std::vector<int>{0, 1, 3}));
    EXPECT_EQ(PlanGraphPath(Square(reversed), 3, 0)->nodes, (std::vector<int>{3, 1, 0}));
  }
  const std::optional<GraphPath> stay = PlanGraphPath(Square(false), 2, 2);
  EXPECT_EQ(stay->nodes, (std::vector<int>{2}));
  EXPECT_EQ(stay->cost, 0.0);
}

// Confirms entered nodes' fixed and extra costs count, the start's do not, and
// extra costs (other robots near node 1) divert the path.
TEST(GraphPlannerTest, CountsCostsOfEnteredNodes) {
  TopologyGraph g = Square(false);
  g.SetNodeCost(0, 10.0);  // the start: not counted
  g.SetNodeCost(3, 0.5);   // the goal: counted
  const std::optional<GraphPath> plain = PlanGraphPath(g, 0, 3);
  EXPECT_EQ(plain->nodes, (std::vector<int>{0, 1, 3}));
  EXPECT_DOUBLE_EQ(plain->cost, 2.5);
  const std::vector<double> near_robot = {0.0, 0.7, 0.0, 0.0};
  const std::optional<GraphPath> diverted = PlanGraphPath(g, 0, 3, near_robot);
  EXPECT_EQ(diverted->nodes, (std::vector<int>{0, 2, 3}));
  EXPECT_DOUBLE_EQ(diverted->cost, 2.5);
}

// Confirms a blocked edge forces the detour, and none once both ways are blocked.
TEST(GraphPlannerTest, AvoidsBlockedEdges) {
  TopologyGraph g = Square(false);
  g.BlockEdge(1, 3);
  EXPECT_EQ(PlanGraphPath(g, 0, 3)->nodes, (std::vector<int>{0, 2, 3}));
  g.BlockEdge(2, 0);
  EXPECT_FALSE(PlanGraphPath(g, 0, 3).has_value());
  EXPECT_FALSE(PlanGraphPath(g, 3, 0).has_value());
}

// Confirms bad indices and extra costs are rejected, and options validate.
TEST(GraphPlannerTest, RejectsBadInput) {
  const TopologyGraph g = Square(false);
  EXPECT_THROW(PlanGraphPath(g, 0, 4), std::invalid_argument);
  EXPECT_THROW(PlanGraphPath(g, -1, 2), std::invalid_argument);
  const std::vector<double> short_costs = {1.0, 2.0};
  EXPECT_THROW(PlanGraphPath(g, 0, 3, short_costs), std::invalid_argument);
  const std::vector<double> negative = {0.0, -1.0, 0.0, 0.0};
  EXPECT_THROW(PlanGraphPath(g, 0, 3, negative), std::invalid_argument);
  GraphPlannerOptions options;
  EXPECT_NO_THROW(options.Validate());
  options.entry_radius_m = 0.0;
  EXPECT_THROW(options.Validate(), std::invalid_argument);
}

core::Point2Uncertain At(double x, double y) { return {Eigen::Vector2d(x, y), {}}; }

// Two nodes left and right of the origin, joined around a wall: "w" at (-2, 0),
// "e" at (3, 0), via "n" at (0, 4). A wall segment x = 1, y in [-1, 1] stands
// between the origin and "e"; a multi-segment line x = -1 with a member over
// y in [0.5, 2] does not hide "w".
core::RobotMap WalledMap() {
  core::RobotMap map;
  map.name = "walled";
  map.nodes = {{"w", {-2, 0, 0}, true}, {"e", {3, 0, 0}, true}, {"n", {0, 4, 0}, false}};
  map.edges = {{"w", "n", 4.5}, {"n", "e", 5.0}};
  core::MapSegment wall;
  wall.id = "wall";
  wall.first_endpoint = At(1, -1);
  wall.second_endpoint = At(1, 1);
  map.segments.push_back(wall);
  core::MapMultiSegmentLine line;
  line.id = "door_wall";
  line.segments = {{At(-1, 0.5), At(-1, 2)}};
  map.multi_segment_lines.push_back(line);
  return map;
}

// Confirms the position enters only at nodes in sight and within the radius:
// the wall hides "e" (3 m away) so the plan goes via "w"; a multi-segment line
// member hides "w" once moved across its span; none when nothing is visible.
TEST(GraphPlannerTest, EntersFromPositionOnlyThroughVisibleNodes) {
  core::RobotMap map = WalledMap();
  const TopologyGraph graph(map);
  const int e = graph.IndexOf("e");
  const std::optional<GraphPath> path = PlanFromPosition(graph, map, {0, 0}, e);
  ASSERT_TRUE(path.has_value());
  // n is 4 m away and visible: 4 + 5 beats 2 + 4.5 + 5 via w.
  EXPECT_EQ(path->nodes, (std::vector<int>{graph.IndexOf("n"), e}));
  EXPECT_DOUBLE_EQ(path->cost, 9.0);
  GraphPlannerOptions near;
  near.entry_radius_m = 3.5;  // n out of reach: enter at w
  const std::optional<GraphPath> via_w = PlanFromPosition(graph, map, {0, 0}, e, near);
  ASSERT_TRUE(via_w.has_value());
  EXPECT_EQ(via_w->nodes, (std::vector<int>{graph.IndexOf("w"), graph.IndexOf("n"), e}));
  EXPECT_DOUBLE_EQ(via_w->cost, 2.0 + 4.5 + 5.0);
  map.multi_segment_lines[0].segments = {{At(-1, -2), At(-1, 2)}};  // now hides w as well
  EXPECT_FALSE(PlanFromPosition(graph, map, {0, 0}, e, near).has_value());
  map.segments.clear();  // e is in sight again, 3 m away
  const std::optional<GraphPath> direct = PlanFromPosition(graph, map, {0, 0}, e, near);
  ASSERT_TRUE(direct.has_value());
  EXPECT_EQ(direct->nodes, (std::vector<int>{e}));
  EXPECT_DOUBLE_EQ(direct->cost, 3.0);
}

}  // namespace
}  // namespace pavilion::nav
