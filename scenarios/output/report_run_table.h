#pragma once

// The report's run table (issue 21): the run in the figures of thesis
// Table 4.3 and Expo.02's statistics — hours, distance, missions, localization
// cycles, lost situations by cause, recoveries, collisions by class, deadlocks,
// interventions — with the scenario's `reference:` figures beside them.

#include <sstream>

#include "scenarios/config/scenario.h"
#include "scenarios/metrics/run_metrics.h"

namespace pavilion::scenarios {

void RunTableSection(std::ostringstream& html, const Scenario& scenario, const RunMetrics& m);

}  // namespace pavilion::scenarios
