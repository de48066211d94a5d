#include "nav/local/ghost_readings.h"

#include <cmath>
#include <stdexcept>
#include <utility>

namespace pavilion::nav {

GhostReadings::GhostReadings(std::vector<Eigen::Vector2d> ghosts_in_world, double robot_radius_m)
    : ghosts_in_world_(std::move(ghosts_in_world)), robot_radius_m_(robot_radius_m) {
  if (!(robot_radius_m >= 0.0 && std::isfinite(robot_radius_m))) {
    throw std::invalid_argument("GhostReadings: robot_radius_m must be finite and >= 0");
  }
}

core::LaserScan GhostReadings::Inject(const core::LaserScan& scan,
                                      const core::Pose2& world_from_robot) const {
  core::LaserScan out = scan;
  const std::size_t n = out.readings.size();
  if (n < 2) return out;
  const double first = out.readings.front().bearing_rad;
  const double step = (out.readings.back().bearing_rad - first) / static_cast<double>(n - 1);
  if (step == 0.0) return out;
  const core::Pose2 sensor_from_world = (world_from_robot * scan.robot_from_sensor).Inverse();
  const Eigen::Vector2d centre = world_from_robot.translation();
  const double reach2 = (scan.max_range_m + robot_radius_m_) * (scan.max_range_m + robot_radius_m_);
  for (const Eigen::Vector2d& g : ghosts_in_world_) {
    const double d2 = (g - centre).squaredNorm();
    if (d2 > reach2 || d2 < robot_radius_m_ * robot_radius_m_) continue;
    const Eigen::Vector2d q = sensor_from_world * g;
    const double range = q.norm();
    if (range >= scan.max_range_m) continue;
    const double index = std::round((std::atan2(q.y(), q.x()) - first) / step);
    if (index < 0.0 || index > static_cast<double>(n - 1)) continue;  // outside the field of view
    core::LaserReading& r = out.readings[static_cast<std::size_t>(index)];
    if (!r.valid || range < r.range_m) {
      r.range_m = range;
      r.valid = true;
      r.reflector = false;
    }
  }
  return out;
}

}  // namespace pavilion::nav
