// Matching and iterative integration (thesis §4.4.2): innovations, the
// validation gate (eq. 4.16), the strongest-observation policy for lines,
// uniqueness first for point features, re-prediction after each update, and
// the extension constraint against the wrong piece of a collinear wall.
#include "core/localization/matching.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/localization/ekf_update.h"
#include "tests/support/localization_world.h"

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;

Observation LineObservation(double alpha, double r, const Eigen::Matrix2d& R) {
  Observation o;
  o.type = ObservationType::kLine;
  o.z = {alpha, r};
  o.covariance = R;
  return o;
}

Observation BeaconObservation(double x, double y, double variance) {
  Observation o;
  o.type = ObservationType::kBeacon;
  o.z = {x, y};
  o.covariance = variance * Eigen::Matrix2d::Identity();
  return o;
}

ObservationBatch Batch(std::vector<Observation> observations) {
  ObservationBatch b;
  b.sensor_id = "laser";
  b.view = testing::CentredView();
  b.observations = std::move(observations);
  return b;
}

// Line innovations wrap the angle across +-pi, and a line through the sensor
// observed with the opposite normal is compared in its equivalent parameters
// (alpha + pi, -r), with the sign of the alpha-r covariance flipped.
TEST(InnovationTest, WrapsAnglesAndFlipsLinesThroughTheSensor) {
  PredictedMeasurement p;
  p.type = ObservationType::kLine;
  p.z = {kPi - 0.01, 2.0};
  p.covariance = testing::LineCovariance(0.01, 0.01);
  Eigen::Matrix2d R;
  R << 1e-4, 2e-5, 2e-5, 1e-4;
  Innovation in = ComputeInnovation(p, LineObservation(-kPi + 0.01, 2.1, R));
  EXPECT_NEAR(in.v[0], 0.02, 1e-12);
  EXPECT_NEAR(in.v[1], 0.1, 1e-12);
  EXPECT_NEAR(in.S(0, 1), 2e-5, 1e-18);
  p.z = {0.1, 0.02};
  in = ComputeInnovation(p, LineObservation(NormalizeAngle(0.1 + kPi), 0.01, R));
  EXPECT_NEAR(in.v[0], 0.0, 1e-12);
  EXPECT_NEAR(in.v[1], -0.03, 1e-12);
  EXPECT_NEAR(in.S(0, 1), -2e-5, 1e-18);
  const double nis = in.v.dot(in.S.inverse() * in.v);
  EXPECT_NEAR(in.nis, nis, 1e-9 * nis);
}

// Strongest observation policy (§4.4.2): of two observations gated with the
// same wall, the one with the smaller det(R) is paired, although the other
// has the smaller Mahalanobis distance (which a nearest-neighbour filter
// would take).
TEST(MatchingTest, LinesPairTheStrongestObservation) {
  const RobotMap map = [] {
    RobotMap m;
    m.lines.push_back(testing::MapLineThrough("wall", {3, -5}, {3, 5}, {0, 0}));
    return m;
  }();
  const MeasurementPredictor predictor(map);
  IterativeMatcher matcher;
  PoseWithCovariance state{{0, 0, 0}, 1e-6 * Eigen::Matrix3d::Identity()};
  const ObservationBatch batch =
      Batch({LineObservation(0.0, 3.0, testing::LineCovariance(0.02, 0.05)),      // NIS 0
             LineObservation(0.0, 3.02, testing::LineCovariance(0.002, 0.01))});  // NIS ~4
  const MatchingResult result = matcher.MatchAndUpdate(predictor, batch, &state);
  EXPECT_EQ(result.predictions, 1);
  EXPECT_EQ(result.observations, 2);
  ASSERT_EQ(result.matches.size(), 1u);
  EXPECT_EQ(result.matches[0].observation_index, 1);
  EXPECT_GT(result.matches[0].innovation.nis, 3.0);
}

// Uniqueness first (§4.4.2): beacon prediction P1 has only O1 in its gate,
// P2 has O1 and O2. Nearest neighbour would pair P2-O1 (the smallest NIS) and
// leave P1 and O2 unpaired; the uniqueness rule pairs P1-O1 first, then P2-O2.
TEST(MatchingTest, PointFeaturesPairUniqueCandidatesFirst) {
  RobotMap map;
  map.beacons.push_back({"P1", {{2.0, 0.0}, Eigen::Matrix2d::Zero()}});
  map.beacons.push_back({"P2", {{2.0, 1.0}, Eigen::Matrix2d::Zero()}});
  const MeasurementPredictor predictor(map);
  IterativeMatcher matcher;
  PoseWithCovariance state{{0, 0, 0}, 1e-6 * Eigen::Matrix3d::Identity()};
  // Gate radius sqrt(5.99 * 0.06) = 0.6 m.
  const ObservationBatch batch =
      Batch({BeaconObservation(2.0, 0.55, 0.06), BeaconObservation(2.0, 1.5, 0.06)});
  const MatchingResult result = matcher.MatchAndUpdate(predictor, batch, &state);
  ASSERT_EQ(result.matches.size(), 2u);
  EXPECT_EQ(FeatureId(map, result.matches[0].feature), "P1");
  EXPECT_EQ(result.matches[0].observation_index, 0);
  EXPECT_EQ(FeatureId(map, result.matches[1].feature), "P2");
  EXPECT_EQ(result.matches[1].observation_index, 1);
}

// Iterated integration: the second pairing's innovation is computed against
// the prediction re-made at the state after the first update, and lines are
// integrated before beacons whatever their order in the batch.
TEST(MatchingTest, RepredictsAfterEachUpdateAndIntegratesLinesFirst) {
  RobotMap map = testing::RectangularRoom(-3, -2, 4, 5);
  map.beacons.push_back({"b", {{1.0, 1.0}, Eigen::Matrix2d::Zero()}});
  const MeasurementPredictor predictor(map);
  const PoseWithCovariance prior{{0.05, -0.03, 0.02},
                                 Eigen::Vector3d(0.01, 0.01, 0.001).asDiagonal()};
  const Eigen::Matrix2d R_strong = testing::LineCovariance(0.002, 0.005);
  const Eigen::Matrix2d R_weak = testing::LineCovariance(0.01, 0.02);
  const Pose2 truth{0, 0, 0};
  std::vector<Observation> obs = {BeaconObservation(1.0, 1.0, 1e-4),
                                  testing::ObserveLine(map.lines[1].line, truth, R_weak),
                                  testing::ObserveLine(map.lines[2].line, truth, R_strong)};
  PoseWithCovariance state = prior;
  IterativeMatcher matcher;
  const MatchingResult result = matcher.MatchAndUpdate(predictor, Batch(obs), &state);
  ASSERT_EQ(result.matches.size(), 3u);
  EXPECT_EQ(result.predictions, 5);
  EXPECT_EQ(result.matches[0].observation_index, 2);  // strongest line
  EXPECT_EQ(result.matches[1].observation_index, 1);
  EXPECT_EQ(result.matches[2].type, ObservationType::kBeacon);
  // Replay by hand: first update, then the second line re-predicted.
  PoseWithCovariance manual = prior;
  const PredictedMeasurement p0 = predictor.Predict(
      {MapFeatureType::kLine, 2}, ObservationType::kLine, manual, testing::CentredView());
  const Innovation in0 = ComputeInnovation(p0, obs[2]);
  ASSERT_TRUE(UpdatePoseEstimate(in0.v, p0.J_z_pose, p0.feature_covariance + R_strong, 2, &manual));
  const PredictedMeasurement p1 = predictor.Predict(
      {MapFeatureType::kLine, 1}, ObservationType::kLine, manual, testing::CentredView());
  const Innovation in1 = ComputeInnovation(p1, obs[1]);
  EXPECT_LT((result.matches[1].innovation.v - in1.v).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_NEAR(result.matches[1].innovation.nis, in1.nis, 1e-12);
}

// Eq. 4.16: an observation outside every validation gate is not paired.
TEST(MatchingTest, RejectsObservationsOutsideTheGate) {
  const RobotMap map = testing::RectangularRoom(-3, -3, 3, 3);
  const MeasurementPredictor predictor(map);
  IterativeMatcher matcher;
  PoseWithCovariance state{{0, 0, 0}, 1e-4 * Eigen::Matrix3d::Identity()};
  const MatchingResult result = matcher.MatchAndUpdate(
      predictor, Batch({LineObservation(0.0, 2.5, testing::LineCovariance(0.01, 0.01))}), &state);
  EXPECT_EQ(result.predictions, 4);
  EXPECT_TRUE(result.matches.empty());
  EXPECT_EQ(state.pose, Pose2{});
}

// The extension constraint keeps an observed segment on the right piece of a
// wall interrupted by a door from being paired with the left piece, which has
// the same supporting line and hence the same NIS; without it, the first
// candidate (the left piece) is taken.
TEST(MatchingTest, ExtensionConstraintPicksTheRightPieceOfACollinearWall) {
  RobotMap map;
  const MapLine wall = testing::MapLineThrough("wall", {-10, 3}, {10, 3}, {0, 0});
  const Eigen::Matrix2d corner = 1e-4 * Eigen::Matrix2d::Identity();
  map.segments.push_back({"left", wall.line, {{-6.0, 3.0}, corner}, {{-1.0, 3.0}, corner}});
  map.segments.push_back({"right", wall.line, {{0.0, 3.0}, corner}, {{5.0, 3.0}, corner}});
  const MeasurementPredictor predictor(map);
  Observation o = LineObservation(kPi / 2, 3.0, testing::LineCovariance(0.002, 0.005));
  o.segments.push_back({{{1.0, 3.0}, corner}, {{2.5, 3.0}, corner}});
  for (bool use_extension : {true, false}) {
    IterativeMatcher matcher({0.95, use_extension});
    PoseWithCovariance state{{0, 0, 0}, 1e-4 * Eigen::Matrix3d::Identity()};
    const MatchingResult result = matcher.MatchAndUpdate(predictor, Batch({o}), &state);
    ASSERT_EQ(result.matches.size(), 1u);
    EXPECT_EQ(FeatureId(map, result.matches[0].feature), use_extension ? "right" : "left");
  }
}

// Options are validated naming the field.
TEST(MatchingTest, ValidatesOptions) {
  try {
    IterativeMatcher matcher({0.0, true});
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("significance"), std::string::npos);
  }
}

}  // namespace
}  // namespace pavilion::core
