#pragma once

#include <optional>
#include <span>

#include "core/features/line_fit.h"
#include "core/features/uncertain_geometry.h"
#include "core/types/sensor_data.h"

namespace pavilion::core {

// sigma_theta_e of the endpoint bearings (eq. 5.2): `override_rad` when > 0,
// else the scan's angular resolution.
double EndpointBearingSigma(const LaserScan& scan, double override_rad);

// What every extractor requires of a segment.
struct SegmentFilter {
  int min_points = 2;         // supporting readings
  double min_length_m = 0.3;  // of the segment (eq. 5.15) and of its longest run of
                              // consecutive readings (people's legs, §6.5)
};

// The segment of `line` fitted to the readings `members` (ascending indices
// into `points`; `reading_index` maps them to scan indices), with endpoints on
// the rays of its first and last reading (eqs. 5.3-5.9) — or nullopt when it
// fails the filter or an end ray is parallel to the line (eq. 5.3 undefined).
std::optional<Segment> BuildSegment(const Line& line, std::span<const int> members,
                                    std::span<const PolarPoint> points,
                                    std::span<const int> reading_index, double bearing_sigma_rad,
                                    const SegmentFilter& filter);

}  // namespace pavilion::core
