#include "core/map/map_geometry.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pavilion::core {
namespace {

using Vec2 = Eigen::Vector2d;

// Below this |component| a clipped line runs parallel to that axis.
constexpr double kParallelEpsilon = 1e-12;

// The part of the infinite line inside `box` as a segment; false when it misses.
bool ClipLineToBox(const Line& line, const Box2& box, Vec2* a, Vec2* b) {
  const Vec2 normal = line.normal();
  const Vec2 foot = line.r_m * normal;
  const Vec2 direction(-normal.y(), normal.x());
  double t_lo = -std::numeric_limits<double>::infinity();
  double t_hi = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 2; ++k) {
    if (std::abs(direction[k]) < kParallelEpsilon) {
      if (foot[k] < box.lo[k] || foot[k] > box.hi[k]) return false;
      continue;
    }
    const double t0 = (box.lo[k] - foot[k]) / direction[k];
    const double t1 = (box.hi[k] - foot[k]) / direction[k];
    t_lo = std::max(t_lo, std::min(t0, t1));
    t_hi = std::min(t_hi, std::max(t0, t1));
  }
  if (!(t_lo <= t_hi)) return false;
  *a = foot + t_lo * direction;
  *b = foot + t_hi * direction;
  return true;
}

}  // namespace

MapGeometry CollectMapGeometry(const RobotMap& map, InfiniteLines lines) {
  MapGeometry g;
  const auto add_segment = [&g](const Vec2& a, const Vec2& b) {
    g.segments.emplace_back(a, b);
    g.bounds.Add(a);
    g.bounds.Add(b);
  };
  const auto add_disc = [&g](const Vec2& centre, double radius_m) {
    g.discs.emplace_back(centre, radius_m);
    g.bounds.Add(centre - Vec2(radius_m, radius_m));
    g.bounds.Add(centre + Vec2(radius_m, radius_m));
  };
  for (const MapSegment& s : map.segments) {
    add_segment(s.first_endpoint.position_m, s.second_endpoint.position_m);
  }
  for (const MapMultiSegmentLine& m : map.multi_segment_lines) {
    for (const auto& [a, b] : m.segments) add_segment(a.position_m, b.position_m);
  }
  for (const MapPoint& p : map.points) add_disc(p.point.position_m, p.radius_m);
  for (const MapBeacon& b : map.beacons) add_disc(b.point.position_m, 0.0);
  if (lines == InfiniteLines::kOmit) return g;
  if (g.bounds.lo.x() > g.bounds.hi.x()) return g;  // no finite geometry: lines are skipped
  for (const MapLine& l : map.lines) {
    Vec2 a, b;
    if (ClipLineToBox(l.line, g.bounds, &a, &b)) g.segments.emplace_back(a, b);
  }
  return g;
}

}  // namespace pavilion::core
