#pragma once

#include <map>
#include <string>

#include "scenarios/config/yaml_reader.h"
#include "sim/world/world_description.h"

namespace pavilion::scenarios {

// Reads a world file (docs/world_format.md). Throws InputError listing every
// problem (file:line: key.path: message).
sim::WorldDescription LoadWorldFile(const std::string& path);

// Reads a world from an already parsed document, adding problems to `doc`.
sim::WorldDescription ReadWorld(YamlDocument* doc);

// Reads a mapping of material names to properties (the `materials` section of
// world and scenario files) into `out`.
void ReadMaterialMap(YamlDocument* doc, const YAML::Node& node, const std::string& path,
                     std::map<std::string, sim::Material>* out);

}  // namespace pavilion::scenarios
