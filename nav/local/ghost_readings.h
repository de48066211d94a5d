#pragma once

// Ghost points injected into a laser scan as virtual readings (thesis §6.3.1:
// "ghost points are used to prevent the robot to go there by injecting them
// into the sensor data"). A controller that reacts to raw scans alone — the
// wander a navigating robot falls back on while it is not localized — then
// keeps off the glass and the low benches its lasers cannot see, placed by
// its belief (while lost: the last estimate carried by odometry, or the best
// hypothesis). A ghost point closer to the robot's centre than its radius
// cannot be where the belief puts it (the robot would stand on it) and is
// left out, so a wrong belief does not freeze the robot.

#include <Eigen/Core>
#include <vector>

#include "core/types/pose2.h"
#include "core/types/sensor_data.h"

namespace pavilion::nav {

class GhostReadings {
 public:
  // `ghosts_in_world`: the map's ghost points, barriers filled
  // (FillGhostBarriers); `robot_radius_m` >= 0.
  GhostReadings(std::vector<Eigen::Vector2d> ghosts_in_world, double robot_radius_m);

  // `scan` with each ghost point in the laser's field of view and range put
  // on its nearest beam when nearer than that beam's reading (or the beam had
  // no return). Bearings are taken as evenly spaced from the first reading to
  // the last, as a scanner's are.
  core::LaserScan Inject(const core::LaserScan& scan, const core::Pose2& world_from_robot) const;

 private:
  std::vector<Eigen::Vector2d> ghosts_in_world_;
  double robot_radius_m_;
};

}  // namespace pavilion::nav
