#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "sim/world/world_description.h"

namespace pavilion::sim {

// A wall's footprint as one convex quadrilateral per polyline segment, mitred at
// the joints so that neighbours share an edge and never overlap. Vertices are
// counter-clockwise.
using Quad = std::array<Eigen::Vector2d, 4>;
std::vector<Quad> WallFootprint(const Wall& wall);

// The outline of a wall's footprint as counter-clockwise segments (solid on the
// left): both long sides and, for open polylines, the two end caps. Joints
// between neighbouring quads are interior and not part of the outline.
std::vector<std::array<Eigen::Vector2d, 2>> WallOutline(const Wall& wall);

// Largest ratio of mitre length to half thickness at any joint; very sharp turns
// make it large (validation rejects walls above kMaxMitreRatio).
double MaxMitreRatio(const Wall& wall);
inline constexpr double kMaxMitreRatio = 8.0;

// The four footprint corners of a yawed box, counter-clockwise.
Quad BoxFootprint(const Box& box);

}  // namespace pavilion::sim
