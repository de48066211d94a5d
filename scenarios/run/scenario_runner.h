#pragma once

#include <csignal>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "scenarios/config/scenario.h"
#include "scenarios/expect/expectation_result.h"
#include "scenarios/metrics/run_metrics.h"
#include "scenarios/run/run_observer.h"
#include "sim/robot/sim_robot.h"

namespace pavilion::scenarios {

struct RunOptions {
  std::string out_dir;    // every output file goes here (created if missing)
  bool progress = false;  // a live progress line on stderr (TTYs only)
  // Threads for the robots' per-tick work (sensors, robot stacks), the
  // calling thread included; 0: every hardware thread. Outputs do not depend
  // on it (same scenario and seed, same bytes; performance.json aside).
  int threads = 0;
  // Set (by a signal handler) to a signal number to end the run early and
  // cleanly: the files are flushed and valid, metrics.json says
  // "interrupted": true and run_finished names the signal. Read once per tick.
  const volatile std::sig_atomic_t* stop_signal = nullptr;
};

// Additions to a run from outside the runner (tests, tools): called for each
// robot after it is built (e.g. to add a sensor with SimRobot::AddSensor), and
// observers of every tick's sensor outputs. Both may be empty.
struct RunExtensions {
  std::function<void(const RobotEntry&, sim::SimRobot*)> add_sensors;
  std::vector<RunObserver*> observers;
};

struct RunSummary {
  double sim_duration_s = 0.0;
  double wall_time_s = 0.0;       // the whole call: start-up, stepping loop, outputs
  double startup_s = 0.0;         // building the world and robots, before the first step
  double loop_s = 0.0;            // the stepping loop (wall s)
  double loop_cpu_s = 0.0;        // the stepping loop (CPU s of the process)
  double real_time_factor = 0.0;  // sim_duration_s / loop_s
  double physics_s = 0.0;         // of loop_s: Bullet steps
  double sensors_s = 0.0;         // of loop_s: robots' sensors (laser rays) and their stacks
  // Robot stacks' estimators, thread seconds summed over robots: ticks that
  // completed a localization cycle (extraction, matching, update) and the
  // others (odometry prediction only).
  double estimator_cycle_s = 0.0;
  double estimator_tick_s = 0.0;
  // Thread time in the robots' control steps (Navigator::Control: the chapter 6
  // navigation's dynamic window, band and planning) and the simulated robot-seconds.
  double control_s = 0.0;
  double robot_sim_s = 0.0;
  std::int64_t estimator_cycles = 0;
  std::int64_t estimator_ticks = 0;  // robot-ticks without a cycle
  std::int64_t laser_rays = 0;       // rays cast by every laser (counted by the scanners)
  double peak_rss_mb = 0.0;          // the process' peak resident memory so far
  std::int64_t ticks = 0;
  std::int64_t events = 0;
  std::int64_t laser_fallback_scans = 0;  // planar backend: scans cast partly with Bullet
  RunMetrics metrics;                     // what metrics.json holds
  // The scenario's `expect:` judged (expectations.json); none without one.
  std::optional<ExpectationResults> expectations;
  int interrupted_by = 0;  // the signal that ended the run early; 0: it ran to its end
  // Why the simulated world ended the run early (a robot left the floor); the
  // outputs hold the run up to then and the run fails. Empty: it did not.
  std::string ended_early;
};

// Runs a scenario to its end and writes metrics.json, performance.json,
// events.jsonl, trajectories.csv, localization.csv, scans.bin,
// snapshots/*.png and report.html into the output folder. Everything but
// performance.json is a function of the scenario and seed alone. Throws
// InputError for problems found while setting up (e.g. a spawn area too
// crowded) and std::runtime_error for I/O failures.
RunSummary RunScenario(const Scenario& scenario, const RunOptions& options,
                       const RunExtensions& extensions = {});

}  // namespace pavilion::scenarios
