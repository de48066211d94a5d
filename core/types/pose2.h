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

// A pose as a map of points, its cosine and sine computed once: for
// transforming many points by one pose (a scan, an obstacle memory).
// Apply(p) gives the bits of pose * p (the same arithmetic; Pose2's operator
// is written with it).
class PointTransform {
 public:
  explicit PointTransform(const Pose2& pose);
  Eigen::Vector2d Apply(const Eigen::Vector2d& point_in_child) const {
    return {x_m_ + c_ * point_in_child.x() - s_ * point_in_child.y(),
            y_m_ + s_ * point_in_child.x() + c_ * point_in_child.y()};
  }

 private:
  double x_m_, y_m_, c_, s_;
};

}  // namespace pavilion::core
