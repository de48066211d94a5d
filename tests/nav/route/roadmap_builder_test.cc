// The roadmap builder over a free-space grid: via nodes fill the reachable
// floor, every edge keeps the robot radius from the obstacles, and a wall with
// a door leaves one connected graph whose edges pass through the door.
#include "nav/route/roadmap_builder.h"

#include <gtest/gtest.h>

#include <map>
#include <set>

namespace pavilion::nav {
namespace {

using Vec2 = Eigen::Vector2d;

constexpr double kCellM = 0.05;
constexpr double kRadiusM = 0.3;

// A 12 m × 6 m room, split at x = 6 by a wall with a 1.4 m door at y ∈ [2.3, 3.7].
core::ObstacleSet RoomWithDoor() {
  core::ObstacleSet o;
  const Vec2 c[4] = {{0, 0}, {12, 0}, {12, 6}, {0, 6}};
  for (int k = 0; k < 4; ++k) o.segments.push_back({c[k], c[(k + 1) % 4]});
  o.segments.push_back({{6, 0}, {6, 2.3}});
  o.segments.push_back({{6, 3.7}, {6, 6}});
  return o;
}

FreeSpaceGrid FloodedGrid(const core::ObstacleSet& o, const Vec2& seed) {
  FreeSpaceGrid free({0, 0}, {12, 6}, o, 1.5, kCellM);
  std::size_t cell;
  EXPECT_TRUE(free.CellOf(seed, &cell));
  free.Flood({cell}, kRadiusM);
  return free;
}

std::vector<core::MapNode> Stations() {
  return {{"station_a", {1.5, 3.0, 0.0}, true}, {"station_b", {10.5, 3.0, 0.0}, true}};
}

// Clearances on the grid: the cap far from walls, the distance next to them;
// the flood reaches both rooms through the door but not the wall itself.
TEST(FreeSpaceGridTest, ClearanceAndReachability) {
  const core::ObstacleSet o = RoomWithDoor();
  const FreeSpaceGrid free = FloodedGrid(o, {1.5, 3.0});
  std::size_t i;
  ASSERT_TRUE(free.CellOf({3.0, 3.0}, &i));
  EXPECT_FLOAT_EQ(free.clearance(i), 1.5f);
  ASSERT_TRUE(free.CellOf({0.51, 3.0}, &i));
  EXPECT_NEAR(free.clearance(i), 0.525, 1e-6);  // cell centre at x = 0.525
  EXPECT_TRUE(free.ReachableAt({10.5, 3.0}));
  EXPECT_FALSE(free.ReachableAt({6.0, 1.0}));
  EXPECT_FALSE(free.ReachableAt({0.1, 3.0}));
}

// Every edge is clear by the robot radius, the graph is connected through the
// door, and the via nodes get fresh numbered names.
TEST(RoadmapBuilderTest, ConnectsTheRoomsThroughTheDoor) {
  const core::ObstacleSet o = RoomWithDoor();
  const FreeSpaceGrid free = FloodedGrid(o, {1.5, 3.0});
  RoadmapOptions options;
  options.robot_radius_m = kRadiusM;
  options.via_spacing_m = 2.0;
  std::vector<std::string> warnings;
  const Roadmap map = BuildRoadmap(Stations(), free, o, options, &warnings);
  EXPECT_TRUE(warnings.empty()) << warnings.front();
  ASSERT_GT(map.nodes.size(), 2u);
  EXPECT_EQ(map.nodes[0].id, "station_a");
  EXPECT_EQ(map.nodes[2].id, "via_001");
  std::map<std::string, Vec2> at;
  for (const auto& n : map.nodes) at[n.id] = n.pose.translation();
  std::map<std::string, std::string> parent;
  const auto find = [&](std::string s) {
    while (parent.contains(s)) s = parent[s];
    return s;
  };
  int through_door = 0;
  for (const auto& e : map.edges) {
    EXPECT_GE(o.Clearance(at[e.from], at[e.to]), kRadiusM) << e.from << "-" << e.to;
    EXPECT_NEAR(e.weight, (at[e.from] - at[e.to]).norm(), 1e-6);
    if ((at[e.from].x() - 6.0) * (at[e.to].x() - 6.0) < 0) ++through_door;
    const std::string a = find(e.from), b = find(e.to);
    if (a != b) parent[a] = b;
  }
  EXPECT_GE(through_door, 1);
  std::set<std::string> roots;
  for (const auto& n : map.nodes) roots.insert(find(n.id));
  EXPECT_EQ(roots.size(), 1u);
}

// A closed door leaves two parts: the builder says so instead of crossing the wall.
TEST(RoadmapBuilderTest, WarnsAboutSeparateParts) {
  core::ObstacleSet o = RoomWithDoor();
  o.segments.push_back({{6, 2.3}, {6, 3.7}});
  FreeSpaceGrid free({0, 0}, {12, 6}, o, 1.5, kCellM);
  std::size_t a, b;
  ASSERT_TRUE(free.CellOf({1.5, 3.0}, &a));
  ASSERT_TRUE(free.CellOf({10.5, 3.0}, &b));
  free.Flood({a, b}, kRadiusM);
  RoadmapOptions options;
  options.robot_radius_m = kRadiusM;
  options.via_spacing_m = 2.0;
  std::vector<std::string> warnings;
  const Roadmap map = BuildRoadmap(Stations(), free, o, options, &warnings);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("2 separate parts"), std::string::npos) << warnings[0];
  for (const auto& e : map.edges) EXPECT_NE(e.from, e.to);
}

// Bad options are rejected naming the field.
TEST(RoadmapBuilderTest, RejectsBadOptions) {
  RoadmapOptions options;
  options.via_spacing_m = 0.0;
  EXPECT_THROW(options.Validate(), std::invalid_argument);
  options = {};
  options.robot_radius_m = -1.0;
  EXPECT_THROW(options.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::nav
