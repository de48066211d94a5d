#pragma once

// The finite geometry a RobotMap describes, in the map frame: what a beam can
// hit. The MCL baseline's likelihood field rasterizes it; the free-space
// constraint of global localization casts beams against it.

#include <Eigen/Core>
#include <utility>
#include <vector>

#include "core/geometry/segment2.h"
#include "core/map/robot_map.h"

namespace pavilion::core {

// What to do with the map's infinite lines, which have no extent.
enum class InfiniteLines {
  kClipToBounds,  // clipped to the bounding box of the finite geometry
  kOmit,          // left out: nothing is known of where the wall ends
};

// Every segment, every member segment of each multi-segment line, the infinite
// lines as `lines` says (none when there is no finite geometry to clip to),
// and the points and beacons as discs (radius 0: a point).
struct MapGeometry {
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> segments;  // endpoints, m
  std::vector<std::pair<Eigen::Vector2d, double>> discs;              // centre, radius (m)
  Box2 bounds;  // of the segments (before the clipped lines) and the discs; empty when none
};

MapGeometry CollectMapGeometry(const RobotMap& map,
                               InfiniteLines lines = InfiniteLines::kClipToBounds);

}  // namespace pavilion::core
