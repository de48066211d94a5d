#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "core/types/image.h"
#include "sim/world/world.h"

namespace pavilion::sim {

struct TopDownOptions {
  int width_px = 900;             // image width; the height follows the floor's aspect, [50, 8000]
  double margin_m = 0.5;          // border around the floor
  double section_height_m = 0.5;  // the cut drawn in black (what a laser at this height sees)
  bool draw_places = true;        // named points and areas
};

// A polyline drawn over the view (e.g. a body's true trajectory).
struct TopDownTrack {
  std::vector<Eigen::Vector2d> points_m;
  std::array<std::uint8_t, 3> rgb{200, 40, 40};
  double alpha = 1.0;     // opacity in [0, 1]
  double width_px = 1.0;  // line width
};

// Renders the world seen from above: floor, element footprints in their material
// colours, the section at the beam height outlined (laser-transparent parts in
// light blue), places, bodies and robots at their current poses, and tracks.
core::RgbImage RenderTopDown(const World& world, const std::vector<TopDownTrack>& tracks,
                             const TopDownOptions& options);

}  // namespace pavilion::sim
