#pragma once

// Observations the EKF pairs with map features (thesis §4.2, eqs. 4.2-4.3):
// extracted features in the frame of the sensor that saw them, each with its
// covariance R, and the sensor geometry a batch of them was taken with.

#include <Eigen/Core>
#include <numbers>
#include <string>
#include <vector>

#include "core/features/uncertain_geometry.h"
#include "core/types/pose2.h"

namespace pavilion::core {

// What a sensor reports of a feature. The type decides which map features an
// observation can be paired with and which measurement model of appendix B
// predicts it.
enum class ObservationType {
  kLine,          // (alpha, r), eq. 4.2; pairs with map lines, segments and MS-lines
  kBeacon,        // (x, y) of a retro-reflector (§3.3); pairs with map beacons
  kPoint,         // (x, y) of a point feature (corner, column centre); pairs with map points
  kVerticalEdge,  // bearing phi, eq. 4.3 (§B.3); pairs with map points (vertical edges)
};

// Dimension n of the measurement: 2, except 1 for a vertical edge's bearing.
inline int MeasurementDimension(ObservationType type) {
  return type == ObservationType::kVerticalEdge ? 1 : 2;
}

// The endpoints of an observed segment in the sensor frame (eqs. 5.3-5.9).
struct ObservedSegment {
  Point2Uncertain first;
  Point2Uncertain last;
};

// One extracted feature in the sensor frame.
struct Observation {
  ObservationType type = ObservationType::kLine;
  // kLine: (alpha_rad, r_m) with r >= 0; kBeacon, kPoint: (x_m, y_m);
  // kVerticalEdge: (phi_rad, unused).
  Eigen::Vector2d z = Eigen::Vector2d::Zero();
  // R, the observation covariance; for a vertical edge only (0, 0) is read.
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  // For a line: the observed segments it supports (one for a segment, several
  // for a multi-segment line, eq. 5.17), used by the extension constraint
  // (§5.3.2.3). Empty: an infinite line, no extension test.
  std::vector<ObservedSegment> segments;
};

// The geometry and perception limits of one sensor (Table 5.3).
struct SensorView {
  Pose2 robot_from_sensor;  // mounting pose x_S^R of eq. 4.9
  // P_S, covariance of the mounting pose (eq. 4.9), of (x_m, y_m, theta_rad);
  // zero for a deterministic transform such as the SICK's (§2.2.2, §4.5.2).
  Eigen::Matrix3d robot_from_sensor_covariance = Eigen::Matrix3d::Zero();
  // R_S, the perception radius (eqs. 5.47, 5.51), m; > 0.
  double perception_radius_m = 8.0;
  // Phi_S, the least angle under which a segment is seen to be perceptible
  // (eq. 5.48), rad; >= 0. Default: the 13 readings (12 intervals of 0.5 deg)
  // of the smallest segment the LMS 200 extraction delivers (n_f = 11, see
  // LineExtractionOptions), the "minimal-point condition" of §5.3.2.2.
  double min_view_angle_rad = 12.0 * 0.5 * std::numbers::pi / 180.0;
  // Field of view: bearings the sensor covers, counter-clockwise from min to
  // max; the full circle by default (the thesis' 360 deg assumption, §5.3.2.2).
  double min_bearing_rad = -std::numbers::pi;
  double max_bearing_rad = std::numbers::pi;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// The observations one sensor delivered at one time stamp.
struct ObservationBatch {
  std::string sensor_id;
  double stamp_s = 0.0;  // time of acquisition T_A (§4.4.3)
  SensorView view;
  std::vector<Observation> observations;
  // The observation types this sensor can deliver: predictions (and their
  // counts) are made for these even when none was extracted this time. Empty:
  // the types present in `observations`.
  std::vector<ObservationType> types;
};

}  // namespace pavilion::core
