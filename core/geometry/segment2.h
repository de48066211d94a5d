#pragma once

// Plane geometry of points, segments, rays and circles (m): the distance and
// intersection tests that map derivation, clearance checks and roadmaps share.

#include <Eigen/Core>
#include <limits>
#include <vector>

namespace pavilion::core {

// The z component of the cross product a × b.
double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b);

// Distance from point p to the closed segment a-b; |p − a| when a = b.
double PointSegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                            const Eigen::Vector2d& b);

// True when segments a-b and c-d cross properly: each one's endpoints strictly
// on opposite sides of the other's line (touching and collinear overlaps are not).
bool SegmentsCross(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                   const Eigen::Vector2d& d);

// Smallest distance between segments a-b and c-d; 0 when they cross.
double SegmentSegmentDistance(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                              const Eigen::Vector2d& c, const Eigen::Vector2d& d);

// Parameter t in [0, 1] where the segment o + t (e − o) meets segment c-d;
// +inf if it does not (or they are parallel).
double RaySegmentHit(const Eigen::Vector2d& o, const Eigen::Vector2d& e, const Eigen::Vector2d& c,
                     const Eigen::Vector2d& d);

// Parameters where the line o + t (e − o) meets the circle (centre, radius):
// none (also for a tangent or o = e), or two in increasing order.
std::vector<double> LineCircleHits(const Eigen::Vector2d& o, const Eigen::Vector2d& e,
                                   const Eigen::Vector2d& centre, double radius);

// An axis-aligned bounding box; empty (lo > hi) until a point is added.
struct Box2 {
  Eigen::Vector2d lo{std::numeric_limits<double>::infinity(),
                     std::numeric_limits<double>::infinity()};
  Eigen::Vector2d hi{-std::numeric_limits<double>::infinity(),
                     -std::numeric_limits<double>::infinity()};

  void Add(const Eigen::Vector2d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  // True when the boxes, this one grown by `margin`, overlap.
  bool Overlaps(const Box2& o, double margin) const {
    return lo.x() - margin <= o.hi.x() && o.lo.x() - margin <= hi.x() &&
           lo.y() - margin <= o.hi.y() && o.lo.y() - margin <= hi.y();
  }
};

// The bounding box of segment a-b.
Box2 SegmentBox(const Eigen::Vector2d& a, const Eigen::Vector2d& b);

}  // namespace pavilion::core
