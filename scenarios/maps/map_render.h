#pragma once

#include "core/map/robot_map.h"
#include "core/types/image.h"
#include "sim/world/world.h"

namespace pavilion::scenarios {

struct MapRenderOptions {
  int width_px = 1400;    // image width; the height follows the drawn area, [50, 8000]
  double margin_m = 0.5;  // border around the world's floor (or the map's extent), >= 0
};

// Draws a robot map from above: segments and multi-segment lines (a tick on
// the side they are seen from, eq. B.4), infinite lines, points with their
// radius, beacons, edges, via and station nodes, and ghost points. With a
// `world`, the image covers its floor like `pavilion world render` and the
// world is drawn underneath in grey; otherwise it covers the map's extent.
core::RgbImage RenderRobotMap(const core::RobotMap& map, const sim::World* world,
                              const MapRenderOptions& options);

}  // namespace pavilion::scenarios
