#pragma once

#include <Eigen/Core>
#include <memory>

#include "core/types/pose2.h"
#include "sim/world/world_description.h"

// Bullet types are only declared here: this header is included by the world's
// implementation units, which include Bullet themselves (the layer lint keeps
// Bullet includes out of every sim/ header).
class btBoxShape;
class btTransform;
class btVector3;

namespace pavilion::sim {

btVector3 ToBt(const Eigen::Vector3d& v);

// The yaw of a Bullet transform (Z of its ZYX Euler angles), rad.
double YawOf(const btTransform& t);

// A pose on the floor lifted to height z.
btTransform PlanarTransform(const core::Pose2& pose, double z);

// A box whose collision margin fits inside it: Bullet keeps the margin inside
// a box's extents, and a margin larger than the thinnest half extent (a 4 cm
// door under the default 4 cm) distorts the shape by centimetres.
std::unique_ptr<btBoxShape> MakeBox(const Eigen::Vector3d& half_m);

// The transform of a box's centre.
btTransform BoxTransform(const Box& box);

}  // namespace pavilion::sim
