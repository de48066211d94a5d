#pragma once

#include <Eigen/Core>
#include <vector>

namespace pavilion::core {

using Polygon2 = std::vector<Eigen::Vector2d>;

// Signed area (m²) by the shoelace formula: positive for counter-clockwise.
double SignedArea(const Polygon2& polygon);

// True when the point lies strictly inside the simple polygon (even-odd rule).
bool Contains(const Polygon2& polygon, const Eigen::Vector2d& point);

// True when the polygon's edges do not cross each other (O(n²), for validation).
bool IsSimple(const Polygon2& polygon);

// The gap (m) between two convex polygons: the least distance between their
// edges, 0 when they overlap.
double ConvexPolygonGap(const Polygon2& a, const Polygon2& b);

// The convex hull of `points` (Andrew's monotone chain), counter-clockwise,
// without collinear points; fewer than three points come back as given.
Polygon2 ConvexHull(std::vector<Eigen::Vector2d> points);

}  // namespace pavilion::core
