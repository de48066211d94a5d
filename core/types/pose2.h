#pragma once

#include <Eigen/Core>

namespace pavilion::core {

// Wraps an angle to (-pi, pi].
double NormalizeAngle(double angle_rad);

// A planar pose (x, y, theta): the frame of a child expressed in a parent frame.
// `world_from_robot` is the robot's pose in the world.
struct Pose2 {
  double x_m = 0.0;
  double y_m = 0.0;
  double theta_rad = 0.0;

  Eigen::Vector2d translation() const { return {x_m, y_m}; }

  // Head-to-tail compounding a ⊕ b (Smith, Self & Cheeseman; thesis appendix B).
  Pose2 operator*(const Pose2& b) const;
  // Inverse compounding ⊖a, so that a.Inverse() * a is the identity.
  Pose2 Inverse() const;
  // Transforms a point expressed in this pose's child frame to its parent frame.
  Eigen::Vector2d operator*(const Eigen::Vector2d& point_in_child) const;

  friend bool operator==(const Pose2&, const Pose2&) = default;
};

}  // namespace pavilion::core
