#pragma once

// The location independent geometric constraints of global localization
// (thesis §5.3.1): unary constraints on a pairing's feature dimensions (Table
// 5.1) and binary constraints on two pairings' relative geometry (Table 5.2).
// Every test is the two-step decision of Figs. 5.7-5.8: first equality on the
// Mahalanobis distance at significance alpha (chi^2, 1 dof), then, where the
// table has an inequality, the non-probabilistic condition. Features are
// uncorrelated with each other (§5.3). The location dependent constraints
// (§5.3.2: rigidity, visibility, extension) are those of the EKF
// (MeasurementPredictor::IsVisible, ComputeInnovation,
// MeasurementPredictor::SatisfiesExtensionConstraint), applied by the
// interpretation tree at a location hypothesis.

#include "core/features/uncertain_geometry.h"
#include "core/localization/measurement_prediction.h"
#include "core/localization/observation.h"
#include "core/map/robot_map.h"

namespace pavilion::core {

// A local (observed) or global (map) feature as these constraints see it, in
// one frame: lines, segments and MS-lines by the (alpha, r) of their
// supporting line (they share their binary constraints, §5.3.1.2), points and
// beacons by (x, y).
struct ConstraintFeature {
  bool is_line = true;
  Line line;              // is_line: its supporting line; normal towards the surface's face
  Point2Uncertain point;  // !is_line
  // Length of the longest segment the feature carries, and its variance (eq.
  // 5.16): a segment's own, an MS-line's longest (Table 5.1: the conjunction of
  // eq. 5.22 reduces to it). finite = false for infinite lines and points.
  bool finite = false;
  double length_m = 0.0;
  double length_variance_m2 = 0.0;
};

// Length and variance of the segment between two uncertain endpoints (eqs.
// 5.15-5.16): l = |p2 - p1|, sigma^2 = u^T (C1 + C2) u with u the unit direction.
void SegmentLength(const Point2Uncertain& first, const Point2Uncertain& second, double* length_m,
                   double* variance_m2);

// A map feature's constraint geometry (map frame).
ConstraintFeature MapConstraintFeature(const RobotMap& map, MapFeatureType type, int index);

// An observation's constraint geometry in the frame of `view.robot_from_sensor`'s
// parent (the robot): lines by eq. B.22-B.23 inverted (LineInParent) with the
// mounting covariance, points and beacons by the mounting transform, segment
// lengths from the observed endpoints (frame invariant).
ConstraintFeature ObservationConstraintFeature(const Observation& observation,
                                               const SensorView& view);

// Table 5.1: the local feature's longest segment is at most as long as the
// global one's, l_l <= l_g (eq. 5.18), after the equality test of eqs.
// 5.19-5.21. True when either has no length (infinite lines, points).
// `gate` is chi^2_{alpha,1}.
bool SatisfiesUnaryConstraint(const ConstraintFeature& local, const ConstraintFeature& global,
                              double gate);

// The Mahalanobis distances of Table 5.2 for the pairings {local_i, global_i}
// and {local_j, global_j}, each chi^2 with 1 dof.
struct BinaryDistances {
  // Line-line: D_alpha^2 (eq. 5.26) of the relative angles; D_r^2 (eq. 5.29)
  // of the separations, set only when the global lines are parallel (eq.
  // 5.27, same or opposite normals), else 0.
  double angle = 0.0;
  bool parallel = false;
  double separation = 0.0;
  // Line-point: D_d^2 of the point-to-line distances (eq. 5.37); point-point:
  // D_d^2 of the Cartesian distances (eq. 5.45).
  double distance = 0.0;
};
BinaryDistances ComputeBinaryDistances(const ConstraintFeature& local_i,
                                       const ConstraintFeature& local_j,
                                       const ConstraintFeature& global_i,
                                       const ConstraintFeature& global_j, double gate);

// Table 5.2 with the condition tree of Fig. 5.8 for lines (angle; if the
// global lines are parallel, also the separation), eq. 5.36 for line-point and
// eq. 5.44 for point-point. `gate` is chi^2_{alpha,1}. Each local feature's
// kind (line or point) must match its global partner's.
bool SatisfiesBinaryConstraint(const ConstraintFeature& local_i, const ConstraintFeature& local_j,
                               const ConstraintFeature& global_i, const ConstraintFeature& global_j,
                               double gate);

}  // namespace pavilion::core
