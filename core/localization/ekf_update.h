#pragma once

// The estimation step of the EKF localization cycle (thesis §4.4.1.5).

#include <Eigen/Core>

#include "core/odometry/diff_drive.h"

namespace pavilion::core {

// Integrates one pairing into the pose estimate (eqs. 4.11-4.15):
//   S = H P H^T + N                      (eq. 4.12, N = S - H P H^T)
//   W = P H^T S^-1                       (eq. 4.13)
//   x <- x + W v                         (eq. 4.14, heading wrapped to (-pi, pi])
//   P <- (I - W H) P (I - W H)^T + W N W^T
// with v the innovation (eq. 4.11, angles already wrapped), H = grad h_x the
// measurement Jacobian with respect to the pose, and N the pose-independent
// part of the innovation covariance: the map feature and mounting-pose terms
// of eq. 4.9 plus the observation covariance R. Only the leading `dimension`
// (1 or 2) rows of v, H and N are used.
//
// The covariance update is the Joseph form. For the optimal gain it equals the
// thesis' P - W S W^T (eq. 4.15) exactly, but it is a sum of two positive
// semi-definite terms, so rounding cannot make P indefinite after many
// sequential updates with very precise observations (e.g. sigma_r of a few mm
// against a pose sigma of metres after a long dead-reckoning stretch, where
// P - W S W^T cancels almost all digits). P is also re-symmetrized. The cost on
// a 3x3 state is negligible.
//
// Returns false, leaving the state unchanged, when S is not positive definite.
bool UpdatePoseEstimate(const Eigen::Vector2d& innovation, const Eigen::Matrix<double, 2, 3>& H,
                        const Eigen::Matrix2d& N, int dimension, PoseWithCovariance* state);

}  // namespace pavilion::core
