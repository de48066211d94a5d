#pragma once

#include <string>

#include "sim/robot/robot_config.h"
#include "sim/world/world_description.h"

namespace pavilion::scenarios {

// A robot file's configuration as the simulator builds it into `world`: the
// robot's own materials are added to `world` as "<model>/<name>" (so two
// models never clash with each other or with the world's), and its model's and
// markers' material names are scoped alike.
sim::RobotConfig WithWorldMaterials(sim::RobotConfig config, sim::WorldDescription* world);

}  // namespace pavilion::scenarios
