#include "core/localization/scan_deskew.h"

#include <cmath>

namespace pavilion::core {

std::optional<LaserScan> DeskewScan(const LaserScan& scan, const OdometryBuffer& odometry) {
  if (scan.readings.empty()) return scan;
  const double t0 = scan.stamp_s + scan.readings.front().time_offset_s;
  bool moving_clock = false;
  for (const LaserReading& r : scan.readings) {
    moving_clock = moving_clock || r.time_offset_s != scan.readings.front().time_offset_s;
  }
  LaserScan out = scan;
  out.stamp_s = t0;
  for (LaserReading& r : out.readings) r.time_offset_s = 0.0;
  if (!moving_clock) return out;

  const std::optional<Pose2> world_from_robot0 = odometry.OdometryPoseAt(t0);
  if (!world_from_robot0) return std::nullopt;
  const Pose2 sensor0_from_world = (*world_from_robot0 * scan.robot_from_sensor).Inverse();
  for (std::size_t k = 0; k < scan.readings.size(); ++k) {
    const LaserReading& in = scan.readings[k];
    const std::optional<Pose2> world_from_robot =
        odometry.OdometryPoseAt(scan.stamp_s + in.time_offset_s);
    if (!world_from_robot) return std::nullopt;
    const Pose2 sensor0_from_sensor =
        sensor0_from_world * (*world_from_robot * scan.robot_from_sensor);  // eq. 2.4
    LaserReading& r = out.readings[k];
    if (!in.valid) {
      r.bearing_rad = NormalizeAngle(in.bearing_rad + sensor0_from_sensor.theta_rad);
      continue;
    }
    const Eigen::Vector2d p(in.range_m * std::cos(in.bearing_rad),
                            in.range_m * std::sin(in.bearing_rad));
    const Eigen::Vector2d q = sensor0_from_sensor * p;
    r.range_m = q.norm();
    r.bearing_rad = std::atan2(q.y(), q.x());
  }
  return out;
}

}  // namespace pavilion::core
