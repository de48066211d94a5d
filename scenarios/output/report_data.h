#pragma once

// The report's time series, read back from a run's line files at its end
// (localization.csv, events.jsonl): streamed line by line into bounded,
// decimated series, so a 12-hour run's files never sit in memory.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "scenarios/output/series_decimator.h"

namespace pavilion::scenarios {

// A robot's localization over time (localization.csv), one series per column.
struct RobotErrorSeries {
  std::string robot_id;
  SeriesDecimator position_error_m;
  SeriesDecimator two_sigma_frontal_m;
  SeriesDecimator two_sigma_lateral_m;
};

// Where events happened on the floor (world frame, m), a bounded sample:
// every stride-th event of the kind, the stride doubling when full.
struct MapMarkers {
  std::string label;  // as its timeline lane
  struct Marker {
    double t_s = 0.0;
    double x_m = 0.0;
    double y_m = 0.0;
  };
  std::vector<Marker> markers;
  std::int64_t seen = 0;    // events of the kind with a position
  std::int64_t stride = 1;  // every stride-th of them kept

  void Add(const Marker& m, std::size_t max_markers);
};

// One lane of the event timeline: the times of one kind of event (a
// collision's class makes its own lane).
struct EventLane {
  std::string label;      // "collision: visitor", "kidnap"
  SeriesDecimator times;  // value: the lane's index on the page (set when drawn)
};

// What events.jsonl says over time.
struct EventSeries {
  // Missions started / completed / aborted so far (cumulative counts).
  SeriesDecimator missions_started;
  SeriesDecimator missions_completed;
  SeriesDecimator missions_aborted;
  std::vector<EventLane> lanes;     // in display order (EventLaneOrder)
  std::vector<MapMarkers> markers;  // kinds with positions, in lane order
  std::int64_t events = 0;          // lines read as events
  std::int64_t skipped_lines = 0;   // not a JSON object with time_s and type
  double end_s = 0.0;               // run_finished, else the last event's time
};

struct ReportSeriesOptions {
  std::size_t max_points = SeriesDecimator::kDefaultMaxPoints;  // per series, >= 4
  std::size_t max_markers = 2000;                               // per kind of event on the map
  std::size_t max_lanes = 24;  // distinct timeline lanes; later kinds go to "other"
};

// Everything the report's charts read back from the run's folder.
struct ReportSeries {
  std::vector<RobotErrorSeries> localization;  // in `robot_order`, then by id
  EventSeries events;
};

// Streams `localization_csv` (columns by header name: time_s, id,
// position_error_m, two_sigma_frontal_m, two_sigma_lateral_m). Robots come in
// `robot_order`, robots not in it after them by id. A missing file gives no
// series; malformed rows are skipped.
std::vector<RobotErrorSeries> ReadLocalizationSeries(const std::filesystem::path& localization_csv,
                                                     const std::vector<std::string>& robot_order,
                                                     const ReportSeriesOptions& options = {});

// Streams `events_jsonl`. A missing file gives empty series; lines that are
// not events (a cut last line) are counted in skipped_lines.
EventSeries ReadEventSeries(const std::filesystem::path& events_jsonl,
                            const ReportSeriesOptions& options = {});

// A timeline lane's label for an event: its type, and for a collision with a
// `class` field the class in words ("collision: visitor").
std::string EventLaneLabel(const std::string& type, const std::string& collision_class);

// Reads both files of the run folder `out`.
ReportSeries ReadReportSeries(const std::filesystem::path& out,
                              const std::vector<std::string>& robot_order,
                              const ReportSeriesOptions& options = {});

}  // namespace pavilion::scenarios
