#include "core/features/segment_builder.h"

#include <algorithm>
#include <cmath>

namespace pavilion::core {
namespace {

// |cos(alpha - theta_e)| below which eq. 5.3 is numerically meaningless
// (incidence within ~0.06 degrees of grazing).
constexpr double kMinRayIncidenceCos = 1e-3;

Eigen::Vector2d Cartesian(const PolarPoint& p) {
  return p.range_m * Eigen::Vector2d(std::cos(p.bearing_rad), std::sin(p.bearing_rad));
}

// Length along the line of the longest run of consecutive readings (runs are
// separated by occluders or dropouts). Collinear leg-sized clusters fused across
// a gap, such as the two legs of a person, have only short runs (§6.5).
double LongestRunLength(const Line& line, std::span<const int> members,
                        std::span<const PolarPoint> points) {
  const Eigen::Vector2d along(std::sin(line.alpha_rad), -std::cos(line.alpha_rad));
  double longest = 0.0;
  std::size_t begin = 0;
  for (std::size_t k = 1; k <= members.size(); ++k) {
    if (k < members.size() && members[k] == members[k - 1] + 1) continue;
    longest = std::max(longest, std::abs(along.dot(Cartesian(points[members[k - 1]]) -
                                                   Cartesian(points[members[begin]]))));
    begin = k;
  }
  return longest;
}

}  // namespace

double EndpointBearingSigma(const LaserScan& scan, double override_rad) {
  if (override_rad > 0.0) return override_rad;
  const std::size_t n = scan.readings.size();
  if (n < 2) return 0.0;
  // Eq. 5.2: sigma_theta_e = the angular resolution.
  return std::abs(scan.readings.back().bearing_rad - scan.readings.front().bearing_rad) /
         static_cast<double>(n - 1);
}

std::optional<Segment> BuildSegment(const Line& line, std::span<const int> members,
                                    std::span<const PolarPoint> points,
                                    std::span<const int> reading_index, double bearing_sigma_rad,
                                    const SegmentFilter& filter) {
  const int count = static_cast<int>(members.size());
  if (count < filter.min_points || count == 0) return std::nullopt;
  const PolarPoint& first = points[members.front()];
  const PolarPoint& last = points[members.back()];
  // A ray parallel to the line cannot bound it; such a fit is not a wall.
  if (std::abs(std::cos(line.alpha_rad - first.bearing_rad)) < kMinRayIncidenceCos ||
      std::abs(std::cos(line.alpha_rad - last.bearing_rad)) < kMinRayIncidenceCos) {
    return std::nullopt;
  }
  Segment s = MakeSegment(line, first.bearing_rad, last.bearing_rad, bearing_sigma_rad, count,
                          reading_index[members.front()], reading_index[members.back()]);
  if (s.length_m < filter.min_length_m ||
      LongestRunLength(line, members, points) < filter.min_length_m) {
    return std::nullopt;
  }
  return s;
}

}  // namespace pavilion::core
