// The differential-drive odometry model and its §2.3 error model: Jacobians
// (eqs. 2.11, 2.12), input covariance (eq. 2.9) and propagation (eq. 2.13).
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <numbers>

#include "core/odometry/diff_drive.h"
#include "core/random/random_stream.h"

namespace pavilion::core {
namespace {

constexpr double kWheelbaseM = 0.4;
constexpr double kDiffStep = 1e-6;  // central-difference step (m, rad)
// Central differences of a smooth function have error O(h²) ≈ 1e-12 plus
// rounding ε/h ≈ 1e-10 for values of order 1.
constexpr double kJacobianTol = 1e-8;

Eigen::Vector3d Vec(const Pose2& p) { return {p.x_m, p.y_m, p.theta_rad}; }

// (a − b) with the heading difference wrapped.
Eigen::Vector3d Diff(const Pose2& a, const Pose2& b) {
  return {a.x_m - b.x_m, a.y_m - b.y_m, NormalizeAngle(a.theta_rad - b.theta_rad)};
}

// ∂f/∂x and ∂f/∂u by central differences, u in the [s_r, s_l] order.
DiffDriveJacobians NumericJacobians(const Pose2& pose, const WheelTravel& travel) {
  DiffDriveJacobians j;
  for (int i = 0; i < 3; ++i) {
    Eigen::Vector3d d = Eigen::Vector3d::Zero();
    d[i] = kDiffStep;
    const Pose2 plus{pose.x_m + d[0], pose.y_m + d[1], pose.theta_rad + d[2]};
    const Pose2 minus{pose.x_m - d[0], pose.y_m - d[1], pose.theta_rad - d[2]};
    j.J_next_pose.col(i) =
        Diff(DiffDriveStep(plus, travel, kWheelbaseM), DiffDriveStep(minus, travel, kWheelbaseM)) /
        (2 * kDiffStep);
  }
  for (int w : {kRightWheel, kLeftWheel}) {
    WheelTravel plus = travel, minus = travel;
    (w == kRightWheel ? plus.right_m : plus.left_m) += kDiffStep;
    (w == kRightWheel ? minus.right_m : minus.left_m) -= kDiffStep;
    j.J_next_travel.col(w) =
        Diff(DiffDriveStep(pose, plus, kWheelbaseM), DiffDriveStep(pose, minus, kWheelbaseM)) /
        (2 * kDiffStep);
  }
  return j;
}

// The analytic Jacobians of eqs. 2.11 and 2.12 match central differences at
// random poses and travels (forward, backward, turning, spinning).
TEST(DiffDriveJacobiansTest, MatchNumericalDerivativesAtRandomPoints) {
  RandomStream rng(11, 1);
  for (int i = 0; i < 200; ++i) {
    const Pose2 pose{rng.Uniform(-10, 10), rng.Uniform(-10, 10), rng.Uniform(-3.1, 3.1)};
    const WheelTravel travel{rng.Uniform(-0.3, 0.3), rng.Uniform(-0.3, 0.3)};
    const DiffDriveJacobians analytic = DiffDriveStepJacobians(pose, travel, kWheelbaseM);
    const DiffDriveJacobians numeric = NumericJacobians(pose, travel);
    EXPECT_LT((analytic.J_next_pose - numeric.J_next_pose).cwiseAbs().maxCoeff(), kJacobianTol)
        << "at point " << i;
    EXPECT_LT((analytic.J_next_travel - numeric.J_next_travel).cwiseAbs().maxCoeff(), kJacobianTol)
        << "at point " << i;
  }
}

// U = diag(k_R|s_r|, k_L|s_l|) in the thesis' [s_r, s_l] order, for either sign of travel.
TEST(WheelTravelCovarianceTest, IsDiagonalRightWheelFirstAndGrowsWithAbsoluteTravel) {
  const Eigen::Matrix2d u = WheelTravelCovariance({-0.2, 0.5}, {3e-6, 7e-6});
  EXPECT_DOUBLE_EQ(u(kRightWheel, kRightWheel), 7e-6 * 0.5);
  EXPECT_DOUBLE_EQ(u(kLeftWheel, kLeftWheel), 3e-6 * 0.2);
  EXPECT_EQ(u(0, 1), 0.0);
  EXPECT_EQ(u(1, 0), 0.0);
}

// A straight step at heading 0 from a certain pose: closed form of eq. 2.13,
// P = k·s·[[1/2, 0, 0], [0, s²/(2b²), s/b²], [0, s/b², 2/b²]].
TEST(DiffDriveCovarianceTest, StraightStepMatchesClosedForm) {
  const double s = 0.3, k = 1e-5, b = kWheelbaseM;
  const PoseWithCovariance next = DiffDriveStepWithCovariance({}, {s, s}, kWheelbaseM, {k, k});
  EXPECT_NEAR(next.pose.x_m, s, 1e-15);
  Eigen::Matrix3d expected;
  expected << 0.5, 0, 0,                    //
      0, s * s / (2 * b * b), s / (b * b),  //
      0, s / (b * b), 2 / (b * b);
  EXPECT_LT((next.covariance - k * s * expected).cwiseAbs().maxCoeff(), 1e-18);
}

// Straight driving carries heading uncertainty into the lateral position:
// from P = diag(0, 0, σθ²), a noise-free straight step of s gives
// σy² = s²σθ² and Cov(y, θ) = s·σθ², and leaves x certain (eq. 2.11).
TEST(DiffDriveCovarianceTest, StraightStepTurnsHeadingVarianceIntoLateralVariance) {
  PoseWithCovariance state;
  state.covariance(2, 2) = 1e-4;
  const PoseWithCovariance next = DiffDriveStepWithCovariance(state, {2.0, 2.0}, kWheelbaseM, {});
  EXPECT_NEAR(next.covariance(0, 0), 0.0, 1e-18);
  EXPECT_NEAR(next.covariance(1, 1), 4.0 * 1e-4, 1e-15);
  EXPECT_NEAR(next.covariance(1, 2), 2.0 * 1e-4, 1e-15);
  EXPECT_NEAR(next.covariance(2, 2), 1e-4, 1e-15);
}

// A spin in place (s_r = −s_l = s, Δs = 0): the heading variance is 2ks/b², the
// position variance k·s/2 lies along the mean heading m = θ + Δθ/2 only, and
// position and heading are uncorrelated.
TEST(DiffDriveCovarianceTest, PureRotationMatchesClosedForm) {
  const double s = 0.2, k = 2e-5, b = kWheelbaseM;
  const Pose2 start{1.0, -2.0, 0.3};
  const PoseWithCovariance next =
      DiffDriveStepWithCovariance({start, Eigen::Matrix3d::Zero()}, {-s, s}, kWheelbaseM, {k, k});
  EXPECT_NEAR(next.pose.x_m, start.x_m, 1e-15);
  EXPECT_NEAR(next.pose.y_m, start.y_m, 1e-15);
  EXPECT_NEAR(next.pose.theta_rad, 0.3 + 2 * s / b, 1e-15);
  const double m = 0.3 + s / b;
  const Eigen::Vector2d along(std::cos(m), std::sin(m));
  const Eigen::Matrix2d position = next.covariance.topLeftCorner<2, 2>();
  EXPECT_LT((position - 0.5 * k * s * along * along.transpose()).cwiseAbs().maxCoeff(), 1e-18);
  EXPECT_NEAR(next.covariance(2, 2), 2 * k * s / (b * b), 1e-18);
  EXPECT_NEAR(next.covariance(0, 2), 0.0, 1e-18);
  EXPECT_NEAR(next.covariance(1, 2), 0.0, 1e-18);
}

// Eq. 2.13 along a curved path agrees with a Monte-Carlo of 4000 draws of
// noisy wheel travels (and of the uncertain start pose): every eigenvalue of
// P⁻¹·S (S the sample covariance) lies within 10% of 1. With n = 4000 the
// sampling error of a variance is √(2/n) ≈ 2.2%; the noise keeps σθ ≈ 0.05 rad
// so the linearization error stays well below that.
TEST(DiffDriveCovarianceTest, PropagationMatchesMonteCarloAlongACurvedPath) {
  constexpr int kSteps = 150;
  constexpr int kDraws = 4000;
  const WheelTravel travel{0.015, 0.02};  // curving left: Δθ = 0.0125 rad per step
  const WheelNoise noise{1e-4, 6e-5};
  const Pose2 start{0.5, 1.0, 0.2};
  Eigen::Matrix3d start_covariance;
  start_covariance << 1e-4, 2e-5, 0,  //
      2e-5, 4e-4, 1e-5,               //
      0, 1e-5, 2e-4;

  PoseWithCovariance predicted{start, start_covariance};
  for (int i = 0; i < kSteps; ++i) {
    predicted = DiffDriveStepWithCovariance(predicted, travel, kWheelbaseM, noise);
  }
  ASSERT_GT(predicted.pose.theta_rad, 1.5);  // a curved path

  RandomStream rng(12, 1);
  const Eigen::Matrix3d start_sqrt = start_covariance.llt().matrixL();
  std::vector<Eigen::Vector3d> ends;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (int d = 0; d < kDraws; ++d) {
    const Eigen::Vector3d z(rng.Normal(), rng.Normal(), rng.Normal());
    const Eigen::Vector3d x0 = Vec(start) + start_sqrt * z;
    Pose2 pose{x0[0], x0[1], x0[2]};
    for (int i = 0; i < kSteps; ++i) {
      const WheelTravel noisy{
          travel.left_m + rng.Normal(0, std::sqrt(noise.k_left_m * std::abs(travel.left_m))),
          travel.right_m + rng.Normal(0, std::sqrt(noise.k_right_m * std::abs(travel.right_m)))};
      pose = DiffDriveStep(pose, noisy, kWheelbaseM);
    }
    ends.push_back(Diff(pose, predicted.pose));
    mean += ends.back() / kDraws;
  }
  Eigen::Matrix3d sample = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& e : ends) sample += (e - mean) * (e - mean).transpose();
  sample /= kDraws - 1;

  // Whitened sample covariance L⁻¹ S L⁻ᵀ with P = L Lᵀ.
  const Eigen::Matrix3d l = predicted.covariance.llt().matrixL();
  const Eigen::Matrix3d l_inv = l.inverse();
  const Eigen::Vector3d ratios =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(l_inv * sample * l_inv.transpose())
          .eigenvalues();
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(ratios[i], 1.0, 0.1) << "eigenvalue " << i;
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(sample(i, i) / predicted.covariance(i, i), 1.0, 0.1) << "variance " << i;
  }
  // The mean end pose is unbiased to first order.
  for (int i = 0; i < 3; ++i) {
    EXPECT_LT(std::abs(mean[i]), 4 * std::sqrt(predicted.covariance(i, i) / kDraws) +
                                     0.05 * std::sqrt(predicted.covariance(i, i)));
  }
}

// Propagation keeps P symmetric and, without noise, only transports the
// start covariance (∇f_x P ∇f_xᵀ).
TEST(DiffDriveCovarianceTest, WithoutNoiseOnlyTransportsTheStartCovariance) {
  PoseWithCovariance state{{0, 0, 0.7}, Eigen::Vector3d(1e-4, 2e-4, 3e-4).asDiagonal()};
  const WheelTravel travel{0.1, 0.3};
  const DiffDriveJacobians j = DiffDriveStepJacobians(state.pose, travel, kWheelbaseM);
  const PoseWithCovariance next = DiffDriveStepWithCovariance(state, travel, kWheelbaseM, {});
  const Eigen::Matrix3d expected = j.J_next_pose * state.covariance * j.J_next_pose.transpose();
  EXPECT_LT((next.covariance - expected).cwiseAbs().maxCoeff(), 1e-18);
  EXPECT_EQ(next.covariance, next.covariance.transpose());
}

// The turn-slip term (an extension of eq. 2.9): a differential slip of
// variance k_turn |s_r - s_l| adds k_turn |s_r - s_l| / b^2 to the heading's
// variance and nothing on a straight step.
TEST(DiffDriveCovarianceTest, TurnSlipAddsHeadingVarianceInTurnsOnly) {
  const double b = 0.4;
  const WheelNoise turn_only{0.0, 0.0, 2e-5};
  const WheelTravel spin{-0.1, 0.1};  // left, right: an in-place turn of 0.5 rad
  const Eigen::Matrix2d u = WheelTravelCovariance(spin, turn_only);
  EXPECT_NEAR(u(kRightWheel, kRightWheel), 0.25 * 2e-5 * 0.2, 1e-18);
  EXPECT_NEAR(u(kRightWheel, kLeftWheel), -0.25 * 2e-5 * 0.2, 1e-18);
  const PoseWithCovariance next = DiffDriveStepWithCovariance({}, spin, b, turn_only);
  EXPECT_NEAR(next.covariance(2, 2), 2e-5 * 0.2 / (b * b), 1e-15);
  const Eigen::Matrix2d position = next.covariance.topLeftCorner(2, 2);
  EXPECT_NEAR(position.norm(), 0.0, 1e-18);  // in place
  const PoseWithCovariance straight =
      DiffDriveStepWithCovariance({}, WheelTravel{0.3, 0.3}, b, turn_only);
  EXPECT_EQ(straight.covariance, Eigen::Matrix3d::Zero());
}

}  // namespace
}  // namespace pavilion::core
