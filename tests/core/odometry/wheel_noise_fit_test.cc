// The maximum-likelihood wheel noise (C5'): recovers k from residuals drawn
// with a known covariance, and the mean χ² at the optimum is the dof per run.
#include "core/odometry/wheel_noise_fit.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <cmath>

#include "core/random/random_stream.h"

namespace pavilion::core {
namespace {

// 300 runs (900 dof, k̂/k has a standard deviation of √(2/900) = 4.7%) with
// residuals drawn from k·A_i, no turn slip: k̂ within 15% (3σ), k̂_turn small.
TEST(WheelNoiseFitTest, RecoversKFromResidualsOfKnownCovariance) {
  constexpr double kK = 3e-5;
  RandomStream rng(7, 1);
  std::vector<NoiseFitRun> runs;
  for (int i = 0; i < 300; ++i) {
    NoiseFitRun run;
    const double s = 1.0 + 0.01 * i;
    run.unit_k = Eigen::Vector3d(s, 2 * s, 0.5 / s).asDiagonal();
    run.unit_turn = Eigen::Vector3d(0.01, 0.01, 3.0).asDiagonal();
    const Eigen::Matrix3d l = (kK * run.unit_k).llt().matrixL();
    run.residual = l * Eigen::Vector3d(rng.Normal(0, 1), rng.Normal(0, 1), rng.Normal(0, 1));
    runs.push_back(run);
  }
  const WheelNoiseFit fit = FitWheelNoise(runs);
  EXPECT_NEAR(fit.k_m / kK, 1.0, 0.15);
  EXPECT_LT(fit.k_turn_m, 0.2 * kK);
  ASSERT_EQ(fit.mahalanobis_sq.size(), runs.size());
  double chi2 = 0;
  for (double m2 : fit.mahalanobis_sq) chi2 += m2;
  EXPECT_NEAR(chi2 / runs.size(), 3.0, 0.1);
}

}  // namespace
}  // namespace pavilion::core
