// Robot-robot proximity from ground truth (issue 15's near misses and
// minimum distance): exact hull distances and near-miss episodes.
#include "scenarios/metrics/robot_proximity.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "core/geometry/polygon.h"
#include "core/geometry/segment2.h"
#include "core/random/random_stream.h"

namespace pavilion::scenarios {
namespace {

core::Polygon2 Square(double half) {
  return {{-half, -half}, {half, -half}, {half, half}, {-half, half}};
}

TEST(ConvexPolygonDistance, IsTheGapBetweenHullsAndZeroWhenTheyMeet) {
  const core::Polygon2 a = Square(0.5);
  core::Polygon2 b = Square(0.5);
  for (auto& v : b) v.x() += 1.3;
  EXPECT_NEAR(ConvexPolygonDistance(a, b), 0.3, 1e-12);
  for (auto& v : b) v.x() -= 0.5;  // overlapping
  EXPECT_EQ(ConvexPolygonDistance(a, b), 0.0);
  // A cross: no vertex inside the other, edges crossing.
  const core::Polygon2 wide{{-1, -0.1}, {1, -0.1}, {1, 0.1}, {-1, 0.1}};
  const core::Polygon2 tall{{-0.1, -1}, {0.1, -1}, {0.1, 1}, {-0.1, 1}};
  EXPECT_EQ(ConvexPolygonDistance(wide, tall), 0.0);
}

// The edge pairs skipped by their boxes cannot change the result: octagons
// (Robox's base) at random poses give exactly what testing every pair gives.
TEST(ConvexPolygonDistance, SkippingFarEdgePairsGivesTheSameBits) {
  const auto every_pair = [](const core::Polygon2& a, const core::Polygon2& b) {
    for (const Eigen::Vector2d& v : a) {
      if (core::Contains(b, v)) return 0.0;
    }
    for (const Eigen::Vector2d& v : b) {
      if (core::Contains(a, v)) return 0.0;
    }
    double d = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < a.size(); ++i) {
      for (std::size_t j = 0; j < b.size(); ++j) {
        const Eigen::Vector2d& a0 = a[i];
        const Eigen::Vector2d& a1 = a[(i + 1) % a.size()];
        const Eigen::Vector2d& b0 = b[j];
        const Eigen::Vector2d& b1 = b[(j + 1) % b.size()];
        if (core::SegmentsCross(a0, a1, b0, b1)) return 0.0;
        d = std::min(
            {d, core::PointSegmentDistance(a0, b0, b1), core::PointSegmentDistance(b0, a0, a1)});
      }
    }
    return d;
  };
  const auto octagon = [](const Eigen::Vector2d& at, double yaw) {
    core::Polygon2 p;
    for (int k = 0; k < 8; ++k) {
      const double a = yaw + std::numbers::pi / 4 * k;
      p.push_back(at + 0.4 * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
    return p;
  };
  core::RandomStream random(3, 0);
  int touching = 0;
  for (int k = 0; k < 20000; ++k) {
    const core::Polygon2 a = octagon({0, 0}, random.Uniform(0.0, 1.0));
    const core::Polygon2 b =
        octagon({random.Uniform(-1.5, 1.5), random.Uniform(-1.5, 1.5)}, random.Uniform(0.0, 1.0));
    const double expected = every_pair(a, b);
    ASSERT_EQ(ConvexPolygonDistance(a, b), expected) << k;
    touching += expected == 0.0 ? 1 : 0;
  }
  EXPECT_GT(touching, 1000);  // both overlapping and apart pairs were drawn
  EXPECT_LT(touching, 19000);
}

TEST(RobotProximity, CountsANearMissOncePerEpisode) {
  RobotProximity p({Square(0.3), Square(0.3), Square(0.3)});
  std::vector<RobotProximity::NearMiss> began;
  std::vector<core::Pose2> poses{{0, 0, 0}, {5, 0, 0}, {0, 10, 0}};
  const double dt = 0.1;
  // Robot 1 comes to 0.1 m of robot 0, stays for 1 s, then leaves.
  for (double x : {2.0, 1.0, 0.75, 0.7, 0.7, 0.7, 0.7, 0.7, 0.7, 0.7, 0.7, 0.74, 0.9, 2.0}) {
    poses[1].x_m = x;
    p.Update(dt, poses, &began);
  }
  ASSERT_EQ(began.size(), 1u);
  EXPECT_EQ(began[0].a, 0);
  EXPECT_EQ(began[0].b, 1);
  EXPECT_NEAR(began[0].distance_m, 0.15, 1e-12);
  EXPECT_EQ(p.fleet().near_misses, 1);
  EXPECT_EQ(p.robot(0).near_misses, 1);
  EXPECT_EQ(p.robot(2).near_misses, 0);
  EXPECT_NEAR(p.fleet().min_distance_m, 0.1, 1e-12);
  // Near from 0.75 (0.15 m) until 0.9 (0.3 m > 0.25): 10 steps of 0.1 s.
  EXPECT_NEAR(p.fleet().time_near_s, 1.0, 1e-9);
  // Back again: a second episode.
  poses[1].x_m = 0.65;
  p.Update(dt, poses, &began);
  EXPECT_EQ(p.fleet().near_misses, 2);
  EXPECT_NEAR(p.robot(2).min_distance_m, 10.0 - 0.6, 1e-12);
}

TEST(RobotProximity, CountsTwoRobotsAtOneStationOncePerEpisode) {
  RobotProximity p({Square(0.3), Square(0.3)});
  p.WatchStations({{0, 0}, {5, 0}});
  std::vector<RobotProximity::NearMiss> began;
  std::vector<RobotProximity::StationConflict> conflicts;
  std::vector<core::Pose2> poses{{0.2, 0, 0}, {3, 0, 0}};
  std::vector<int> began_at;
  int step = 0;
  for (double x : {3.0, 1.5, 0.9, 0.9, 1.2, 0.8}) {  // within 1 m at 0.9, 0.9 and 0.8
    poses[1].y_m = x;
    poses[1].x_m = 0.0;
    const std::size_t before = conflicts.size();
    p.Update(0.1, poses, &began, &conflicts);
    if (conflicts.size() > before) began_at.push_back(step);
    ++step;
  }
  EXPECT_EQ(p.fleet().station_conflicts, 2);
  // Each episode is reported once, when it begins, with its station and robots.
  EXPECT_EQ(began_at, (std::vector<int>{2, 5}));
  ASSERT_EQ(conflicts.size(), 2u);
  EXPECT_EQ(conflicts[0].station, 0);
  EXPECT_EQ(conflicts[0].robots, (std::vector<int>{0, 1}));
}

}  // namespace
}  // namespace pavilion::scenarios
