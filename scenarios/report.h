#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scenarios/scenario.h"

namespace pavilion::scenarios {

// A self-contained HTML page for a run: scenario, the figures of metrics.json,
// and the top-down snapshot embedded as a PNG.
std::string RenderReportHtml(const Scenario& scenario, const nlohmann::ordered_json& metrics,
                             const std::vector<std::uint8_t>& topdown_png);

}  // namespace pavilion::scenarios
