#pragma once

#include <cstdint>

#include "scenarios/config/realism.h"
#include "scenarios/config/scenario.h"

namespace pavilion::scenarios {

// Builds the physical robot of a `realism: realistic` scenario (issue 20):
// its true wheels (radius ratio, wheelbase and mean radius off the robot
// file's within the calibration's residuals) and, per laser, the true mount,
// the mirror's angular offset, a latency, and the range errors of
// sim::LaserSystematicErrors. Draws from streams named after the robot and
// laser ("realism/<robot>/wheels", "realism/<robot>/laser/<id>"), so the
// draws do not depend on the order of the entries. The robot's software
// (odometry calibration, laser profile as the extraction sees it) is left as
// the robot file gives it. Does nothing for an ideal profile.
void DrawRealisticRobot(const RealismProfile& profile, std::uint64_t seed, RobotEntry* robot);

// The seed of the surface biases every laser of a run shares: a wall reads
// long alike for every robot that sees it.
std::uint64_t SurfaceBiasSeed(std::uint64_t seed);

}  // namespace pavilion::scenarios
