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

// A crop of the top-down view around the first robot at one moment of the run
// (scenarios/output/crowd_strip.h), as PNG bytes.
struct CrowdFrame {
  std::string path;  // relative to the run's folder: snapshots/crowd_NN.png
  double time_s = 0.0;
  double size_m = 0.0;  // side of the square crop
  std::vector<std::uint8_t> png;
};

// A crowd frame's caption: "t = 120 s", in tenths of a second ("t = 7.5 s")
// where the time is not within 0.05 s of a whole second.
std::string CrowdFrameCaption(double time_s);

// A self-contained HTML page for a run: scenario, the figures of metrics.json,
// the top-down snapshot, the robots' localization plots and, when there are
// any, a strip of crowd frames side by side, embedded as PNGs.
std::string RenderReportHtml(const Scenario& scenario, const RunMetrics& metrics,
                             const std::vector<std::uint8_t>& topdown_png,
                             const std::vector<LocalizationPlot>& localization_plots = {},
                             const std::vector<HypothesisFigure>& hypothesis_figures = {},
                             const std::vector<CrowdFrame>& crowd_frames = {});

}  // namespace pavilion::scenarios
