#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scenarios/config/scenario.h"
#include "scenarios/metrics/run_metrics.h"

namespace pavilion::scenarios {

// A robot's picture of its localization's 2-sigma bounds over time (PNG bytes).
struct LocalizationPlot {
  std::string robot_id;
  std::vector<std::uint8_t> png;
};

// A robot's location hypotheses after a kidnap, drawn from above (PNG bytes).
struct HypothesisFigure {
  std::string robot_id;
  double time_s = 0.0;
  int hypotheses = 0;
  std::vector<std::uint8_t> png;
};

// A self-contained HTML page for a run: scenario, the figures of metrics.json,
// the top-down snapshot and the robots' localization plots embedded as PNGs.
std::string RenderReportHtml(const Scenario& scenario, const RunMetrics& metrics,
                             const std::vector<std::uint8_t>& topdown_png,
                             const std::vector<LocalizationPlot>& localization_plots = {},
                             const std::vector<HypothesisFigure>& hypothesis_figures = {});

}  // namespace pavilion::scenarios
