#include "core/geometry/segment2.h"

#include <algorithm>
#include <cmath>

namespace pavilion::core {

using Vec2 = Eigen::Vector2d;

double Cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

double PointSegmentDistance(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

bool SegmentsCross(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double d1 = Cross(b - a, c - a), d2 = Cross(b - a, d - a);
  const double d3 = Cross(d - c, a - c), d4 = Cross(d - c, b - c);
  return ((d1 > 0) != (d2 > 0)) && ((d3 > 0) != (d4 > 0)) && d1 != 0 && d2 != 0 && d3 != 0 &&
         d4 != 0;
}

double SegmentSegmentDistance(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  if (SegmentsCross(a, b, c, d)) return 0.0;
  return std::min({PointSegmentDistance(a, c, d), PointSegmentDistance(b, c, d),
                   PointSegmentDistance(c, a, b), PointSegmentDistance(d, a, b)});
}

double RaySegmentHit(const Vec2& o, const Vec2& e, const Vec2& c, const Vec2& d) {
  const Vec2 r = e - o, s = d - c;
  const double denom = Cross(r, s);
  if (denom == 0.0) return std::numeric_limits<double>::infinity();
  const double t = Cross(c - o, s) / denom;
  const double u = Cross(c - o, r) / denom;
  if (t < 0.0 || t > 1.0 || u < 0.0 || u > 1.0) return std::numeric_limits<double>::infinity();
  return t;
}

std::vector<double> LineCircleHits(const Vec2& o, const Vec2& e, const Vec2& c, double radius) {
  const Vec2 d = e - o, f = o - c;
  const double A = d.squaredNorm(), B = 2.0 * f.dot(d), C = f.squaredNorm() - radius * radius;
  const double disc = B * B - 4.0 * A * C;
  if (A == 0.0 || disc <= 0.0) return {};
  const double q = std::sqrt(disc);
  return {(-B - q) / (2.0 * A), (-B + q) / (2.0 * A)};
}

Box2 SegmentBox(const Vec2& a, const Vec2& b) {
  Box2 box;
  box.Add(a);
  box.Add(b);
  return box;
}

}  // namespace pavilion::core
