#pragma once

#include <string>

#include "scenarios/config/scenario.h"

namespace pavilion::scenarios {

struct RunOptions {
  std::string out_dir;    // every output file goes here (created if missing)
  bool progress = false;  // a live progress line on stderr (TTYs only)
  // Threads for the robots' per-tick work (sensors, localization), the
  // calling thread included; 0: every hardware thread. Outputs do not depend
  // on it (same scenario and seed, same bytes; performance.json aside).
  int threads = 0;
};

struct RunSummary {
  double sim_duration_s = 0.0;
  double wall_time_s = 0.0;       // the whole call: start-up, stepping loop, outputs
  double startup_s = 0.0;         // building the world and robots, before the first step
  double loop_s = 0.0;            // the stepping loop (wall s)
  double loop_cpu_s = 0.0;        // the stepping loop (CPU s of the process)
  double real_time_factor = 0.0;  // sim_duration_s / loop_s
  double physics_s = 0.0;         // of loop_s: Bullet steps
  double sensors_s = 0.0;         // of loop_s: robots' sensors (laser rays) and their controllers
  std::int64_t laser_rays = 0;    // rays cast by every laser (counted by the scanners)
  double peak_rss_mb = 0.0;       // the process' peak resident memory so far
  std::int64_t ticks = 0;
  std::int64_t events = 0;
  std::int64_t laser_fallback_scans = 0;  // planar backend: scans cast partly with Bullet
};

// Runs a scenario to its end and writes metrics.json, performance.json,
// events.jsonl, trajectories.csv, snapshots/topdown_final.png and report.html
// into the output folder. Everything but performance.json is a function of the
// scenario and seed alone. Throws InputError for problems found while setting up
// (e.g. a spawn area too crowded) and std::runtime_error for I/O failures.
RunSummary RunScenario(const Scenario& scenario, const RunOptions& options);

}  // namespace pavilion::scenarios
