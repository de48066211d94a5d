#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "scenarios/config/scenario.h"
#include "scenarios/expect/expectation_result.h"
#include "scenarios/metrics/run_metrics.h"
#include "scenarios/output/camera_snapshots.h"
#include "scenarios/output/report_charts.h"
#include "scenarios/output/report_data.h"
#include "scenarios/output/series_decimator.h"

namespace pavilion::scenarios {

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

// The top-down view around the robot that detected a run's first overlap
// deadlock (thesis §6.5), at that moment: snapshots/deadlock_first.png.
struct DeadlockFrame {
  std::string robot_id;
  CrowdFrame frame;
};

// A crowd frame's caption: "t = 120 s", in tenths of a second ("t = 7.5 s")
// where the time is not within 0.05 s of a whole second.
std::string CrowdFrameCaption(double time_s);

// What report.html shows beside the scenario and its metrics.
struct ReportContent {
  std::vector<std::uint8_t> topdown_png;  // snapshots/topdown_final.png
  // The world rectangle the picture shows: events with a position are marked
  // on it (none: the picture alone).
  std::optional<PictureExtent> topdown_extent;
  std::vector<HypothesisFigure> hypothesis_figures;
  std::vector<CrowdFrame> crowd_frames;
  std::optional<DeadlockFrame> first_deadlock;
  // The scenario's `snapshots:` pictures (camera and overview), in the order taken.
  const std::vector<SnapshotFrame>* camera_snapshots = nullptr;
  // Read back from the run's line files (ReadReportSeries); null: no charts
  // of them.
  const ReportSeries* series = nullptr;
  const SeriesDecimator* visitors_present = nullptr;  // null: the run has no crowd
  const ExpectationResults* expectations = nullptr;   // null: the scenario has none
  // The run's output files that exist, relative to its folder, linked in
  // this order.
  std::vector<std::string> files;
};

// A self-contained HTML page for a run (docs/report.md): the expectations'
// outcome, a run table after thesis Table 4.3, charts drawn by the inlined
// Chart.js (localization error and 2 sigma, visitors present, missions, the
// event timeline, events on the top-down picture), the figures of
// metrics.json, and the crowd strip and hypothesis figures as PNGs. The same
// inputs give the same bytes.
std::string RenderReportHtml(const Scenario& scenario, const RunMetrics& metrics,
                             const ReportContent& content);

// A number for people: `significant` digits, never fewer than the integer
// part has (17.513708 -> "17.5", 0.0131234 -> "0.0131", 145433.2 -> "145,433"),
// thousands grouped with commas, no trailing zeros after the point.
std::string HumanNumber(double value, int significant = 3);
// A count with its thousands grouped: 145433 -> "145,433".
std::string HumanCount(std::int64_t count);
// A length: "17.5 m", from 1 km on "5.01 km".
std::string HumanDistance(double metres);
// A duration: "45 s", from 2 min on "12.5 min", from 2 h on "28 h".
std::string HumanDuration(double seconds);

}  // namespace pavilion::scenarios
