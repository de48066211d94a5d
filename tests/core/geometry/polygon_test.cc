#include "core/geometry/polygon.h"

#include <gtest/gtest.h>

#include "core/geometry/planar_section.h"

namespace pavilion::core {
namespace {

// Shoelace area is signed by orientation.
TEST(PolygonTest, SignedAreaFollowsOrientation) {
  Polygon2 square = {{0, 0}, {2, 0}, {2, 3}, {0, 3}};
  EXPECT_DOUBLE_EQ(SignedArea(square), 6.0);
  Polygon2 reversed(square.rbegin(), square.rend());
  EXPECT_DOUBLE_EQ(SignedArea(reversed), -6.0);
}

// Containment of points of a concave (L-shaped) polygon.
TEST(PolygonTest, ContainsHandlesConcavePolygons) {
  const Polygon2 l = {{0, 0}, {3, 0}, {3, 1}, {1, 1}, {1, 3}, {0, 3}};
  EXPECT_TRUE(Contains(l, {0.5, 2.5}));
  EXPECT_TRUE(Contains(l, {2.5, 0.5}));
  EXPECT_FALSE(Contains(l, {2.0, 2.0}));
  EXPECT_FALSE(Contains(l, {-0.1, 0.5}));
}

// A bow-tie crosses itself; a convex polygon does not.
TEST(PolygonTest, IsSimpleDetectsSelfIntersection) {
  EXPECT_TRUE(IsSimple({{0, 0}, {1, 0}, {1, 1}, {0, 1}}));
  EXPECT_FALSE(IsSimple({{0, 0}, {1, 1}, {1, 0}, {0, 1}}));
  EXPECT_FALSE(IsSimple({{0, 0}, {1, 0}}));
}

// The gap between convex polygons: edge to edge, corner to edge, 0 when they
// overlap or one holds the other.
TEST(PolygonTest, ConvexPolygonGapIsTheLeastEdgeDistance) {
  const Polygon2 unit = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  const auto shifted = [&](double dx, double dy) {
    Polygon2 p = unit;
    for (Eigen::Vector2d& v : p) v += Eigen::Vector2d(dx, dy);
    return p;
  };
  EXPECT_NEAR(ConvexPolygonGap(unit, shifted(1.25, 0.5)), 0.25, 1e-12);  // side to side
  EXPECT_NEAR(ConvexPolygonGap(unit, shifted(1.3, 1.4)), 0.5, 1e-12);    // corner to corner
  EXPECT_DOUBLE_EQ(ConvexPolygonGap(unit, shifted(0.5, 0.5)), 0.0);      // overlapping
  const Polygon2 inner = {{0.4, 0.4}, {0.6, 0.4}, {0.6, 0.6}, {0.4, 0.6}};
  EXPECT_DOUBLE_EQ(ConvexPolygonGap(unit, inner), 0.0);  // one inside the other
  EXPECT_DOUBLE_EQ(ConvexPolygonGap(inner, unit), 0.0);
}

// Section bounds include circles' extents and total length sums segments.
TEST(PlanarSectionTest, BoundsAndLengths) {
  PlanarSection s;
  const int e = s.AddElement({"wall", LaserResponse::kNormal, false});
  s.segments.push_back({{0, 0}, {3, 4}, e});
  s.circles.push_back({{5, 5}, 1.0, e});
  Eigen::Vector2d lo, hi;
  ASSERT_TRUE(s.Bounds(&lo, &hi));
  EXPECT_TRUE(lo.isApprox(Eigen::Vector2d(0, 0)));
  EXPECT_TRUE(hi.isApprox(Eigen::Vector2d(6, 6)));
  EXPECT_DOUBLE_EQ(s.TotalSegmentLength(), 5.0);
  EXPECT_STREQ(ToString(LaserResponse::kTransparent), "transparent");
}

}  // namespace
}  // namespace pavilion::core
