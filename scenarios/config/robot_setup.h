#pragma once

#include <string>

#include "core/types/pose2.h"
#include "sim/robot/robot_config.h"
#include "sim/robot/sim_robot.h"
#include "sim/world/world_description.h"

namespace pavilion::scenarios {

// Turns a robot file's configuration into what the simulator builds: the
// robot's own materials are added to `world` as "<model>/<name>" (so two
// models never clash with each other or with the world's), its markers become
// chassis attachments and its lasers scanner mounts.
sim::SimRobotSetup MakeSimRobotSetup(const std::string& id, const sim::RobotConfig& config,
                                     const core::Pose2& pose, sim::WorldDescription* world);

}  // namespace pavilion::scenarios
