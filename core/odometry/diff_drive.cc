#include "core/odometry/diff_drive.h"

#include <cmath>

namespace pavilion::core {

Pose2 DiffDriveStep(const Pose2& pose, const WheelTravel& travel, double wheelbase_m) {
  const double ds = 0.5 * (travel.right_m + travel.left_m);              // Δs, eq. 2.7
  const double dtheta = (travel.right_m - travel.left_m) / wheelbase_m;  // Δθ, eq. 2.7
  const double mid = pose.theta_rad + 0.5 * dtheta;
  return {pose.x_m + ds * std::cos(mid), pose.y_m + ds * std::sin(mid),
          NormalizeAngle(pose.theta_rad + dtheta)};  // eq. 2.8
}

}  // namespace pavilion::core
