#pragma once

#include <Eigen/Core>

#include "core/types/pose2.h"

namespace pavilion::core {

// Wheel travels of one odometry step (thesis eq. 2.5): the arc lengths the
// left and right wheel contact points covered, in metres.
struct WheelTravel {
  double left_m = 0.0;
  double right_m = 0.0;
};

// The differential-drive kinematic model f(x, u) of thesis eqs. 2.6–2.8: the
// pose after driving `travel` from `pose` with wheelbase `wheelbase_m`,
// integrating along the chord at the mean heading θ + Δθ/2.
Pose2 DiffDriveStep(const Pose2& pose, const WheelTravel& travel, double wheelbase_m);

// ---------------------------------------------------------------------------
// The §2.3 error model (Chong & Kleeman): non-systematic errors in wheel space.
//
// Ordering: as in the thesis, the input vector is u = [s_r, s_l]ᵀ (eq. 2.5) —
// the RIGHT wheel first. Every wheel-space vector and matrix below (the columns
// of J_next_travel, the rows and columns of U) uses this order; the indices
// are kRightWheel and kLeftWheel. Poses are ordered [x, y, θ].
// ---------------------------------------------------------------------------

inline constexpr int kRightWheel = 0;
inline constexpr int kLeftWheel = 1;

// Wheel-space noise of eq. 2.9: the variance of a wheel's travel grows by
// k·|s| per step, k in metres (thesis value k_L = k_R = 5e-6 m).
//
// Extension (not in the thesis): slip in turns. A differential slip d with
// Var(d) = k_turn·|s_r − s_l| moves the wheels by +d/2 and −d/2, so the
// heading's variance grows by k_turn·|Δθ|/b per step besides the k terms.
// Wheels scrub when they turn the robot (in-place turns, tight curves); eq.
// 2.9 alone, calibrated on straights and turns together, makes the odometry
// several times too confident in turns (docs/calibration.md). 0 gives eq. 2.9.
struct WheelNoise {
  double k_left_m = 0.0;   // >= 0
  double k_right_m = 0.0;  // >= 0
  double k_turn_m = 0.0;   // >= 0
};

// Jacobians of f(x, u) (eq. 2.10) at the step's input.
struct DiffDriveJacobians {
  Eigen::Matrix3d J_next_pose;                // ∇f_x = ∂f/∂x, eq. 2.11
  Eigen::Matrix<double, 3, 2> J_next_travel;  // ∇f_u = ∂f/∂u, eq. 2.12; columns [s_r, s_l]
};

DiffDriveJacobians DiffDriveStepJacobians(const Pose2& pose, const WheelTravel& travel,
                                          double wheelbase_m);

// U = Cov(u) = diag(k_R|s_r|, k_L|s_l|), eq. 2.9, in the [s_r, s_l] order, plus
// the turn-slip term k_turn·|s_r − s_l|/4·[1 −1; −1 1] (see WheelNoise).
Eigen::Matrix2d WheelTravelCovariance(const WheelTravel& travel, const WheelNoise& noise);

// A pose with its 3×3 covariance P = Cov([x, y, θ]ᵀ).
struct PoseWithCovariance {
  Pose2 pose;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

// One odometry step with first-order error propagation (eq. 2.13):
// P' = ∇f_x P ∇f_xᵀ + ∇f_u U ∇f_uᵀ, the Jacobians taken at (x, u).
PoseWithCovariance DiffDriveStepWithCovariance(const PoseWithCovariance& state,
                                               const WheelTravel& travel, double wheelbase_m,
                                               const WheelNoise& noise);

}  // namespace pavilion::core
