// The location estimate without a prior (thesis §5.4.2, eqs. 5.63-5.68) and
// the "location available" test.
#include "core/localization/global/location_estimate.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/localization/matching.h"
#include "tests/support/localization_world.h"

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
const Eigen::Matrix2d kLineR = testing::LineCovariance(0.3 * kDeg, 0.01);
const Pose2 kTruth{0.5, -0.3, 0.4};

SensorView MountedView() {
  SensorView view = testing::CentredView();
  view.robot_from_sensor = {0.2, 0.05, 0.1};
  return view;
}

// The map frame is chosen away from the walls so that the map's r carry the
// angle uncertainty of eq. B.13 too.
RobotMap WallsMap(const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& walls) {
  RobotMap map;
  int k = 0;
  for (const auto& [a, b] : walls) {
    map.lines.push_back(testing::MapLineThrough("wall" + std::to_string(k++), a, b, {0.5, -0.3},
                                                0.1 * kDeg, 0.005));
  }
  return map;
}

// Noiseless observations: z of the map's lines (or points) predicted at the truth.
LocalMap Observe(const MeasurementPredictor& predictor, const RobotMap& map, const SensorView& view,
                 std::vector<Pairing>* support) {
  ObservationBatch batch;
  batch.view = view;
  const PoseWithCovariance at{kTruth, Eigen::Matrix3d::Zero()};
  auto add = [&](MapFeatureRef ref, ObservationType type, const Eigen::Matrix2d& R) {
    Observation o;
    o.type = type;
    o.z = predictor.Predict(ref, type, at, view).z;
    o.covariance = R;
    support->push_back(Pairing{static_cast<int>(batch.observations.size()), ref, false});
    batch.observations.push_back(o);
  };
  for (std::size_t i = 0; i < map.lines.size(); ++i) {
    add({MapFeatureType::kLine, static_cast<int>(i)}, ObservationType::kLine, kLineR);
  }
  for (std::size_t i = 0; i < map.points.size(); ++i) {
    add({MapFeatureType::kPoint, static_cast<int>(i)}, ObservationType::kPoint,
        Eigen::Vector2d(1e-4, 1e-4).asDiagonal());
  }
  LocalMap local;
  AddToLocalMap(batch, &local);
  return local;
}

// Two perpendicular walls and a third (diagonal) one: the truth to 1e-6 and
// P = (H^T S^-1 H)^-1 with H = grad h_x at the truth and S = R + the map's
// and mounting's share of eq. 4.9 (eqs. 5.63, 5.66).
TEST(LocationEstimateTest, RecoversTheTruthAndTheInformationCovariance) {
  const RobotMap map = WallsMap({{{4, -5}, {4, 5}}, {{-5, 3}, {5, 3}}, {{-3, 0}, {0, -3}}});
  const MeasurementPredictor predictor(map);
  const SensorView view = MountedView();
  std::vector<Pairing> support;
  const LocalMap local = Observe(predictor, map, view, &support);
  ASSERT_EQ(support.size(), 3u);
  const LocationEstimate e = EstimateLocation(predictor, local, support);
  ASSERT_TRUE(e.available);
  EXPECT_NEAR(e.location.pose.x_m, kTruth.x_m, 1e-6);
  EXPECT_NEAR(e.location.pose.y_m, kTruth.y_m, 1e-6);
  EXPECT_NEAR(NormalizeAngle(e.location.pose.theta_rad - kTruth.theta_rad), 0.0, 1e-6);
  EXPECT_NEAR(e.joint_mahalanobis, 0.0, 1e-9);
  Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
  for (const Pairing& p : support) {
    const PredictedMeasurement z = predictor.Predict(p.feature, ObservationType::kLine,
                                                     {kTruth, Eigen::Matrix3d::Zero()}, view);
    const Eigen::Matrix2d S = kLineR + z.feature_covariance;
    info += z.J_z_pose.transpose() * S.inverse() * z.J_z_pose;
  }
  const Eigen::Matrix3d expected = info.inverse();
  EXPECT_LT((e.location.covariance - expected).cwiseAbs().maxCoeff(),
            1e-6 * expected.cwiseAbs().maxCoeff());
  // Two perpendicular walls alone fix the location too (4 equations, 3 unknowns).
  const std::vector<Pairing> two(support.begin(), support.begin() + 2);
  const LocationEstimate e2 = EstimateLocation(predictor, local, two);
  ASSERT_TRUE(e2.available);
  EXPECT_NEAR(e2.location.pose.x_m, kTruth.x_m, 1e-6);
  EXPECT_NEAR(e2.location.pose.y_m, kTruth.y_m, 1e-6);
}

// Noisy observations: the estimate's error is consistent with its covariance
// (one draw inside the 99.9 % chi^2(3) bound, 16.27), and the joint Mahalanobis
// distance is the sum of the pairings' NIS at the estimate.
TEST(LocationEstimateTest, NoisyObservationsStayWithinTheirCovariance) {
  const RobotMap map = WallsMap({{{4, -5}, {4, 5}}, {{-5, 3}, {5, 3}}, {{-3, 0}, {0, -3}}});
  const MeasurementPredictor predictor(map);
  const SensorView view = MountedView();
  std::vector<Pairing> support;
  LocalMap local = Observe(predictor, map, view, &support);
  RandomStream rng(7, RandomStream::StreamId("location_estimate"));
  for (LocalFeature& f : local.features) {
    f.observation.z += testing::SampleGaussian<2>(f.observation.covariance, rng);
    f.geometry = ObservationConstraintFeature(f.observation, f.view);
  }
  const LocationEstimate e = EstimateLocation(predictor, local, support);
  ASSERT_TRUE(e.available);
  EXPECT_LT(testing::Nees(e.location, kTruth), 16.27);
  double joint = 0.0;
  for (const Pairing& p : support) {
    const LocalFeature& f = local.features[static_cast<std::size_t>(p.local)];
    const PoseWithCovariance at{e.location.pose, Eigen::Matrix3d::Zero()};
    joint += ComputeInnovation(predictor.Predict(p.feature, f.observation.type, at, f.view),
                               f.observation)
                 .nis;
  }
  EXPECT_NEAR(e.joint_mahalanobis, joint, 1e-6 * (1.0 + joint));
  EXPECT_GT(e.joint_mahalanobis, 0.0);
}

// No unique location: one line, two parallel lines, a single point.
TEST(LocationEstimateTest, DegenerateSupportingSetsAreNotAvailable) {
  {
    const RobotMap map = WallsMap({{{4, -5}, {4, 5}}});
    const MeasurementPredictor predictor(map);
    std::vector<Pairing> support;
    const LocalMap local = Observe(predictor, map, MountedView(), &support);
    EXPECT_FALSE(EstimateLocation(predictor, local, support).available) << "one line";
  }
  {
    const RobotMap map = WallsMap({{{4, -5}, {4, 5}}, {{-2, -5}, {-2, 5}}});
    const MeasurementPredictor predictor(map);
    std::vector<Pairing> support;
    const LocalMap local = Observe(predictor, map, MountedView(), &support);
    EXPECT_FALSE(EstimateLocation(predictor, local, support).available) << "parallel lines";
  }
  {
    RobotMap map;
    map.points.push_back({"column", {{2.0, 1.0}, Eigen::Vector2d(1e-4, 1e-4).asDiagonal()}});
    const MeasurementPredictor predictor(map);
    std::vector<Pairing> support;
    const LocalMap local = Observe(predictor, map, MountedView(), &support);
    EXPECT_FALSE(EstimateLocation(predictor, local, support).available) << "one point";
  }
  {  // All pairings star: nothing to estimate from.
    const RobotMap map = WallsMap({{{4, -5}, {4, 5}}, {{-5, 3}, {5, 3}}});
    const MeasurementPredictor predictor(map);
    std::vector<Pairing> support;
    const LocalMap local = Observe(predictor, map, MountedView(), &support);
    for (Pairing& p : support) p.star = true;
    EXPECT_FALSE(EstimateLocation(predictor, local, support).available) << "all star";
  }
}

// Two lines 2 deg apart observed with sigma_r 2 cm: grad h^T R^-1 grad h is
// regular, but along the lines sigma ~ sqrt(2) sigma_r / sin(2 deg) = 0.028 /
// 0.035 ~ 0.8 m, beyond max_position_sigma_m (0.5 m). Not available by the
// sigma limit alone: with a generous limit it is available, at the truth.
TEST(LocationEstimateTest, NearlyParallelLinesFailTheSigmaLimits) {
  const double angle = 2.0 * kDeg;
  const Eigen::Vector2d far(-2.0 - 10.0 * std::sin(angle), 10.0 * std::cos(angle));
  const RobotMap map = WallsMap({{{4, -5}, {4, 5}}, {{-2, 0}, far}});
  const MeasurementPredictor predictor(map);
  std::vector<Pairing> support;
  LocalMap local = Observe(predictor, map, MountedView(), &support);
  for (LocalFeature& f : local.features) {
    f.observation.covariance = testing::LineCovariance(0.3 * kDeg, 0.02);
    f.geometry = ObservationConstraintFeature(f.observation, f.view);
  }
  const LocationEstimate strict = EstimateLocation(predictor, local, support);
  EXPECT_FALSE(strict.available);
  LocationEstimateOptions generous;
  generous.max_position_sigma_m = 100.0;
  generous.max_heading_sigma_rad = 1.0;
  const LocationEstimate loose = EstimateLocation(predictor, local, support, generous);
  ASSERT_TRUE(loose.available);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(
      loose.location.covariance.topLeftCorner<2, 2>());
  EXPECT_GT(std::sqrt(eig.eigenvalues().maxCoeff()),
            LocationEstimateOptions{}.max_position_sigma_m);
  EXPECT_NEAR(loose.location.pose.x_m, kTruth.x_m, 1e-6);
  EXPECT_NEAR(loose.location.pose.y_m, kTruth.y_m, 1e-6);
}

// Every option is validated, naming the field.
TEST(LocationEstimateTest, ValidatesOptions) {
  const auto expect_field = [](const LocationEstimateOptions& o, const std::string& field) {
    try {
      o.Validate();
      ADD_FAILURE() << "no throw for " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  EXPECT_NO_THROW(LocationEstimateOptions{}.Validate());
  LocationEstimateOptions o;
  o.max_iterations = 0;
  expect_field(o, "max_iterations");
  o = {};
  o.converged_m = 0.0;
  expect_field(o, "converged_m");
  o = {};
  o.max_position_sigma_m = -1.0;
  expect_field(o, "max_position_sigma_m");
  o = {};
  o.max_heading_sigma_rad = 0.0;
  expect_field(o, "max_heading_sigma_rad");
}

}  // namespace
}  // namespace pavilion::core
