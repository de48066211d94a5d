#pragma once

// One laser scan as an observation batch (thesis §4.4.1.2): the lines (with
// their segments) and beacons extracted from it, and the sensor view they were
// seen with (Table 5.3). Shared by pose tracking (Localizer) and global
// localization (GlobalLocalizer), which see the same observations.

#include <optional>

#include "core/localization/localizer.h"
#include "core/localization/observation.h"
#include "core/localization/odometry_buffer.h"
#include "core/types/sensor_data.h"

namespace pavilion::core {

// The batch of a registered scan (every time offset zero, stamp_s at its first
// reading). `raw` is the scan as taken: its bearings give the field of view.
// Lines: the pieces of one line seen through gaps (Segment::line_id) form one
// observation with several segments (an MS-line, eq. 5.17).
ObservationBatch ScanObservations(const LaserScan& registered, const LaserScan& raw,
                                  const LaserSensorOptions& laser);

// The scan registered into the frame of its first reading when `laser.deskew`
// (§2.2.1.4, §4.4.4) with the odometry of `buffer`, or stamped at its first
// reading otherwise; nullopt when the buffer does not cover it.
std::optional<LaserScan> RegisterScan(const LaserScan& raw, const LaserSensorOptions& laser,
                                      const OdometryBuffer& buffer);

}  // namespace pavilion::core
