#include "sim/world/wall_geometry.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/geometry/polygon.h"

namespace pavilion::sim {
namespace {

double DistanceToLine(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                      const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = (b - a).normalized();
  const Eigen::Vector2d n(-d.y(), d.x());
  return std::abs((p - a).dot(n));
}

Wall LWall() {
  Wall w;
  w.id = "l";
  w.points_m = {{0, 0}, {4, 0}, {4, 3}};
  w.thickness_m = 0.2;
  return w;
}

// An L-shaped wall: each quad's long sides lie at half the thickness from its
// centre line, quads are counter-clockwise and neighbours share the mitre edge.
TEST(WallGeometryTest, MitredQuadsKeepThicknessAndShareJoints) {
  const Wall w = LWall();
  const auto quads = WallFootprint(w);
  ASSERT_EQ(quads.size(), 2u);
  for (std::size_t i = 0; i < quads.size(); ++i) {
    const auto& q = quads[i];
    EXPECT_GT(core::SignedArea({q.begin(), q.end()}), 0.0);
    for (const auto& corner : q) {
      EXPECT_NEAR(DistanceToLine(corner, w.points_m[i], w.points_m[i + 1]), 0.1, 1e-12);
    }
  }
  EXPECT_TRUE(quads[0][1].isApprox(quads[1][0]));  // right side joint
  EXPECT_TRUE(quads[0][2].isApprox(quads[1][3]));  // left side joint
  // The outer corner of a right-angle mitre sits at (4.1, -0.1).
  EXPECT_TRUE(quads[0][1].isApprox(Eigen::Vector2d(4.1, -0.1)));
  // Footprint area = centre-line length × thickness for a mitred right angle.
  double area = 0.0;
  for (const auto& q : quads) area += core::SignedArea({q.begin(), q.end()});
  EXPECT_NEAR(area, 7.0 * 0.2, 1e-12);
}

// The outline of an open wall is a closed CCW loop of 2n + 2 segments whose
// length is both sides plus the caps.
TEST(WallGeometryTest, OutlineIsClosedCounterClockwiseLoop) {
  const Wall w = LWall();
  const auto outline = WallOutline(w);
  ASSERT_EQ(outline.size(), 6u);
  core::Polygon2 loop;
  double length = 0.0;
  for (std::size_t i = 0; i < outline.size(); ++i) {
    length += (outline[i][1] - outline[i][0]).norm();
    loop.push_back(outline[i][0]);
  }
  // Segments follow each other head to tail.
  for (std::size_t i = 0; i + 1 < outline.size(); ++i) {
    bool linked = false;
    for (const auto& s : outline) linked |= s[0].isApprox(outline[i][1]);
    EXPECT_TRUE(linked) << "segment " << i;
  }
  // Outer sides 4.1 + 3.1, inner sides 3.9 + 2.9, two caps of 0.2.
  EXPECT_NEAR(length, 4.1 + 3.1 + 3.9 + 2.9 + 0.4, 1e-12);
}

// A closed square room has no caps: 8 outline segments, inner loop clockwise
// seen from the room (solid on the left of each segment).
TEST(WallGeometryTest, ClosedWallHasNoCaps) {
  Wall w;
  w.points_m = {{0, 0}, {5, 0}, {5, 4}, {0, 4}};
  w.closed = true;
  w.thickness_m = 0.2;
  const auto outline = WallOutline(w);
  ASSERT_EQ(outline.size(), 8u);
  double length = 0.0;
  for (const auto& s : outline) length += (s[1] - s[0]).norm();
  EXPECT_NEAR(length, 2 * (5.2 + 4.2) + 2 * (4.8 + 3.8), 1e-12);
  // A point inside the room sees every inner segment with the solid beyond it:
  // the room centre lies to the right of inner segments.
  const Eigen::Vector2d centre(2.5, 2.0);
  int inner = 0;
  for (const auto& s : outline) {
    const Eigen::Vector2d d = s[1] - s[0];
    const Eigen::Vector2d to_c = centre - s[0];
    const double cross = d.x() * to_c.y() - d.y() * to_c.x();
    const bool is_inner = (s[0] - centre).cwiseAbs().maxCoeff() < 2.5;
    if (is_inner) {
      ++inner;
      EXPECT_LT(cross, 0.0);
    }
  }
  EXPECT_EQ(inner, 4);
}

// Sharp turns produce long mitres, which validation rejects.
TEST(WallGeometryTest, MitreRatioGrowsWithSharpTurns) {
  Wall w;
  w.thickness_m = 0.2;
  w.points_m = {{0, 0}, {4, 0}, {4, 3}};
  EXPECT_NEAR(MaxMitreRatio(w), std::sqrt(2.0), 1e-12);
  w.points_m = {{0, 0}, {4, 0}, {0, 0.1}};
  EXPECT_GT(MaxMitreRatio(w), kMaxMitreRatio);
}

// Box footprints are CCW rectangles with the box's yaw.
TEST(WallGeometryTest, BoxFootprintRotates) {
  Box b;
  b.pose = {1.0, 2.0, std::numbers::pi / 2};
  b.size_m = {2.0, 1.0, 1.0};
  const Quad q = BoxFootprint(b);
  EXPECT_NEAR(core::SignedArea({q.begin(), q.end()}), 2.0, 1e-12);
  EXPECT_TRUE(q[0].isApprox(Eigen::Vector2d(1.5, 1.0)));
}

}  // namespace
}  // namespace pavilion::sim
