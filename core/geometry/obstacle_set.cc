#include "core/geometry/obstacle_set.h"

#include <algorithm>
#include <limits>

#include "core/geometry/segment2.h"

namespace pavilion::core {

double ObstacleSet::Clearance(const Eigen::Vector2d& a, const Eigen::Vector2d& b) const {
  double best = std::numeric_limits<double>::infinity();
  const Box2 box = SegmentBox(a, b);
  for (const auto& s : segments) {
    const Box2 sb = SegmentBox(s.a_m, s.b_m);
    if (!box.Overlaps(sb, best)) continue;
    best = std::min(best, SegmentSegmentDistance(a, b, s.a_m, s.b_m));
  }
  for (const auto& c : circles) {
    best = std::min(best, std::max(0.0, PointSegmentDistance(c.center_m, a, b) - c.radius_m));
  }
  return best;
}

}  // namespace pavilion::core
