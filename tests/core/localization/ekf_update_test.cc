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
// The update with map correlations (Schmidt-Kalman): with no correlation yet
// it gives the plain update's state and starts recording C = -W G M; with a
// correlation it equals the optimal-gain form P - W S W^T, where S carries the
// cross terms, and carries the other features' C by (I - W H).
TEST(EkfUpdateTest, CorrelatedUpdateCarriesTheCrossCovariance) {
  RobotMap map;
  map.lines.push_back(testing::MapLineThrough("wall", {3.0, -2.0}, {3.2, 2.0}, {0.0, 0.0}));
  map.lines.push_back(testing::MapLineThrough("side", {-2.0, 2.5}, {2.0, 2.4}, {0.0, 0.0}));
  const Eigen::Matrix2d M = testing::LineCovariance(0.004, 0.006);
  for (MapLine& l : map.lines) l.line.covariance = M;
  const MeasurementPredictor predictor(map, PredictionOptions{0.95, true});
  PoseWithCovariance plain{{0.1, -0.2, 0.15}, Eigen::Vector3d(0.01, 0.02, 0.003).asDiagonal()};
  plain.covariance(0, 2) = plain.covariance(2, 0) = 0.001;
  PoseWithCovariance correlated = plain;
  PoseMapCrossCovariance cross(map);
  const Eigen::Matrix2d R = testing::LineCovariance(0.01, 0.02);
  const Eigen::Vector2d v(0.003, -0.01);

  const MapFeatureRef wall{MapFeatureType::kLine, 0};
  const MapFeatureRef side{MapFeatureType::kLine, 1};
  PredictedMeasurement p = predictor.Predict(wall, ObservationType::kLine, plain, SensorView{});
  const Eigen::Matrix2d N = p.feature_covariance + R;
  ASSERT_TRUE(UpdatePoseEstimate(v, p.J_z_pose, N, 2, &plain));
  ASSERT_TRUE(UpdatePoseEstimate(v, p.J_z_pose, N, 2, {wall, p.J_z_map, p.map_covariance},
                                 &correlated, &cross));
  EXPECT_LT((plain.covariance - correlated.covariance).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_NEAR(plain.pose.x_m, correlated.pose.x_m, 1e-15);
  ASSERT_EQ(cross.features().size(), 1u);
  const PoseMapCross C_wall = cross.Get(wall);
  EXPECT_GT(C_wall.norm(), 1e-6);

  // A second observation of the same wall: S has the cross terms, and the
  // posterior is P - W S W^T with W = (P H^T + C G^T) S^-1.
  const PoseWithCovariance prior = correlated;
  p = predictor.Predict(wall, ObservationType::kLine, correlated, SensorView{}, &cross);
  const Eigen::Matrix<double, 3, 2> PHt =
      prior.covariance * p.J_z_pose.transpose() + C_wall * p.J_z_map.transpose();
  const Eigen::Matrix2d S = p.covariance + R;
  const Eigen::Matrix2d S_expected = p.J_z_pose * prior.covariance * p.J_z_pose.transpose() +
                                     p.J_z_pose * C_wall * p.J_z_map.transpose() +
                                     p.J_z_map * C_wall.transpose() * p.J_z_pose.transpose() +
                                     p.J_z_map * M * p.J_z_map.transpose() + R;
  EXPECT_LT((S - S_expected).cwiseAbs().maxCoeff(), 1e-15);
  const Eigen::Matrix<double, 3, 2> gain = PHt * S.inverse();
  const Eigen::Matrix3d expected = prior.covariance - gain * S * gain.transpose();
  ASSERT_TRUE(UpdatePoseEstimate(v, p.J_z_pose, p.feature_covariance + R, 2,
                                 {wall, p.J_z_map, p.map_covariance}, &correlated, &cross));
  EXPECT_LT((correlated.covariance - expected).cwiseAbs().maxCoeff(), 1e-12);
  const Eigen::Vector3d dx = gain * v;
  EXPECT_NEAR(correlated.pose.x_m, prior.pose.x_m + dx.x(), 1e-14);
  EXPECT_NEAR(correlated.pose.theta_rad, prior.pose.theta_rad + dx.z(), 1e-14);
  const Eigen::Matrix3d A = Eigen::Matrix3d::Identity() - gain * p.J_z_pose;
  EXPECT_LT((cross.Get(wall) - (A * C_wall - gain * p.J_z_map * M)).cwiseAbs().maxCoeff(), 1e-15);

  // The other wall's correlation is carried by (I - W H) once it exists.
  const PoseMapCross C_side = PoseMapCross::Constant(1e-4);
  cross.Set(side, C_side);
  const PoseWithCovariance before_side = correlated;
  const PoseMapCross C_wall_before = cross.Get(wall);
  p = predictor.Predict(wall, ObservationType::kLine, correlated, SensorView{}, &cross);
  const Eigen::Matrix<double, 3, 2> gain2 =
      (before_side.covariance * p.J_z_pose.transpose() + C_wall_before * p.J_z_map.transpose()) *
      (p.covariance + R).inverse();
  ASSERT_TRUE(UpdatePoseEstimate(v, p.J_z_pose, p.feature_covariance + R, 2,
                                 {wall, p.J_z_map, p.map_covariance}, &correlated, &cross));
  const Eigen::Matrix3d A2 = Eigen::Matrix3d::Identity() - gain2 * p.J_z_pose;
  EXPECT_LT((cross.Get(side) - A2 * C_side).cwiseAbs().maxCoeff(), 1e-15);
  cross.Clear();
  EXPECT_TRUE(cross.features().empty());
  EXPECT_TRUE(cross.Get(side).isZero(0.0));
}

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
