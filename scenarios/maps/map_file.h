#pragma once

#include <string>

#include "core/map/robot_map.h"
#include "scenarios/config/yaml_reader.h"

namespace pavilion::scenarios {

// Robot map files (`worlds/<name>/map.yaml`, docs/map_format.md): the a-priori
// map of thesis §4.3 and §6.3.1 (features, topology, ghost points).

// Reads a map file. Throws InputError listing every problem
// (file:line: key.path: message).
core::RobotMap LoadMapFile(const std::string& path);

// Reads a map from an already parsed document, adding problems to `doc`.
core::RobotMap ReadRobotMap(YamlDocument* doc);

// The text of a map file. Deterministic (the same map gives the same bytes) and
// exact: numbers are printed in the shortest form that reads back to the same
// double, so ReadRobotMap(RobotMapToYaml(m)) == m. Throws std::invalid_argument
// when the map breaks core::ValidateRobotMap or an id is not a name.
std::string RobotMapToYaml(const core::RobotMap& map);

// Writes RobotMapToYaml(map) to `path` atomically.
void WriteMapFile(const std::string& path, const core::RobotMap& map);

}  // namespace pavilion::scenarios
