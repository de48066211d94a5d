#pragma once

// The files a run writes at its end: snapshots/topdown_final.png, one
// snapshots/two_sigma_<robot>.png per robot that localizes, the crowd strip's
// snapshots/crowd_NN.png, report.html and performance.json (the one file with
// wall-clock figures).

#include <Eigen/Core>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "nav/mission/mission.h"
#include "nav/stack/pose_estimator.h"
#include "scenarios/config/scenario.h"
#include "scenarios/expect/expectation_result.h"
#include "scenarios/metrics/localization_tracker.h"
#include "scenarios/metrics/run_metrics.h"
#include "scenarios/output/camera_snapshots.h"
#include "scenarios/output/report.h"
#include "scenarios/output/series_decimator.h"
#include "scenarios/run/scenario_runner.h"
#include "sim/world/world.h"

namespace pavilion::scenarios {

class CrowdStrip;

// A robot's location hypotheses at one moment after a kidnap (issue 18): the
// largest set its global localization held, with the truth.
struct HypothesisSnapshot {
  double time_s = 0.0;
  core::Pose2 truth;
  std::vector<nav::LocationHypothesis> hypotheses;  // best first
};

// What a robot's trajectory looked like, for the top-down picture.
struct RobotTracks {
  std::vector<Eigen::Vector2d> truth;
  std::vector<Eigen::Vector2d> odometry;  // what its encoders believe
  std::vector<Eigen::Vector2d> estimate;  // its localization (robots that localize)
  // Its navigation at the end (robots with a mission): plan, band, DWA arc.
  std::optional<nav::NavigationPicture> navigation;
  std::optional<HypothesisSnapshot> hypotheses;  // robots with global localization, kidnapped
};

// A robot's localization record for its 2-sigma plot.
struct RobotLocalization {
  std::string robot_id;
  const LocalizationTracker* tracker = nullptr;
};

// Pictures the world at the end of the run, writes the figures under
// snapshots/ (with the frames `crowd_strip` captured and the snapshot of the
// first overlap deadlock and the scenario's camera snapshots, when given) and
// report.html: its charts read localization.csv and events.jsonl back from
// `out` (streamed, bounded memory), plus the visitors present over time and
// the expectations' results when given.
void WriteSnapshotsAndReport(const std::filesystem::path& out, const Scenario& scenario,
                             const sim::World& world,
                             const std::vector<std::vector<Eigen::Vector2d>>& body_tracks,
                             const std::vector<RobotTracks>& robot_tracks,
                             const std::vector<RobotLocalization>& localizations,
                             const RunMetrics& metrics, const CrowdStrip* crowd_strip = nullptr,
                             const SeriesDecimator* visitors_present = nullptr,
                             const ExpectationResults* expectations = nullptr,
                             const DeadlockFrame* first_deadlock = nullptr,
                             const std::vector<SnapshotFrame>* camera_snapshots = nullptr);

// performance.json from the run's summary.
void WritePerformanceJson(const std::filesystem::path& out, const RunSummary& summary, int threads,
                          const std::string& laser_backend);

}  // namespace pavilion::scenarios
