#pragma once

// A scenario robot's software (nav::Navigator) assembled from its entry: dead
// reckoning with its calibrated odometry, the EKF when it has a
// `localization:` block, and the controller of its `drive:`, `route:` or
// `wander:` block.

#include <cstddef>
#include <memory>
#include <optional>

#include "core/map/robot_map.h"
#include "nav/fleet/coordinator.h"
#include "nav/stack/navigator.h"
#include "scenarios/config/scenario.h"

namespace pavilion::scenarios {

// The map a robot localizes and plans with: its map file (default: the
// world's map.yaml), or for `map: derive` a map derived from `world` (static
// geometry only: call before bodies and robots are added) with the entry's
// tape-measure noise drawn from the scenario's seed. Throws InputError naming
// the scenario key for a bad map.
core::RobotMap LoadRobotMap(const RobotEntry& robot, const Scenario& scenario,
                            const sim::World& world);

// True when the robot needs a map (it localizes or follows a route).
bool NeedsMap(const RobotEntry& robot);

// The robot stack of `scenario.robots[index]`; `map` is its LoadRobotMap()
// when NeedsMap(). Throws InputError naming the scenario key for a route
// through stops the map does not have. A mission robot joins `fleet` when it
// has a coordinator (issue 15).
std::unique_ptr<nav::Navigator> MakeNavigator(const Scenario& scenario, std::size_t index,
                                              const std::optional<core::RobotMap>& map,
                                              nav::FleetLink fleet = {});

}  // namespace pavilion::scenarios
