#pragma once

// Reads a scenario's `expect:` list (expectation.h), checking every metric
// path, robot id, event type and comparison before the run.

#include <vector>

#include "scenarios/config/yaml_reader.h"
#include "scenarios/expect/expectation.h"
#include "scenarios/expect/metrics_schema.h"

namespace pavilion::scenarios {

// Reads `expect:` of the scenario's top-level mapping (absent: none);
// problems go to the reader's document.
std::vector<Expectation> ReadExpectations(MapReader& top, const MetricIds& ids);

}  // namespace pavilion::scenarios
