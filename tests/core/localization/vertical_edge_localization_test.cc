// Vertical edges in the EKF (thesis §4.4, eq. 4.3, §B.3; issue 19): a camera
// image becomes a batch of bearings with the camera's view; bearings to
// mapped edges correct the heading; an edge behind a map segment is not
// predicted; a column (a point of radius > 0) is never paired with an edge;
// an observation that two predictions' gates share is not paired, nor one in
// the gate of a mapped edge beyond the perception radius.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/features/camera_model.h"
#include "core/localization/camera_observations.h"
#include "core/localization/localizer.h"
#include "core/localization/matching.h"
#include "core/localization/measurement_prediction.h"
#include "tests/support/localization_world.h"

namespace pavilion::core {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Observation EdgeObservation(double bearing_rad, double sigma_rad) {
  Observation o;
  o.type = ObservationType::kVerticalEdge;
  o.z = {bearing_rad, 0.0};
  o.covariance(0, 0) = sigma_rad * sigma_rad;
  return o;
}

ObservationBatch EdgeBatch(std::vector<Observation> observations) {
  ObservationBatch b;
  b.sensor_id = "camera";
  b.view = testing::CentredView();
  b.types = {ObservationType::kVerticalEdge};
  b.observations = std::move(observations);
  return b;
}

MapPoint Edge(const std::string& id, double x, double y, double sigma_m = 0.0) {
  return {id, {{x, y}, sigma_m * sigma_m * Eigen::Matrix2d::Identity()}, 0.0};
}

double Bearing(const Pose2& from, double x, double y) {
  return NormalizeAngle(std::atan2(y - from.y_m, x - from.x_m) - from.theta_rad);
}

// A 640 x 480 image of a bright bar between two undistorted columns on a dark
// background (area-coverage edges), through the camera's lens.
GrayImage BarImage(const CameraIntrinsics& camera, double left_px, double right_px) {
  CameraIntrinsics pinhole = camera;
  pinhole.radial = {0.0, 0.0, 0.0, 0.0};
  GrayImage image(camera.width_px, camera.height_px, 40);
  for (int v = 0; v < camera.height_px; ++v) {
    for (int u = 0; u < camera.width_px; ++u) {
      const double cover =
          std::clamp(std::min(u + 1.0, right_px) - std::max(1.0 * u, left_px), 0.0, 1.0);
      image.at(u, v) = static_cast<std::uint8_t>(std::lround(40 + 160 * cover));
    }
  }
  return DistortImage(image, camera);
}

TEST(CameraObservationsTest, AnImageBecomesBearingsWithTheCamerasView) {
  CameraSensorOptions camera;
  camera.id = "forward";
  camera.intrinsics = CameraIntrinsics::FromHorizontalFov(640, 480, 54.0 * kDeg);
  camera.intrinsics.radial = {0.06, 0.01, 0.0, 0.0};
  camera.robot_from_sensor = {0.2, 0.0, 0.0};
  const double left = ColumnOfBearing(camera.intrinsics, 10.0 * kDeg);
  const double right = ColumnOfBearing(camera.intrinsics, 6.0 * kDeg);
  const CameraImage image{"forward", 12.5, BarImage(camera.intrinsics, left, right)};
  const ObservationBatch batch = EdgeObservations(image, camera);
  EXPECT_EQ(batch.sensor_id, "forward");
  EXPECT_DOUBLE_EQ(batch.stamp_s, 12.5);
  ASSERT_EQ(batch.types.size(), 1u);
  EXPECT_EQ(batch.types[0], ObservationType::kVerticalEdge);
  ASSERT_EQ(batch.observations.size(), 2u);
  // Column ascending: bearing descending.
  EXPECT_NEAR(batch.observations[0].z[0], 10.0 * kDeg, 0.02 * kDeg);
  EXPECT_NEAR(batch.observations[1].z[0], 6.0 * kDeg, 0.02 * kDeg);
  for (const Observation& o : batch.observations) {
    EXPECT_GT(o.covariance(0, 0), 0.0);
    EXPECT_LT(std::sqrt(o.covariance(0, 0)), 0.05 * kDeg);
  }
  // The view: the camera's mount and its opening less the border margins.
  EXPECT_DOUBLE_EQ(batch.view.robot_from_sensor.x_m, 0.2);
  EXPECT_LT(batch.view.max_bearing_rad, 27.0 * kDeg);
  EXPECT_GT(batch.view.max_bearing_rad, 25.0 * kDeg);
  EXPECT_NEAR(batch.view.min_bearing_rad, -batch.view.max_bearing_rad, 1e-9);
}

TEST(CameraObservationsTest, EdgesAtTheBorderAreNotUsed) {
  CameraSensorOptions camera;
  camera.id = "forward";
  camera.intrinsics = CameraIntrinsics::FromHorizontalFov(640, 480, 54.0 * kDeg);
  // A bar whose left edge lies 8 px inside the image's left border.
  const CameraImage image{"forward", 0.0, BarImage(camera.intrinsics, 8.0, 200.0)};
  const ObservationBatch batch = EdgeObservations(image, camera);
  ASSERT_EQ(batch.observations.size(), 1u);
  EXPECT_NEAR(batch.observations[0].z[0], BearingOfColumn(camera.intrinsics, 200.0), 0.02 * kDeg);
  camera.border_margin_px = 0.0;
  EXPECT_EQ(EdgeObservations(image, camera).observations.size(), 2u);
  camera.border_margin_px = 400.0;
  EXPECT_THROW(camera.Validate(), std::invalid_argument);
}

TEST(VerticalEdgeMatchingTest, BearingsCorrectTheHeading) {
  RobotMap map;
  map.points = {Edge("e1", 4.0, 1.0), Edge("e2", 5.0, -2.0), Edge("e3", 3.0, -0.5)};
  const MeasurementPredictor predictor(map);
  IterativeMatcher matcher;
  const Pose2 truth{0.0, 0.0, 0.0};
  // The estimate is 1 degree off with a 2 degree sigma.
  PoseWithCovariance state{{0.0, 0.0, 1.0 * kDeg},
                           Eigen::Vector3d(1e-6, 1e-6, std::pow(2.0 * kDeg, 2)).asDiagonal()};
  std::vector<Observation> observations;
  for (const MapPoint& p : map.points) {
    observations.push_back(EdgeObservation(
        Bearing(truth, p.point.position_m.x(), p.point.position_m.y()), 0.01 * kDeg));
  }
  const MatchingResult result = matcher.MatchAndUpdate(predictor, EdgeBatch(observations), &state);
  EXPECT_EQ(result.matches.size(), 3u);
  EXPECT_NEAR(state.pose.theta_rad, 0.0, 0.01 * kDeg);
  EXPECT_LT(std::sqrt(state.covariance(2, 2)), 0.02 * kDeg);
}

TEST(VerticalEdgeMatchingTest, ColumnsAreNotEdges) {
  RobotMap map;
  map.points = {Edge("edge", 4.0, 0.0), {"column", {{4.0, 2.0}, Eigen::Matrix2d::Zero()}, 0.2}};
  const MeasurementPredictor predictor(map);
  std::vector<PredictedMeasurement> predicted;
  const PoseWithCovariance state{{0, 0, 0}, 1e-6 * Eigen::Matrix3d::Identity()};
  predictor.PredictVisible(ObservationType::kVerticalEdge, state, testing::CentredView(),
                           &predicted);
  ASSERT_EQ(predicted.size(), 1u);
  EXPECT_EQ(FeatureId(map, predicted[0].feature), "edge");
  predicted.clear();  // the laser's points see both
  predictor.PredictVisible(ObservationType::kPoint, state, testing::CentredView(), &predicted);
  EXPECT_EQ(predicted.size(), 2u);
}

TEST(VerticalEdgeMatchingTest, AnEdgeBehindAMapSegmentIsNotPredicted) {
  RobotMap map;
  map.points = {Edge("behind", 6.0, 0.0), Edge("before", 2.0, 1.0), Edge("on_the_wall", 4.0, 1.0)};
  // A wall across x = 4 from y = -1 to y = 1 (its upper end is an edge).
  MapSegment wall;
  wall.id = "wall";
  wall.line = testing::MapLineThrough("wall", {4.0, -1.0}, {4.0, 1.0}, {0.0, 0.0}).line;
  wall.first_endpoint = {{4.0, -1.0}, Eigen::Matrix2d::Zero()};
  wall.second_endpoint = {{4.0, 1.0}, Eigen::Matrix2d::Zero()};
  map.segments.push_back(wall);
  const PoseWithCovariance state{{0, 0, 0}, 1e-6 * Eigen::Matrix3d::Identity()};
  std::vector<PredictedMeasurement> predicted;
  MeasurementPredictor(map).PredictVisible(ObservationType::kVerticalEdge, state,
                                           testing::CentredView(), &predicted);
  std::vector<std::string> ids;
  for (const auto& p : predicted) ids.push_back(FeatureId(map, p.feature));
  EXPECT_EQ(ids, (std::vector<std::string>{"before", "on_the_wall"}));
  // Without the occlusion test (the thesis' conditions) all three are predicted.
  PredictionOptions thesis;
  thesis.occlude_vertical_edges = false;
  predicted.clear();
  MeasurementPredictor(map, thesis)
      .PredictVisible(ObservationType::kVerticalEdge, state, testing::CentredView(), &predicted);
  EXPECT_EQ(predicted.size(), 3u);
}

TEST(VerticalEdgeMatchingTest, AnObservationTwoGatesShareIsNotPaired) {
  // Two edges 0.3 deg apart seen from 4 m (a door frame's two corners), a
  // heading sigma of 0.5 deg: one observation between them lies in both gates.
  RobotMap map;
  map.points = {Edge("a", 4.0, 0.0), Edge("b", 4.0, 4.0 * std::tan(0.3 * kDeg))};
  const MeasurementPredictor predictor(map);
  const ObservationBatch batch = EdgeBatch({EdgeObservation(0.15 * kDeg, 0.01 * kDeg)});
  const PoseWithCovariance start{{0, 0, 0},
                                 Eigen::Vector3d(1e-6, 1e-6, std::pow(0.5 * kDeg, 2)).asDiagonal()};
  PoseWithCovariance state = start;
  EXPECT_TRUE(IterativeMatcher().MatchAndUpdate(predictor, batch, &state).matches.empty());
  // The thesis' rule (§4.4.2) takes it by the smallest Mahalanobis distance.
  MatchingOptions thesis;
  thesis.unambiguous_vertical_edges = false;
  state = start;
  EXPECT_EQ(IterativeMatcher(thesis).MatchAndUpdate(predictor, batch, &state).matches.size(), 1u);
}

TEST(VerticalEdgeMatchingTest, AnObservationNearAMappedEdgeBeyondTheRangeIsNotPaired) {
  // Office seed 1 at 46 s: a door frame's edge 5 m ahead is predicted, the
  // frames of the next door 6-7 m ahead are beyond the 5 m range and are not;
  // the camera sees one of those 1.5 deg from the near edge, inside its gate
  // (heading sigma 1 deg), and the near edge itself is not extracted.
  RobotMap map;
  map.points = {Edge("near", 4.8, 1.0), Edge("far", 6.5, 1.2)};
  const MeasurementPredictor predictor(map);
  ObservationBatch batch = EdgeBatch({EdgeObservation(Bearing({}, 6.5, 1.2), 0.01 * kDeg)});
  batch.view.perception_radius_m = 5.0;
  ASSERT_NEAR(Bearing({}, 4.8, 1.0) - Bearing({}, 6.5, 1.2), 1.3 * kDeg, 0.2 * kDeg);
  const PoseWithCovariance start{{0, 0, 0},
                                 Eigen::Vector3d(1e-6, 1e-6, std::pow(1.0 * kDeg, 2)).asDiagonal()};
  PoseWithCovariance state = start;
  EXPECT_TRUE(IterativeMatcher().MatchAndUpdate(predictor, batch, &state).matches.empty());
  EXPECT_DOUBLE_EQ(state.pose.theta_rad, 0.0);
  // Without the far edge in the map the same observation is paired (falsely).
  RobotMap near_only;
  near_only.points = {map.points[0]};
  state = start;
  const MeasurementPredictor near_predictor(near_only);
  EXPECT_EQ(IterativeMatcher().MatchAndUpdate(near_predictor, batch, &state).matches.size(), 1u);
  EXPECT_GT(std::abs(state.pose.theta_rad), 0.5 * kDeg);
  // An edge behind a map segment is no distractor: a wall across x = 6 hides the far one.
  MapSegment wall;
  wall.id = "wall";
  wall.line = testing::MapLineThrough("wall", {6.0, 0.0}, {6.0, 3.0}, {0.0, 0.0}).line;
  wall.first_endpoint = {{6.0, 0.0}, Eigen::Matrix2d::Zero()};
  wall.second_endpoint = {{6.0, 3.0}, Eigen::Matrix2d::Zero()};
  map.segments.push_back(wall);
  state = start;
  EXPECT_EQ(
      IterativeMatcher().MatchAndUpdate(MeasurementPredictor(map), batch, &state).matches.size(),
      1u);
}

TEST(VerticalEdgeMatchingTest, LocalizerTakesImagesOfItsCamerasOnly) {
  LocalizerOptions options;
  options.odometry = {0.09, 0.09, 0.5, 5e-6, 5e-6};
  CameraSensorOptions camera;
  camera.id = "forward";
  camera.intrinsics = CameraIntrinsics::FromHorizontalFov(64, 48, 54.0 * kDeg);
  camera.edges.min_pixels = 10;
  options.cameras.push_back(camera);
  Localizer localizer(RobotMap{}, options);
  localizer.Initialize({0, 0, 0}, 1e-4 * Eigen::Matrix3d::Identity(), 0.0);
  EXPECT_THROW(localizer.AddImage({"unknown", 0.0, GrayImage(64, 48, 0)}), std::invalid_argument);
  EXPECT_THROW(localizer.AddImage({"forward", 0.0, GrayImage(32, 48, 0)}), std::invalid_argument);
  options.cameras.push_back(camera);  // the same id twice
  EXPECT_THROW(Localizer(RobotMap{}, options), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::core
