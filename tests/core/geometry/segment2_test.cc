// Plane geometry of segments, rays and circles: distances and intersection
// parameters on cases with known answers.
#include "core/geometry/segment2.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/geometry/obstacle_set.h"

namespace pavilion::core {
namespace {

using Vec2 = Eigen::Vector2d;

// Point–segment distance: perpendicular inside, to the nearer end outside, and
// to the point itself for a degenerate segment.
TEST(Segment2Test, PointSegmentDistance) {
  EXPECT_DOUBLE_EQ(PointSegmentDistance({1, 2}, {0, 0}, {3, 0}), 2.0);
  EXPECT_DOUBLE_EQ(PointSegmentDistance({-3, 4}, {0, 0}, {3, 0}), 5.0);
  EXPECT_DOUBLE_EQ(PointSegmentDistance({6, 4}, {0, 0}, {3, 0}), 5.0);
  EXPECT_DOUBLE_EQ(PointSegmentDistance({3, 4}, {0, 0}, {0, 0}), 5.0);
}

// Crossing is proper only: touching at an endpoint or collinear overlap is not.
TEST(Segment2Test, SegmentsCrossProperlyOnly) {
  EXPECT_TRUE(SegmentsCross({0, 0}, {2, 2}, {0, 2}, {2, 0}));
  EXPECT_FALSE(SegmentsCross({0, 0}, {1, 1}, {1, 1}, {2, 0}));
  EXPECT_FALSE(SegmentsCross({0, 0}, {2, 0}, {1, 0}, {3, 0}));
  EXPECT_FALSE(SegmentsCross({0, 0}, {1, 0}, {0, 1}, {1, 1}));
}

// Segment–segment distance: 0 when crossing, else the nearest endpoint's.
TEST(Segment2Test, SegmentSegmentDistance) {
  EXPECT_DOUBLE_EQ(SegmentSegmentDistance({0, 0}, {2, 2}, {0, 2}, {2, 0}), 0.0);
  EXPECT_DOUBLE_EQ(SegmentSegmentDistance({0, 0}, {1, 0}, {0, 1}, {1, 1}), 1.0);
  EXPECT_DOUBLE_EQ(SegmentSegmentDistance({0, 0}, {1, 0}, {2, -1}, {2, 1}), 1.0);
}

// The ray parameter at the hit, +inf for misses and parallel segments.
TEST(Segment2Test, RaySegmentHit) {
  EXPECT_DOUBLE_EQ(RaySegmentHit({0, 0}, {4, 0}, {1, -1}, {1, 1}), 0.25);
  EXPECT_TRUE(std::isinf(RaySegmentHit({0, 0}, {0.5, 0}, {1, -1}, {1, 1})));
  EXPECT_TRUE(std::isinf(RaySegmentHit({0, 0}, {4, 0}, {0, 1}, {4, 1})));
}

// Line–circle: two parameters through the centre, none when it passes by or touches.
TEST(Segment2Test, LineCircleHits) {
  const std::vector<double> t = LineCircleHits({-2, 0}, {2, 0}, {0, 0}, 1.0);
  ASSERT_EQ(t.size(), 2u);
  EXPECT_DOUBLE_EQ(t[0], 0.25);
  EXPECT_DOUBLE_EQ(t[1], 0.75);
  EXPECT_TRUE(LineCircleHits({-2, 2}, {2, 2}, {0, 0}, 1.0).empty());
  EXPECT_TRUE(LineCircleHits({-2, 1}, {2, 1}, {0, 0}, 1.0).empty());
  EXPECT_TRUE(LineCircleHits({1, 1}, {1, 1}, {0, 0}, 2.0).empty());
}

// Boxes grow with their points and overlap within a margin.
TEST(Segment2Test, BoxesOverlapWithinTheMargin) {
  const Box2 a = SegmentBox({0, 0}, {1, 1});
  const Box2 b = SegmentBox({1.5, 0}, {2, 1});
  EXPECT_FALSE(a.Overlaps(b, 0.0));
  EXPECT_TRUE(a.Overlaps(b, 0.6));
  EXPECT_DOUBLE_EQ(a.hi.x(), 1.0);
}

// Clearance of a path: the nearest segment or circle surface, +inf with none.
TEST(ObstacleSetTest, ClearanceIsTheNearestObstacle) {
  ObstacleSet obstacles;
  EXPECT_TRUE(std::isinf(obstacles.Clearance({0, 0}, {1, 0})));
  obstacles.segments.push_back({{0, 2}, {4, 2}});
  obstacles.circles.push_back({{2, -1.5}, 0.5});
  EXPECT_DOUBLE_EQ(obstacles.Clearance({0, 0}, {4, 0}), 1.0);
  obstacles.circles.push_back({{2, 0}, 0.0});
  EXPECT_DOUBLE_EQ(obstacles.Clearance({0, 0}, {4, 0}), 0.0);
}

}  // namespace
}  // namespace pavilion::core
