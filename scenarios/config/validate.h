#pragma once

#include <string>
#include <vector>

#include "scenarios/config/input_error.h"

namespace pavilion::scenarios {

// Checks one input file of any kind Pavilion reads, by its top-level `kind`
// (world, scenario, robot, map); returns every problem found, empty when the file is valid.
// A scenario is checked together with the world it names.
std::vector<Diagnostic> ValidateFile(const std::string& path);

}  // namespace pavilion::scenarios
