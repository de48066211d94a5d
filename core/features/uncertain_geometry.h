#pragma once

#include <Eigen/Core>

#include "core/types/pose2.h"

namespace pavilion::core {

// A point with the 2x2 covariance of its (x, y) position, in some frame.
struct Point2Uncertain {
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();  // of (x_m, y_m), m^2
};

// An infinite line in Hessian form x cos(alpha) + y sin(alpha) - r = 0 (eq. B.1)
// with the covariance of (alpha_rad, r_m). The sign of r carries visibility
// (eq. B.4): the line is seen from the side of the points p with
// n(alpha) . p < r (eq. B.21), so r > 0 means it is visible from the origin of
// its frame (eq. B.24). Lines fitted to a scan in the sensor frame have r >= 0.
// alpha_rad is kept in (-pi, pi].
struct Line {
  double alpha_rad = 0.0;
  double r_m = 0.0;
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();  // of (alpha_rad, r_m)

  // Unit normal (cos alpha, sin alpha).
  Eigen::Vector2d normal() const;
  // n . p - r (eq. B.10): negative on the visible side, zero on the line.
  double SignedDistance(const Eigen::Vector2d& point) const;
  // Visibility condition of eq. B.21: d_v = n . p < r_v.
  bool IsVisibleFrom(const Eigen::Vector2d& point) const;
  // Eq. B.24: visible from the origin of the line's frame iff r > 0.
  bool IsVisibleFromOrigin() const { return r_m > 0.0; }
};

// Jacobians of a line frame transform, for callers that keep cross-covariances.
struct LineTransformJacobians {
  Eigen::Matrix2d J_line_line = Eigen::Matrix2d::Zero();  // wrt (alpha, r)
  Eigen::Matrix<double, 2, 3> J_line_pose =
      Eigen::Matrix<double, 2, 3>::Zero();  // wrt (x, y, theta)
};

// Expresses a line given in a parent frame in the child frame whose pose in the
// parent is `parent_from_child` (eqs. B.22-B.23, which keep the visibility sign
// of B.4), propagating the line covariance and the pose covariance (3x3, of
// x_m, y_m, theta_rad; no line-pose cross-correlation) per eq. B.16 with the
// Jacobians B.12-B.15.
Line LineInChild(const Line& line_in_parent, const Pose2& parent_from_child,
                 const Eigen::Matrix3d& pose_covariance = Eigen::Matrix3d::Zero(),
                 LineTransformJacobians* jacobians = nullptr);

// The inverse of LineInChild: a line given in the child frame expressed in the
// parent frame (eqs. B.22-B.23 solved for the parent's parameters), with first-
// order propagation of both covariances.
Line LineInParent(const Line& line_in_child, const Pose2& parent_from_child,
                  const Eigen::Matrix3d& pose_covariance = Eigen::Matrix3d::Zero(),
                  LineTransformJacobians* jacobians = nullptr);

// Intersection of the ray at `bearing_rad` (from the frame origin) with the line
// (eq. 5.3), and its covariance from the line covariance and the bearing
// uncertainty `bearing_sigma_rad` (eq. 5.2) through the Jacobian of eqs.
// 5.4-5.6, i.e. eqs. 5.7-5.9. Requires cos(alpha - bearing) != 0.
Point2Uncertain EndpointOnRay(const Line& line, double bearing_rad, double bearing_sigma_rad);

// A line segment extracted from a scan: its supporting line in the sensor frame,
// its endpoints on the rays of its first and last readings (eqs. 5.3-5.9), its
// length and the variance of the length (eqs. 5.15-5.16).
struct Segment {
  Line line;
  Point2Uncertain first_endpoint;  // on the ray of the first reading (lowest index)
  Point2Uncertain last_endpoint;   // on the ray of the last reading
  double length_m = 0.0;
  double length_variance_m2 = 0.0;
  int point_count = 0;  // valid readings supporting the line
  int first_index = 0;  // index of the first supporting reading in the scan
  int last_index = 0;   // index of the last supporting reading in the scan
  // Pieces of one line seen through gaps (a multi-segment line, eq. 5.17) share
  // the line, estimated from all their readings, and this id; point_count and
  // the indices are the piece's own. -1: the segment's line is its own.
  int line_id = -1;
};

// Builds a segment on `line` between the rays `first_bearing_rad` and
// `last_bearing_rad`, both with bearing uncertainty `bearing_sigma_rad`.
Segment MakeSegment(const Line& line, double first_bearing_rad, double last_bearing_rad,
                    double bearing_sigma_rad, int point_count, int first_index, int last_index);

}  // namespace pavilion::core
