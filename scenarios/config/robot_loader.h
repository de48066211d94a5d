#pragma once

#include <string>

#include "scenarios/config/yaml_reader.h"
#include "sim/robot/robot_config.h"

namespace pavilion::scenarios {

// Reads a robot file (docs/robot_format.md) and the URDF it names. Throws
// InputError listing every problem (file:line: key.path: message); a problem
// in the URDF is reported at the robot file's `urdf` key (or at the key that
// names a missing link or joint) with the URDF's own file:line message.
sim::RobotConfig LoadRobotFile(const std::string& robot_yaml_path);

// Reads a robot from an already parsed document, adding problems to `doc`.
sim::RobotConfig ReadRobot(YamlDocument* doc);

}  // namespace pavilion::scenarios
