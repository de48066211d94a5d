#pragma once

// The charts of report.html (issue 17), drawn by the inlined Chart.js from
// data embedded in the page: each chart a spec (kind, axes, datasets of
// decimated points) that one small script turns into a Chart.js chart.

#include <array>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "scenarios/output/report_data.h"
#include "scenarios/output/series_decimator.h"

namespace pavilion::scenarios {

// The world rectangle a top-down picture shows (x right, y up), m.
struct PictureExtent {
  double min_x_m = 0.0;
  double min_y_m = 0.0;
  double max_x_m = 1.0;
  double max_y_m = 1.0;
};

// The charts' time axis: from 0 to the run's end, in seconds, minutes or
// hours after the run's length, so that a 12-hour day reads in hours.
struct TimeUnit {
  std::string name = "s";
  double seconds = 1.0;  // seconds per unit
  double end = 0.0;      // the run's end in this unit; 0: the data's extent

  static TimeUnit For(double duration_s);
};

struct ChartDataset {
  std::string label;                          // the legend's text, with the unit
  std::string color;                          // CSS colour
  std::vector<std::array<double, 3>> points;  // x, y and (map markers) time
  bool line = true;                           // joined; else markers only
  bool stepped = false;                       // a count: flat until the next point
  double radius_px = 0.0;                     // markers
};

struct ChartSpec {
  enum class Kind { kLine, kTimeline, kMap };
  Kind kind = Kind::kLine;
  std::string id;  // the canvas' id
  std::string x_label;
  std::string y_label;
  std::string x_unit;           // in tooltips
  std::optional<double> x_max;  // time charts: the run's end (they start at 0)
  bool counts = false;          // whole-number y ticks
  bool log_y = false;           // a logarithmic y axis at first (a button switches)
  std::vector<ChartDataset> datasets;
  std::vector<std::string> lanes;       // timeline: the y axis' lanes, top down
  std::string background_image_id;      // map: the <img> drawn under the markers
  std::optional<PictureExtent> extent;  // map: the axes' ranges
};

// The charts a report shows, each built from the run's series.
ChartSpec LocalizationChart(const RobotErrorSeries& series, const TimeUnit& unit,
                            const std::string& id);
ChartSpec VisitorsChart(const SeriesDecimator& visitors_present, const TimeUnit& unit,
                        const std::string& id);
ChartSpec MissionsChart(const EventSeries& events, const TimeUnit& unit, const std::string& id);
ChartSpec TimelineChart(const EventSeries& events, const TimeUnit& unit, const std::string& id);
// Where events with a position happened, over the top-down picture `image_id`.
ChartSpec EventMapChart(const EventSeries& events, const PictureExtent& extent,
                        const std::string& image_id, const std::string& id);

// A chart's place on the page: its canvas in a box the chart sizes
// (`description`: plain text, for screen readers).
std::string ChartCanvas(const ChartSpec& chart, const std::string& description);

// The page's scripts: the charts' data as JSON, Chart.js inlined, and the
// script that draws every chart once the page (and its images) loaded.
// Nothing when there are no charts.
std::string ChartScripts(const std::vector<ChartSpec>& charts);

// `text` with & < > " escaped for HTML text and attribute values.
std::string EscapeHtml(const std::string& text);

// `value` as JSON text safe inside a <script> element: every '<' escaped as
// \u003c, so no "</script" or "<!--" can occur.
std::string JsonForScript(const nlohmann::json& value);

}  // namespace pavilion::scenarios
