#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/geometry/planar_section.h"
#include "sim/world/world.h"

// Bullet types are only declared here (the layer lint keeps Bullet includes out
// of every sim/ header); the callers include Bullet themselves.
class btTransform;
class btVector3;

namespace pavilion::sim {

// Cuts of dynamic shapes by the plane z = h (World::AppendDynamicSection).
// Shapes are placed by Bullet transforms; `h` is in the world frame. Where
// `uncut` may be given, a null `uncut` asks for an approximation instead (the
// top-down view and spawn checks).

// A sphere: a circle while the plane crosses it.
void CutSphere(const btVector3& centre, double radius, double h, int element,
               core::PlanarSection* out);

// A vertical prism over a convex counter-clockwise polygon (shape frame), z
// in [z0, z1), placed by `t`. While the plane crosses only its side faces the
// cut is exact at any tilt: the points where the plane meets the side edges,
// still counter-clockwise (the map from the polygon to its cut is affine with a
// positive determinant while the axis points up). A plane through a cap gives
// another polygon: listed in `uncut`, or with a null `uncut` added as the
// upright extrusion at the prism's planar pose.
void CutPrism(const btTransform& t, const std::vector<Eigen::Vector2d>& polygon, double z0,
              double z1, double h, int element, core::PlanarSection* out,
              std::vector<UncutElement>* uncut);

// A cylinder about its shape z axis, centred at its origin. Upright, its cut is
// a circle; tilted by θ it is an ellipse with semi-axes r and r/cos θ about the
// point where the axis meets the plane (a point at distance x along the axis'
// horizontal direction and y across it is |p − axis| = √(x² cos² θ + y²) from
// the axis), taken as the circle of radius r there while θ <= max_tilt_rad
// (error r(1/cos θ − 1): 7.6 µm for r = 5 cm at 1°) and as the ellipse beyond.
// With the plane through a cap it goes to `uncut` (or, with a null `uncut`, is
// added as the circle anyway).
void CutCylinder(const btTransform& t, double radius, double half_height, double h,
                 double max_tilt_rad, int element, core::PlanarSection* out,
                 std::vector<UncutElement>* uncut);

}  // namespace pavilion::sim
