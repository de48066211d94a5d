#pragma once

// The scenario's bodies put into the world: spawn areas drawn from the run's
// seeded stream (clear of the world and of earlier bodies), and each body's
// motion (scripted profile or random walk).

#include <memory>
#include <vector>

#include "scenarios/config/scenario.h"
#include "sim/bodies/body_motion.h"

namespace pavilion::scenarios {

// Adds every body of `scenario` to `world` in order; returns their motions
// (null for bodies that do not move by themselves). Throws InputError when a
// spawn area is too small or too crowded.
std::vector<std::unique_ptr<sim::BodyMotion>> SpawnBodies(const Scenario& scenario,
                                                          sim::World* world);

}  // namespace pavilion::scenarios
