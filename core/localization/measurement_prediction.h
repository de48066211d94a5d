#pragma once

// Measurement prediction of the EKF localization cycle (thesis §4.4.1.3): map
// features transformed into a sensor frame with the first-order covariance of
// eq. 4.9, their Jacobians with respect to the robot pose, the visibility
// constraints of Table 5.3 and the extension constraint of §5.3.2.3.

#include <Eigen/Core>
#include <span>
#include <string>
#include <vector>

#include "core/localization/observation.h"
#include "core/map/robot_map.h"
#include "core/odometry/diff_drive.h"

namespace pavilion::core {

class PoseMapCrossCovariance;

// The map collection a feature comes from.
enum class MapFeatureType { kLine, kSegment, kMultiSegmentLine, kPoint, kBeacon };

// A feature of a RobotMap: its collection and index in it.
struct MapFeatureRef {
  MapFeatureType type = MapFeatureType::kLine;
  int index = 0;

  friend bool operator==(const MapFeatureRef&, const MapFeatureRef&) = default;
};

// A foil-wrapped column (a map beacon of radius r > 0, docs/map_format.md)
// flags every reading on its lit arc, and the beacon's range is their mean
// (eq. 3.17): short of the centre at distance d by
//   delta(d) = r (pi/4 + 0.165 r / d),
// pi/4 being 1 less the mean depth 1 - cos(psi) over an arc whose readings
// are spread evenly in bearing, far from it; the second term is a fit of the
// exact mean for nearer columns (within 0.5 mm for d >= 2.4 r). The extraction
// models a point reflector (range sigma / sqrt(n), eq. 3.18), but a mean over
// an arc sampled every 0.5 deg moves by up to 2 cm as readings enter and leave
// its edges (8 m, r = 0.25 m): the prediction adds that along the line of
// sight, as a fraction of r. Ignoring the radius, a 0.25 m column predicted at
// its centre was 0.20 m off every reading: gated out while the robot was sure,
// it was paired once a collision's noise widened the gate, and pulled the
// estimate 0.2 m (expo_day seed 3, issue 21).
inline constexpr double kLitArcFarFraction = 0.7853981633974483;  // pi / 4
inline constexpr double kLitArcNearFactor = 0.165;
inline constexpr double kLitArcSamplingFraction = 0.08;  // sigma / r (chosen: 2 cm at 0.25 m)

struct LitArcMeasurement {
  Eigen::Vector2d z;                    // the beacon measurement (sensor frame)
  Eigen::Matrix2d J_z_center;           // dz / d(centre)
  Eigen::Matrix2d sampling_covariance;  // the arc's sampling, along the line of sight
};
// The beacon measurement of a column of `radius_m` whose centre lies at
// `center_m` (sensor frame). A marker (radius 0) is measured at its position.
LitArcMeasurement LitArc(double radius_m, const Eigen::Vector2d& center_m);

// The id of the referenced feature (e.g. "wall_north"); throws std::out_of_range
// for an index outside its collection.
const std::string& FeatureId(const RobotMap& map, MapFeatureRef ref);

// Whether an observation of `observation` can be paired with a map feature of
// `feature`: lines with lines, segments and MS-lines (their supporting line is
// the estimation information, §5.2); beacons with beacons; points and vertical
// edges with points.
bool CanPair(ObservationType observation, MapFeatureType feature);

// The prediction z^_i = h(x^(k+1|k), m_i) of one map feature in one sensor
// frame (eq. 4.8), in the observation's parameters (see Observation::z). Points
// and beacons are predicted as Cartesian (x, y) in the sensor frame (eq. B.28):
// that is the map's own point model (§B.2), the Jacobians are rational with no
// singularity at the sensor, innovations need no angle wrapping, and the
// extractors' polar estimates convert to it exactly to first order
// (Beacon::Cartesian) at the ranges and bearing errors of a laser (bearing
// sigma ~0.25 deg: 3.5 cm at 8 m, curvature error ~1e-5 m).
struct PredictedMeasurement {
  MapFeatureRef feature;
  ObservationType type = ObservationType::kLine;
  Eigen::Vector2d z = Eigen::Vector2d::Zero();
  // grad h_x of eq. 4.10: derivative of z with respect to the robot pose
  // (x_m, y_m, theta_rad) in the map frame. For a vertical edge only row 0.
  Eigen::Matrix<double, 2, 3> J_z_pose = Eigen::Matrix<double, 2, 3>::Zero();
  // grad h_g M grad h_g^T + grad h_s P_S grad h_s^T: the covariance terms of
  // eq. 4.9 that do not involve the robot pose (map feature, sensor mounting).
  Eigen::Matrix2d feature_covariance = Eigen::Matrix2d::Zero();
  // grad h_g: derivative of z with respect to the feature's map parameters
  // (lines, segments, MS-lines: (alpha, r) of the supporting line; points and
  // beacons: (x, y)). For a vertical edge only row 0.
  Eigen::Matrix2d J_z_map = Eigen::Matrix2d::Zero();
  // M: the covariance of those parameters as the prediction used it (the
  // §4.3 option applied).
  Eigen::Matrix2d map_covariance = Eigen::Matrix2d::Zero();
  // C = Cov(pose error, map parameter error) at the prediction's state; zero
  // unless the caller keeps map correlations (PoseMapCrossCovariance).
  Eigen::Matrix<double, 3, 2> pose_map_cross = Eigen::Matrix<double, 3, 2>::Zero();
  // S_M of eq. 4.9: J_z_pose P J_z_pose^T + feature_covariance, plus the
  // cross terms J_z_pose C J_z_map^T + (...)^T when C is kept.
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();

  int dimension() const { return MeasurementDimension(type); }
};

struct PredictionOptions {
  // alpha of the Mahalanobis pre-tests (§5.3.2.2): a constraint such as r > 0
  // or d <= R_S is taken as satisfied when its two sides are statistically
  // equal, (lhs - rhs)^2 / sigma^2 <= chi^2_{alpha,1}, before the hard test is
  // applied. Same alpha as the extension constraint (eq. 5.58); in (0, 1).
  double significance = 0.95;
  // The thesis (§4.3) neglects the angular uncertainty of the map lines: the
  // Hessian model's r uncertainty is not frame-transform invariant (eq. B.13
  // grows with the distance from the world origin's foot point), which gives
  // wrong local uncertainties in the prediction. false: sigma_alpha of map lines
  // (and its correlation) is ignored, as in the thesis; true: eq. B.16 in full.
  bool use_map_line_angle_variance = false;
  // A vertical edge is predicted only when the sight line from the camera to
  // it crosses no segment of the map (of a map segment or MS-line, a wall at
  // the beam height standing for the full-height wall): the map's own
  // occlusion test, beyond the thesis' field-of-view and range conditions
  // (§5.3.2.2), which predicted edges behind walls and let them take another
  // feature's observation (§4.5.1.2: false pairings of vertical edges).
  bool occlude_vertical_edges = true;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// Predicts map features into sensor frames. Holds a reference to the map,
// which must outlive it.
class MeasurementPredictor {
 public:
  MeasurementPredictor(const RobotMap& map, const PredictionOptions& options = {});

  // Eqs. 4.8-4.10 for one feature observed as `type` (CanPair must hold),
  // without any visibility test: lines by eqs. B.22-B.23 with the Jacobians
  // B.12-B.15 (grad h_g = B.12-B.13; grad h_x, grad h_s through the compounding
  // of robot pose and mounting pose); points by eq. B.28 with eqs. B.29-B.32;
  // vertical edges as the bearing of the point (§B.3). With `correlations`,
  // the pose-map cross-covariance of the feature enters S_M (see
  // PredictedMeasurement::covariance).
  PredictedMeasurement Predict(MapFeatureRef feature, ObservationType type,
                               const PoseWithCovariance& world_from_robot, const SensorView& view,
                               const PoseMapCrossCovariance* correlations = nullptr) const;

  // The visibility constraint of Table 5.3 for a prediction from Predict:
  // lines r > 0 and r <= R_S (eq. 5.47); segments also phi >= Phi_S (eqs.
  // 5.48-5.50); MS-lines the disjunction over their segments; points and
  // beacons d <= R_S (eqs. 5.51-5.52). Each inequality is first tested for
  // equality by its Mahalanobis distance (chi^2, 1 dof) and counts as satisfied
  // when equality holds. Additionally (not in Table 5.3, whose sensor covers
  // 360 deg): the feature must overlap the sensor's field of view, and a
  // segment's nearest point must be within R_S.
  bool IsVisible(const PredictedMeasurement& prediction, const PoseWithCovariance& world_from_robot,
                 const SensorView& view) const;

  // Appends the visible predictions of every map feature an observation of
  // `type` can be paired with.
  void PredictVisible(ObservationType type, const PoseWithCovariance& world_from_robot,
                      const SensorView& view, std::vector<PredictedMeasurement>* out,
                      const PoseMapCrossCovariance* correlations = nullptr) const;

  // The extension constraint (§5.3.2.3, Table 5.4): every observed segment must
  // be fully overlapped by the map segment (for an MS-line: by one of its
  // segments), d_max <= l_max (eqs. 5.54-5.55), tested first for equality by
  // the Mahalanobis distance of eqs. 5.58-5.60 at `significance`. d_max - l_max
  // is linearized jointly in the robot pose, the mounting pose, the map and the
  // observed endpoints, so the shared endpoint's correlation (sigma_dl of eq.
  // 5.60) is exact to first order. Lines, points and observations without
  // segments satisfy it trivially.
  bool SatisfiesExtensionConstraint(MapFeatureRef feature,
                                    std::span<const ObservedSegment> observed_segments,
                                    const PoseWithCovariance& world_from_robot,
                                    const SensorView& view) const;

  const RobotMap& map() const { return map_; }
  const PredictionOptions& options() const { return options_; }

 private:
  const RobotMap& map_;
  PredictionOptions options_;
  double equality_gate_;  // chi^2_{alpha,1}
};

}  // namespace pavilion::core
