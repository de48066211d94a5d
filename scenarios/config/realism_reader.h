#pragma once

#include "scenarios/config/realism.h"
#include "scenarios/config/yaml_reader.h"

namespace pavilion::scenarios {

// Reads the scenario's `realism:` key: `ideal`, `realistic`, or a mapping
// {profile: ideal | realistic, <RealismProfile magnitudes>}. Absent: ideal.
// Errors go to `doc` as file:line: realism.key: message.
void ReadRealism(YamlDocument* doc, MapReader& top, RealismProfile* profile);

}  // namespace pavilion::scenarios
