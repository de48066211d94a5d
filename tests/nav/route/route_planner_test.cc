// Shortest routes over a map's topology and tours through stops.
#include "nav/route/route_planner.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace pavilion::nav {
namespace {

// a - b - c in a row (1 m apart) and a detour a - d - c of 3 m.
core::RobotMap Graph() {
  core::RobotMap map;
  map.name = "graph";
  map.nodes = {{"a", {0, 0, 0}, true},
               {"b", {1, 0, 0}, false},
               {"c", {2, 0, 0}, true},
               {"d", {1, 1.2, 0}, false}};
  map.edges = {{"a", "b", 1.0}, {"b", "c", 1.0}, {"a", "d", 1.5}, {"d", "c", 1.5}};
  return map;
}

TEST(RoutePlanner, TakesTheShortestRoute) {
  EXPECT_EQ(ShortestRoute(Graph(), "a", "c"), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(ShortestRoute(Graph(), "c", "a"), (std::vector<std::string>{"c", "b", "a"}));
  EXPECT_EQ(ShortestRoute(Graph(), "d", "d"), (std::vector<std::string>{"d"}));
  core::RobotMap heavy = Graph();
  heavy.edges[0].weight = 5.0;  // a - b now costs more than the detour
  EXPECT_EQ(ShortestRoute(heavy, "a", "c"), (std::vector<std::string>{"a", "d", "c"}));
}

TEST(RoutePlanner, TourJoinsRoutesWithoutRepeatingStops) {
  const std::vector<Eigen::Vector2d> path = TourPath(Graph(), {"a", "c", "d"});
  ASSERT_EQ(path.size(), 4u);  // a b c d
  EXPECT_TRUE(path[2].isApprox(Eigen::Vector2d(2, 0)));
  EXPECT_NEAR(PathLength(path), 2.0 + std::hypot(1.0, 1.2), 1e-12);
}

TEST(RoutePlanner, RejectsUnknownNodesAndDisconnectedGraphs) {
  EXPECT_THROW(ShortestRoute(Graph(), "a", "x"), std::invalid_argument);
  core::RobotMap split = Graph();
  split.nodes.push_back({"island", {9, 9, 0}, true});
  EXPECT_THROW(ShortestRoute(split, "a", "island"), std::invalid_argument);
  EXPECT_THROW(TourPath(Graph(), {"a"}), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::nav
