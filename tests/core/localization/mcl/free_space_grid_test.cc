// Where random particles are drawn: the map's free space reached from its
// topology nodes, with the robot's clearance.
#include "core/localization/mcl/free_space_grid.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "core/geometry/segment2.h"

namespace pavilion::core {
namespace {

using Vec2 = Eigen::Vector2d;

Point2Uncertain At(double x, double y) { return {Vec2(x, y), Eigen::Matrix2d::Identity() * 1e-6}; }

// A closed room [2, 6]^2 with a node at its centre, and an edge point at
// (10, 10) that stretches the bounding box over a node-less outside region.
RobotMap ClosedRoom() {
  RobotMap map;
  const Vec2 c[4] = {{2, 2}, {6, 2}, {6, 6}, {2, 6}};
  for (int i = 0; i < 4; ++i) {
    MapSegment s;
    s.id = "wall_" + std::to_string(i);
    s.first_endpoint = {c[i], Eigen::Matrix2d::Identity() * 1e-6};
    s.second_endpoint = {c[(i + 1) % 4], Eigen::Matrix2d::Identity() * 1e-6};
    map.segments.push_back(s);
  }
  map.points.push_back({"far_edge", At(10, 10), 0.0});
  map.nodes.push_back({"centre", {4.0, 4.0, 0.0}, true});
  return map;
}

double WallDistance(const Vec2& p) {
  const Vec2 c[4] = {{2, 2}, {6, 2}, {6, 6}, {2, 6}};
  double d = 1e9;
  for (int i = 0; i < 4; ++i) d = std::min(d, PointSegmentDistance(p, c[i], c[(i + 1) % 4]));
  return d;
}

// Samples fall only inside the room the node is in, keep the robot's
// clearance (less the raster's sqrt(2) resolution) and cover the room.
TEST(MapFreeSpaceTest, SamplesOnlyTheNodesRoomWithClearance) {
  const MapFreeSpaceOptions options;
  const MapFreeSpace free_space(ClosedRoom(), options);
  RandomStream random(7, 1);
  Vec2 lo(1e9, 1e9), hi(-1e9, -1e9), mean = Vec2::Zero();
  constexpr int kSamples = 4000;
  for (int i = 0; i < kSamples; ++i) {
    const Vec2 p = free_space.Sample(random);
    ASSERT_TRUE(p.x() > 2.0 && p.x() < 6.0 && p.y() > 2.0 && p.y() < 6.0) << p.transpose();
    ASSERT_GE(WallDistance(p), options.robot_radius_m - std::sqrt(2.0) * options.resolution_m);
    ASSERT_TRUE(free_space.IsFree(p));
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
    mean += p / kSamples;
  }
  const double reach_m = options.robot_radius_m + 2.0 * options.resolution_m;
  EXPECT_LT(lo.x(), 2.0 + reach_m);
  EXPECT_LT(lo.y(), 2.0 + reach_m);
  EXPECT_GT(hi.x(), 6.0 - reach_m);
  EXPECT_GT(hi.y(), 6.0 - reach_m);
  EXPECT_NEAR(mean.x(), 4.0, 0.05);  // 3.4 m wide: sigma of the mean ~0.016 m
  EXPECT_NEAR(mean.y(), 4.0, 0.05);
  EXPECT_FALSE(free_space.IsFree({8.0, 8.0}));
  EXPECT_FALSE(free_space.IsFree({2.1, 4.0}));
  // About (4 - 2 * 0.3)^2 / 0.05^2 cells, give or take a ring of cells.
  const double expected = (3.4 / 0.05) * (3.4 / 0.05);
  EXPECT_NEAR(free_space.free_cells(), expected, 4.0 * 3.4 / 0.05 + 4.0);
}

// Without nodes every in-bounds cell with clearance is free, outside too.
TEST(MapFreeSpaceTest, WithoutNodesEveryClearCellIsFree) {
  RobotMap map = ClosedRoom();
  map.nodes.clear();
  const MapFreeSpace free_space(map);
  EXPECT_TRUE(free_space.IsFree({4.0, 4.0}));
  EXPECT_TRUE(free_space.IsFree({8.0, 8.0}));
  EXPECT_FALSE(free_space.IsFree({10.0, 10.1}));  // beside the edge point
  EXPECT_FALSE(free_space.IsFree({11.0, 11.0}));  // beyond the bounding box
}

// Samples are a function of the stream: same seed, same points.
TEST(MapFreeSpaceTest, SamplesAreReproducible) {
  const MapFreeSpace free_space(ClosedRoom());
  RandomStream a(3, 9), b(3, 9);
  for (int i = 0; i < 100; ++i) EXPECT_EQ(free_space.Sample(a), free_space.Sample(b));
}

// A map with no free cell cannot be sampled; options are validated.
TEST(MapFreeSpaceTest, RejectsEmptySpaceAndBadOptions) {
  const MapFreeSpace empty(RobotMap{});
  EXPECT_EQ(empty.free_cells(), 0);
  RandomStream random(1, 1);
  EXPECT_THROW(empty.Sample(random), std::logic_error);
  MapFreeSpaceOptions o;
  o.robot_radius_m = 0.05;  // below 2 cells
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = {};
  o.resolution_m = 0.0;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::core
