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

DiffDriveJacobians DiffDriveStepJacobians(const Pose2& pose, const WheelTravel& travel,
                                          double wheelbase_m) {
  const double b = wheelbase_m;
  const double ds = 0.5 * (travel.right_m + travel.left_m);
  const double mid = pose.theta_rad + 0.5 * (travel.right_m - travel.left_m) / b;
  const double c = std::cos(mid);
  const double s = std::sin(mid);
  DiffDriveJacobians j;
  // Eq. 2.11: only the heading enters the step's displacement.
  j.J_next_pose << 1.0, 0.0, -ds * s,  //
      0.0, 1.0, ds * c,                //
      0.0, 0.0, 1.0;
  // Eq. 2.12: ∂Δs/∂s_{r,l} = 1/2 and ∂(θ + Δθ/2)/∂s_{r,l} = ±1/(2b), so
  // ∂f_x/∂s_r = c/2 − Δs·s/(2b), ∂f_x/∂s_l = c/2 + Δs·s/(2b), and likewise for y.
  const double lever = ds / (2.0 * b);
  j.J_next_travel.col(kRightWheel) << 0.5 * c - lever * s, 0.5 * s + lever * c, 1.0 / b;
  j.J_next_travel.col(kLeftWheel) << 0.5 * c + lever * s, 0.5 * s - lever * c, -1.0 / b;
  return j;
}

Eigen::Matrix2d WheelTravelCovariance(const WheelTravel& travel, const WheelNoise& noise) {
  Eigen::Matrix2d u = Eigen::Matrix2d::Zero();
  u(kRightWheel, kRightWheel) = noise.k_right_m * std::abs(travel.right_m);
  u(kLeftWheel, kLeftWheel) = noise.k_left_m * std::abs(travel.left_m);
  // Turn slip: d ~ N(0, k_turn |s_r - s_l|) as +d/2 on the right wheel, -d/2 on
  // the left.
  const double turn = 0.25 * noise.k_turn_m * std::abs(travel.right_m - travel.left_m);
  u(kRightWheel, kRightWheel) += turn;
  u(kLeftWheel, kLeftWheel) += turn;
  u(kRightWheel, kLeftWheel) -= turn;
  u(kLeftWheel, kRightWheel) -= turn;
  return u;
}

PoseWithCovariance DiffDriveStepWithCovariance(const PoseWithCovariance& state,
                                               const WheelTravel& travel, double wheelbase_m,
                                               const WheelNoise& noise) {
  const DiffDriveJacobians j = DiffDriveStepJacobians(state.pose, travel, wheelbase_m);
  PoseWithCovariance next;
  next.pose = DiffDriveStep(state.pose, travel, wheelbase_m);
  next.covariance = j.J_next_pose * state.covariance * j.J_next_pose.transpose() +
                    j.J_next_travel * WheelTravelCovariance(travel, noise) *
                        j.J_next_travel.transpose();  // eq. 2.13
  // Keep P exactly symmetric against rounding over long runs.
  next.covariance = 0.5 * (next.covariance + next.covariance.transpose()).eval();
  return next;
}

}  // namespace pavilion::core
