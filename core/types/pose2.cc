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
  const double c = std::cos(theta_rad);
  const double s = std::sin(theta_rad);
  return {x_m + c * point_in_child.x() - s * point_in_child.y(),
          y_m + s * point_in_child.x() + c * point_in_child.y()};
}

}  // namespace pavilion::core
