#pragma once

// The shipped robot files (robots/<name>/robot.yaml), each loaded once per
// test binary.

#include <map>
#include <string>

#include "scenarios/config/robot_loader.h"

namespace pavilion::testing {

inline const sim::RobotConfig& ShippedRobot(const std::string& name) {
  static std::map<std::string, sim::RobotConfig> loaded;
  auto it = loaded.find(name);
  if (it == loaded.end()) {
    it = loaded
             .emplace(name, scenarios::LoadRobotFile(std::string(PAVILION_SOURCE_DIR) + "/robots/" +
                                                     name + "/robot.yaml"))
             .first;
  }
  return it->second;
}

}  // namespace pavilion::testing
