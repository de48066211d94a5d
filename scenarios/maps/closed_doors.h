#pragma once

// The doors closed at a run's start, applied to a robot's map: edges of the
// topology whose straight line crosses a closed door's panel are dropped, so
// that the global planner neither plans through them nor calls a room behind
// one reachable (issue 14: an unreachable goal is an error before the run).

#include <string>
#include <vector>

#include "core/map/robot_map.h"
#include "sim/world/world_description.h"

namespace pavilion::scenarios {

// Removes the edges crossing any closed door of `doors`; returns their
// "from-to" names in map order.
std::vector<std::string> RemoveEdgesThroughClosedDoors(const std::vector<sim::Door>& doors,
                                                       core::RobotMap* map);

}  // namespace pavilion::scenarios
