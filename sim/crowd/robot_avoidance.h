#pragma once

#include <Eigen/Core>
#include <span>
#include <vector>

#include "sim/crowd/crowd.h"

namespace pavilion::sim::crowd {

// Turns a walker's direction `direction` (unit) so that it passes the robots
// ahead instead of walking into them: the smallest turn that makes its line
// clear each robot's bounding circle (radius `robot_reach_m[r]`, at the
// robot's position extrapolated to when the walker gets there) by a margin;
// a robot straight ahead is passed on the right. Robots beyond the goal
// (`goal_distance_m` away), behind the walker or farther than the look-ahead,
// and robot `ignore` (one the walker means to approach), are left alone. The
// social force model alone decelerates a walker in front of an obstacle it
// meets head-on but hardly turns it; this is the walker's anticipation.
Eigen::Vector2d SteerAroundRobots(const Eigen::Vector2d& position_m, double radius_m,
                                  double speed_mps, const Eigen::Vector2d& direction,
                                  double goal_distance_m, std::span<const CrowdRobot> robots,
                                  const std::vector<double>& robot_reach_m, int ignore);

// `desired` without its component into each robot whose hull a person at
// position_m of radius_m touches (within a few centimetres): someone touching a
// machine does not keep walking into it (only a pusher means to, and does not
// ask). Before this, curious and crowding visitors whose place lay beyond the
// robot pressed into it with their whole driving force, m v0 / tau = 214 N,
// for the length of an episode (docs/crowd.md).
Eigen::Vector2d NotIntoRobots(const Eigen::Vector2d& position_m, double radius_m,
                              const Eigen::Vector2d& desired,
                              std::span<const RobotObstacle> robots);

}  // namespace pavilion::sim::crowd
