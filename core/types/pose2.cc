#include "core/types/pose2.h"

#include <cmath>
#include <numbers>

namespace pavilion::core {

double NormalizeAngle(double angle_rad) {
  if (angle_rad > -std::numbers::pi && angle_rad <= std::numbers::pi) return angle_rad;
  double a = std::remainder(angle_rad, 2.0 * std::numbers::pi);
  if (a <= -std::numbers::pi) a += 2.0 * std::numbers::pi;
  return a;
}

Pose2 Pose2::operator*(const Pose2& b) const {
  const double c = std::cos(theta_rad);
  const double s = std::sin(theta_rad);
  return {x_m + c * b.x_m - s * b.y_m, y_m + s * b.x_m + c * b.y_m,
          NormalizeAngle(theta_rad + b.theta_rad)};
}

Pose2 Pose2::Inverse() const {
  const double c = std::cos(theta_rad);
  const double s = std::sin(theta_rad);
  return {-c * x_m - s * y_m, s * x_m - c * y_m, NormalizeAngle(-theta_rad)};
}

Eigen::Vector2d Pose2::operator*(const Eigen::Vector2d& point_in_child) const {
  return PointTransform(*this).Apply(point_in_child);
}

PointTransform::PointTransform(const Pose2& pose)
    : x_m_(pose.x_m), y_m_(pose.y_m), c_(std::cos(pose.theta_rad)), s_(std::sin(pose.theta_rad)) {}

}  // namespace pavilion::core
