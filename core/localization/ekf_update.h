#pragma once

// The estimation step of the EKF localization cycle (thesis §4.4.1.5).

#include <Eigen/Core>

#include "core/localization/map_cross_covariance.h"
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

// The map feature of a pairing, for the update with map correlations.
struct PairedMapFeature {
  MapFeatureRef feature;
  Eigen::Matrix2d J_z_map = Eigen::Matrix2d::Zero();         // grad h_g (rows as H)
  Eigen::Matrix2d map_covariance = Eigen::Matrix2d::Zero();  // M
};

// The same estimation step when the map feature's error m is correlated with
// the pose error e (C = Cov(e, m), kept in `correlations`; see
// map_cross_covariance.h): a Schmidt-Kalman update, the map a "consider"
// state that is never changed. With v = n - H e - G m (G = grad h_g, n the
// observation and mounting noise, N = G M G^T + Cov(n) as above):
//   S = H P H^T + H C G^T + G C^T H^T + N
//   W = (P H^T + C G^T) S^-1,  x <- x + W v,  A = I - W H
//   P <- A P A^T + W N W^T - A C G^T W^T - W G C^T A^T   (Joseph form)
//   C_k <- A C_k for every other feature k in use,  C <- A C - W G M
// The map features' errors are independent of each other. With C = 0 for
// every feature this is UpdatePoseEstimate, except that it starts recording
// the pairing's correlation. Returns false, changing nothing, when S is not
// positive definite.
bool UpdatePoseEstimate(const Eigen::Vector2d& innovation, const Eigen::Matrix<double, 2, 3>& H,
                        const Eigen::Matrix2d& N, int dimension, const PairedMapFeature& map,
                        PoseWithCovariance* state, PoseMapCrossCovariance* correlations);

}  // namespace pavilion::core
