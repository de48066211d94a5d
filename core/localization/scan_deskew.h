#pragma once

// Registration of a scan taken while the robot moves (thesis §2.2.1.4 and
// §4.4.4): every reading re-expressed in the sensor frame at the scan's first
// reading, using the robot's motion from odometry.

#include <optional>

#include "core/localization/odometry_buffer.h"
#include "core/types/sensor_data.h"

namespace pavilion::core {

// Transforms each reading, taken at stamp_s + time_offset_s from the sensor
// frame S' of that instant, into the sensor frame S at the first reading's
// time (eq. 2.4): S P = (R T_S)^-1 (W T_R)^-1 W T_R' R' T_S' S' P, with W T_R the
// dead-reckoned poses of the buffer (only relative motion over the scan
// matters, which odometry measures best; corrections do not enter) and
// R T_S = robot_from_sensor. Range and bearing are recomputed; invalid
// readings keep their range and are only rotated. The result has stamp_s at the
// first reading and every time_offset_s zero: "the compensated scan receives the
// timestamp of [the first reading]". Returns nullopt when the buffer does not
// cover the scan's time span; a scan whose readings share one time is returned
// unchanged.
std::optional<LaserScan> DeskewScan(const LaserScan& scan, const OdometryBuffer& odometry);

}  // namespace pavilion::core
