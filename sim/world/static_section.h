#pragma once

#include "core/geometry/planar_section.h"
#include "sim/world/world_description.h"

namespace pavilion::sim {

// Appends the cut of the static elements of `description` (walls, boxes,
// cylinders, meshes, doors in their current state) by the plane z = height_m,
// with the element indices of sim::World (the floor 0, then description order).
void AppendStaticSection(const WorldDescription& description, double height_m,
                         core::PlanarSection* out);

}  // namespace pavilion::sim
