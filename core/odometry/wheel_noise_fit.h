#pragma once

// Maximum-likelihood estimate of the §2.3 wheel-space noise k (and the turn
// slip k_turn of core::WheelNoise) from the end-pose residuals of calibration
// runs (formula C5' of wheel_noise_fit.cc).

#include <Eigen/Core>
#include <vector>

namespace pavilion::core {

// The end-pose residual of one run with its covariance per unit noise: the
// run's P(k, k_turn) = k·unit_k + k_turn·unit_turn (eq. 2.13 propagated along
// the run's wheel travels from P = 0 with unit k, resp. unit k_turn).
struct NoiseFitRun {
  Eigen::Vector3d residual{0, 0, 0};  // true − odometry end pose [x, y, θ], world frame
  Eigen::Matrix3d unit_k = Eigen::Matrix3d::Zero();
  Eigen::Matrix3d unit_turn = Eigen::Matrix3d::Zero();
};

struct WheelNoiseFit {
  double k_m = 0.0;       // k̂ (= k_L = k_R)
  double k_turn_m = 0.0;  // k̂_turn
  // eᵢᵀ P(k̂, k̂_turn)⁻¹ eᵢ of each run (χ² with 3 dof if consistent).
  std::vector<double> mahalanobis_sq;
};

// The (k, k_turn) that maximize the Gaussian likelihood of the residuals.
WheelNoiseFit FitWheelNoise(const std::vector<NoiseFitRun>& runs);

}  // namespace pavilion::core
