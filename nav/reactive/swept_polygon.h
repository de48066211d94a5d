#pragma once

// Exact geometry of a convex robot polygon moving on a circular arc (thesis
// §6.3.4, after Philippsen & Siegwart 2003): the reference the clearance
// look-up table is built from and checked against. A motion at constant wheel
// speeds is a constant body twist; in the robot frame a world-fixed point then
// turns about the instantaneous centre of rotation (ICR) (0, v/ω) at -ω, or
// slides along -x when ω = 0.

#include <Eigen/Core>
#include <vector>

#include "core/geometry/polygon.h"
#include "core/types/pose2.h"

namespace pavilion::nav {

// A constant body twist: forward speed and turn rate of the robot frame.
struct BodyTwist {
  double v_mps = 0.0;
  double omega_radps = 0.0;
};

// The twist of a differential drive with rim speeds (v_l, v_r) and wheelbase b:
// v = (v_l + v_r)/2, ω = (v_r - v_l)/b.
BodyTwist TwistFromWheels(double left_mps, double right_mps, double wheelbase_m);

// True when the polygon has >= 3 finite vertices, counter-clockwise, strictly convex.
bool IsConvexCounterClockwise(const core::Polygon2& polygon);

// Largest vertex distance from the robot origin (m).
double Circumradius(const core::Polygon2& polygon);

// The convex polygon grown by `offset_m` >= 0 with mitred corners: each edge
// moved outwards by offset_m. It contains the Minkowski sum with the disk of
// radius offset_m, so contact with it is never later than with the rounded one.
core::Polygon2 InflateConvexPolygon(const core::Polygon2& polygon, double offset_m);

// Signed Euclidean distance (m) from the point to the boundary of the convex
// counter-clockwise polygon: positive outside, minus the penetration depth
// inside. `outward_normal` (unit) is the gradient: from the nearest boundary
// point towards the point outside, the nearest edge's outward normal on or
// inside the boundary.
double SignedDistance(const core::Polygon2& polygon, const Eigen::Vector2d& point_in_polygon,
                      Eigen::Vector2d* outward_normal);

// The pose reached after driving `twist` for `time_s` from the origin.
Eigen::Vector3d PoseAfter(const BodyTwist& twist, double time_s);

// The outline of `polygon` (robot frame) at the poses the robot passes while
// it drives `twist` for `duration_s` >= 0, appended to `points` in the frame
// `frame_from_robot`: copies from the start to the end pose, no vertex
// travelling more than `step_m` > 0 between two, each edge sampled at most
// `spacing_m` > 0 apart. Another robot's hull where it will be.
void AppendSweptOutline(const core::Polygon2& polygon, const BodyTwist& twist, double duration_s,
                        double step_m, double spacing_m, const core::Pose2& frame_from_robot,
                        std::vector<Eigen::Vector2d>* points);

// Time (s) until the world-fixed point, given in the robot frame now, first
// touches the boundary of the convex polygon while the robot moves with the
// constant twist: 0 when the point is inside or on it, +inf when it never
// touches (a straight motion that misses, a point on the ICR, a circle that
// misses every edge, a zero twist).
double ExactTimeToCollision(const core::Polygon2& polygon_in_robot, const BodyTwist& twist,
                            const Eigen::Vector2d& point_in_robot);

// Forward arc length (m) to contact on the path of curvature κ (1/m, left
// positive; 0 is straight ahead): ExactTimeToCollision at v = 1 m/s, ω = κ.
double ExactArcLengthToCollision(const core::Polygon2& polygon_in_robot, double curvature_per_m,
                                 const Eigen::Vector2d& point_in_robot);

// Rotation angle (rad) to contact when turning on the spot, counter-clockwise
// when `counter_clockwise`, else clockwise.
double ExactRotationToCollision(const core::Polygon2& polygon_in_robot, bool counter_clockwise,
                                const Eigen::Vector2d& point_in_robot);

}  // namespace pavilion::nav
