#include "sim/crowd/robot_avoidance.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pavilion::sim::crowd {
namespace {

// Robots ahead within this distance make a walker steer around them, and the
// walker keeps this margin beyond both bodies, m (chosen; people pass a
// machine a little wider than each other).
constexpr double kLookaheadM = 4.0;
constexpr double kPassMarginM = 0.35;
// The furthest ahead (s) a walker extrapolates a robot's motion, and the
// slowest walking speed (m/s) it assumes for that.
constexpr double kPredictionS = 2.0;
constexpr double kSlowestMps = 0.3;
// A person this close to a robot's hull touches it, m (the pushers' reach).
constexpr double kTouchM = 0.05;

}  // namespace

Eigen::Vector2d SteerAroundRobots(const Eigen::Vector2d& position_m, double radius_m,
                                  double speed_mps, const Eigen::Vector2d& direction,
                                  double goal_distance_m, std::span<const CrowdRobot> robots,
                                  const std::vector<double>& robot_reach_m, int ignore) {
  double turn = 0.0;
  for (std::size_t r = 0; r < robots.size(); ++r) {
    if (static_cast<int>(r) == ignore) continue;
    const Eigen::Vector2d now = robots[r].pose.translation() - position_m;
    const double lead = std::min(kPredictionS, now.norm() / std::max(speed_mps, kSlowestMps));
    const Eigen::Vector2d p = now + robots[r].velocity_mps * lead;
    const double along = p.dot(direction);
    const double dist = p.norm();
    const double clearance = radius_m + robot_reach_m[r] + kPassMarginM;
    if (along <= 0.0 || along > kLookaheadM || dist <= 0.0) continue;
    if (goal_distance_m < along - robot_reach_m[r]) continue;  // the goal comes first
    // > 0: the robot is on the left.
    const double lateral = direction.x() * p.y() - direction.y() * p.x();
    if (std::abs(lateral) >= clearance) continue;
    const double needed = dist > clearance
                              ? std::asin(clearance / dist) - std::asin(std::abs(lateral) / dist)
                              : std::numbers::pi / 2;
    const double side = lateral > 0.0 ? -1.0 : (lateral < 0.0 ? 1.0 : -1.0);
    if (needed > std::abs(turn)) turn = side * needed;
  }
  if (turn == 0.0) return direction;
  const double c = std::cos(turn), s = std::sin(turn);
  return {c * direction.x() - s * direction.y(), s * direction.x() + c * direction.y()};
}

Eigen::Vector2d NotIntoRobots(const Eigen::Vector2d& position_m, double radius_m,
                              const Eigen::Vector2d& desired,
                              std::span<const RobotObstacle> robots) {
  Eigen::Vector2d v = desired;
  for (const RobotObstacle& r : robots) {
    if (r.hull_m.size() < 3) continue;
    Eigen::Vector2d n, c;  // n points from the robot to the person
    if (SignedDistanceToConvex(r.hull_m, position_m, &n, &c) - radius_m > kTouchM) continue;
    const double into = v.dot(n);
    if (into < 0.0) v -= into * n;
  }
  return v;
}

}  // namespace pavilion::sim::crowd
