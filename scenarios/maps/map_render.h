#pragma once

#include <vector>

#include "core/map/robot_map.h"
#include "core/types/image.h"
#include "scenarios/output/canvas.h"
#include "sim/world/world.h"

namespace pavilion::scenarios {

struct MapRenderOptions {
  int width_px = 1400;    // image width; the height follows the drawn area, [50, 8000]
  double margin_m = 0.5;  // border around the world's floor (or the map's extent), >= 0
};

// Draws a robot map from above in the thesis' style (Fig. 4.2): segments and
// multi-segment lines as lines (a tick on the side they are seen from, eq.
// B.4), infinite lines, vertical edges (points of radius 0) as crosses,
// columns as circles of their radius, beacons, edges, via and station nodes,
// and ghost points; with a scale bar and a legend (MapLegend) in the quietest
// corners. With a `world`, the image covers its floor like `pavilion world
// render` and the world is drawn underneath in grey; otherwise it covers the
// map's extent.
core::RgbImage RenderRobotMap(const core::RobotMap& map, const sim::World* world,
                              const MapRenderOptions& options);

// The legend of RenderRobotMap's picture of `map`: one row per kind of item
// the map holds, features first ("map line", "infinite line", "vertical
// edge", "column", "beacon", "station", "via node", "graph edge", "ghost
// point").
std::vector<LegendEntry> MapLegend(const core::RobotMap& map);

}  // namespace pavilion::scenarios
