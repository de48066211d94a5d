#include "core/features/segment_builder.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace pavilion::core {
namespace {

// |cos(alpha - theta_e)| below which eq. 5.3 is numerically meaningless
// (incidence within ~0.06 degrees of grazing).
constexpr double kMinRayIncidenceCos = 1e-3;

Eigen::Vector2d Cartesian(const PolarPoint& p) {
  return p.range_m * Eigen::Vector2d(std::cos(p.bearing_rad), std::sin(p.bearing_rad));
}

// Runs of readings (LongestRunLength) break where consecutive points jump by
// more than kRunJumpRatio times the run's median step and at least
// kRunJumpFloorM; a piece of a run counts only if one of its rays meets the
// line less grazingly than kMaxRunIncidenceRad. Chosen with crowd_scans_test
// (expo_crowd: leg lines in 4 % of the robot's scans before, 0.8 % after) and
// extraction_scoring_test (true positives 0.960 before, 0.957 after).
constexpr double kRunJumpRatio = 5.0;
constexpr double kRunJumpFloorM = 0.05;
constexpr double kMaxRunIncidenceRad = 85.0 * std::numbers::pi / 180.0;

// Length along the line of the longest run of consecutive readings (runs are
// separated by occluders or dropouts). Collinear leg-sized clusters fused across
// a gap, such as the two legs of a person, have only short runs (§6.5). Two
// more cases of legs in a crowd: legs of people side by side at different
// depths lined up in one run (a step far longer than the run's typical one is
// a depth discontinuity: a surface's spacing grows smoothly with range and
// incidence), and the mixed pixels a leg's edge sheds along the ray (§2.2.1),
// a radial trail no surface could show the laser (every ray of it grazes the
// line).
double LongestRunLength(const Line& line, std::span<const int> members,
                        std::span<const PolarPoint> points) {
  const Eigen::Vector2d along(std::sin(line.alpha_rad), -std::cos(line.alpha_rad));
  const double grazing_cos = std::cos(kMaxRunIncidenceRad);
  double longest = 0.0;
  std::vector<double> steps, sorted;
  std::size_t begin = 0;
  for (std::size_t k = 1; k <= members.size(); ++k) {
    if (k < members.size() && members[k] == members[k - 1] + 1) continue;
    // The run members[begin, k): split it at jumps.
    steps.clear();
    for (std::size_t j = begin + 1; j < k; ++j) {
      steps.push_back((Cartesian(points[members[j]]) - Cartesian(points[members[j - 1]])).norm());
    }
    double limit = std::numeric_limits<double>::infinity();
    if (steps.size() >= 2) {
      sorted = steps;
      std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
      limit = std::max(kRunJumpRatio * sorted[sorted.size() / 2], kRunJumpFloorM);
    }
    std::size_t piece = begin;
    double best_cos = 0.0;
    for (std::size_t j = begin; j < k; ++j) {
      best_cos =
          std::max(best_cos, std::abs(std::cos(line.alpha_rad - points[members[j]].bearing_rad)));
      if (j + 1 < k && steps[j - begin] <= limit) continue;
      if (best_cos >= grazing_cos) {
        longest = std::max(longest, std::abs(along.dot(Cartesian(points[members[j]]) -
                                                       Cartesian(points[members[piece]]))));
      }
      piece = j + 1;
      best_cos = 0.0;
    }
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
