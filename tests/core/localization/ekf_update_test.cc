// The EKF estimation step (eqs. 4.11-4.15) in Joseph form.
#include "core/localization/ekf_update.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/localization/measurement_prediction.h"
#include "core/random/random_stream.h"
#include "tests/support/localization_world.h"

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;

// A single perfect observation of a wall (zero innovation, tiny R) leaves the
// pose unchanged, shrinks the variance along the wall's normal and of the
// heading, and leaves the variance along the wall untouched (the line carries
// no information along itself, §5.2): for a sensor at the robot origin
// grad h_x = [[0, 0, -1], [-cos a, -sin a, 0]] (eqs. B.14-B.15) has no
// component along the wall.
TEST(EkfUpdateTest, PerfectLineObservationReducesUncertaintyOnlyAlongItsNormal) {
  for (double wall_angle : {0.0, 0.4, 1.3, -2.2}) {
    const Eigen::Vector2d n(std::cos(wall_angle), std::sin(wall_angle));
    const Eigen::Vector2d along(-n.y(), n.x());
    RobotMap map;
    map.lines.push_back(
        testing::MapLineThrough("wall", 3.0 * n - along, 3.0 * n + along, {0.0, 0.0}));
    PoseWithCovariance state{{0.0, 0.0, 0.2}, Eigen::Vector3d(0.04, 0.09, 0.01).asDiagonal()};
    state.covariance(0, 1) = state.covariance(1, 0) = 0.01;
    const MeasurementPredictor predictor(map);
    const PredictedMeasurement p =
        predictor.Predict({MapFeatureType::kLine, 0}, ObservationType::kLine, state, SensorView{});
    const Eigen::Matrix2d R = testing::LineCovariance(1e-4, 1e-4);
    const PoseWithCovariance prior = state;
    ASSERT_TRUE(UpdatePoseEstimate(Eigen::Vector2d::Zero(), p.J_z_pose, R, 2, &state));
    EXPECT_NEAR(state.pose.x_m, prior.pose.x_m, 1e-15);
    EXPECT_NEAR(state.pose.y_m, prior.pose.y_m, 1e-15);
    EXPECT_NEAR(state.pose.theta_rad, prior.pose.theta_rad, 1e-15);
    const Eigen::Matrix2d before = prior.covariance.topLeftCorner<2, 2>();
    const Eigen::Matrix2d after = state.covariance.topLeftCorner<2, 2>();
    // Along the normal: down to about sigma_r^2 (the prior is ~1e2 times larger).
    EXPECT_LT(n.dot(after * n), 1.5e-8) << wall_angle;
    EXPECT_LT(state.covariance(2, 2), 1.5e-8);
    // Along the wall, only what is correlated with the normal direction is
    // explained: the conditional variance along | normal.
    const double cross = along.dot(before * n);
    const double conditional = along.dot(before * along) - cross * cross / n.dot(before * n);
    EXPECT_NEAR(along.dot(after * along), conditional, 1e-6) << wall_angle;
    if (std::abs(cross) < 1e-12) {
      EXPECT_NEAR(along.dot(after * along), along.dot(before * along), 1e-12);
    }
  }
}

// With the prior's axes aligned to the wall the along-wall variance stays
// exactly the same.
TEST(EkfUpdateTest, AlongWallVarianceUnchangedForAlignedPrior) {
  RobotMap map;
  map.lines.push_back(testing::MapLineThrough("wall", {-5, 2}, {5, 2}, {0, 0}));
  PoseWithCovariance state{{0.0, 0.0, 0.0}, Eigen::Vector3d(0.25, 0.04, 0.003).asDiagonal()};
  const PredictedMeasurement p = MeasurementPredictor(map).Predict(
      {MapFeatureType::kLine, 0}, ObservationType::kLine, state, SensorView{});
  ASSERT_TRUE(UpdatePoseEstimate(Eigen::Vector2d::Zero(), p.J_z_pose,
                                 testing::LineCovariance(1e-3, 5e-3), 2, &state));
  EXPECT_DOUBLE_EQ(state.covariance(0, 0), 0.25);
  EXPECT_LT(state.covariance(1, 1), 0.04 * 0.001);
  EXPECT_LT(state.covariance(2, 2), 0.003 * 0.001);
}

// The Joseph form equals the thesis' P - W S W^T (eq. 4.15) for the optimal
// gain, the mean follows eq. 4.14, and P stays symmetric positive definite,
// for random 1- and 2-dimensional measurements.
TEST(EkfUpdateTest, JosephFormEqualsThesisFormAndKeepsPositiveDefinite) {
  RandomStream rng(71, 1);
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::Matrix3d A;
    for (int i = 0; i < 9; ++i) A(i) = rng.Uniform(-0.3, 0.3);
    PoseWithCovariance state{{rng.Uniform(-3, 3), rng.Uniform(-3, 3), rng.Uniform(-3, 3)},
                             A * A.transpose() + 1e-4 * Eigen::Matrix3d::Identity()};
    Eigen::Matrix<double, 2, 3> H;
    for (int i = 0; i < 6; ++i) H(i) = rng.Uniform(-2, 2);
    const Eigen::Matrix2d N =
        testing::LineCovariance(rng.Uniform(1e-3, 0.1), rng.Uniform(1e-3, 0.1));
    const Eigen::Vector2d v(rng.Uniform(-0.1, 0.1), rng.Uniform(-0.1, 0.1));
    const int dim = trial % 2 == 0 ? 2 : 1;
    const PoseWithCovariance prior = state;
    ASSERT_TRUE(UpdatePoseEstimate(v, H, N, dim, &state));
    const Eigen::MatrixXd Hd = H.topRows(dim);
    const Eigen::MatrixXd S = Hd * prior.covariance * Hd.transpose() + N.topLeftCorner(dim, dim);
    const Eigen::MatrixXd W = prior.covariance * Hd.transpose() * S.inverse();
    const Eigen::Matrix3d thesis = prior.covariance - W * S * W.transpose();
    EXPECT_LT((state.covariance - thesis).cwiseAbs().maxCoeff(), 1e-12) << trial;
    const Eigen::Vector3d dx = W * v.head(dim);
    EXPECT_NEAR(state.pose.x_m, prior.pose.x_m + dx.x(), 1e-12);
    EXPECT_NEAR(state.pose.y_m, prior.pose.y_m + dx.y(), 1e-12);
    EXPECT_NEAR(NormalizeAngle(state.pose.theta_rad - prior.pose.theta_rad - dx.z()), 0.0, 1e-12);
    EXPECT_EQ(state.covariance, state.covariance.transpose());
    EXPECT_GT(
        Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(state.covariance).eigenvalues().minCoeff(),
        0.0);
    EXPECT_LE(std::abs(state.pose.theta_rad), kPi);  // wrapped into (-pi, pi]
  }
}

// A singular innovation covariance is refused and leaves the state as it was;
// a bad dimension throws.
TEST(EkfUpdateTest, RefusesSingularInnovationCovariance) {
  PoseWithCovariance state{{1.0, 2.0, 0.3}, Eigen::Matrix3d::Zero()};
  const PoseWithCovariance prior = state;
  Eigen::Matrix<double, 2, 3> H = Eigen::Matrix<double, 2, 3>::Ones();
  EXPECT_FALSE(UpdatePoseEstimate({0.1, 0.1}, H, Eigen::Matrix2d::Zero(), 2, &state));
  EXPECT_EQ(state.pose, prior.pose);
  EXPECT_THROW(UpdatePoseEstimate({0.1, 0.1}, H, Eigen::Matrix2d::Identity(), 3, &state),
               std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::core
