#pragma once

// The scenario runner's private state (scenario_runner.h runs it): a run's
// world, robots, logs and tallies, and the phases of a tick. Shared by
// scenario_runner.cc (building, stepping, finishing) and
// scenario_run_records.cc (what a tick records: contacts, localization
// cycles, navigation events, trajectory rows, the metrics).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <set>
#include <tuple>

#include "nav/reactive/swept_polygon.h"
#include "nav/stack/navigator.h"
#include "scenarios/config/input_error.h"
#include "scenarios/config/robot_setup.h"
#include "scenarios/events/event_log.h"
#include "scenarios/events/event_types.h"
#include "scenarios/expect/expect_eval.h"
#include "scenarios/metrics/collision_classes.h"
#include "scenarios/metrics/localization_tracker.h"
#include "scenarios/metrics/relocalization_tracker.h"
#include "scenarios/metrics/robot_proximity.h"
#include "scenarios/metrics/run_table.h"
#include "scenarios/metrics/social_navigation.h"
#include "scenarios/metrics/stride_buffer.h"
#include "scenarios/output/camera_snapshots.h"
#include "scenarios/output/crowd_strip.h"
#include "scenarios/output/run_logs.h"
#include "scenarios/output/run_outputs.h"
#include "scenarios/output/scan_log.h"
#include "scenarios/output/series_decimator.h"
#include "scenarios/realism/world_realism.h"
#include "scenarios/run/body_spawner.h"
#include "scenarios/run/progress_line.h"
#include "scenarios/run/robot_stack.h"
#include "scenarios/run/scenario_runner.h"
#include "scenarios/version.h"
#include "sim/raycast/planar_caster.h"
#include "sim/runtime/schedule.h"
#include "sim/runtime/worker_pool.h"

namespace pavilion::scenarios::detail {

using Clock = std::chrono::steady_clock;

// Events are due when their time is reached up to this rounding of tick times (s).
inline constexpr double kDueToleranceS = 1e-9;
inline constexpr double kDegPerRad = 180.0 / std::numbers::pi;
// A walker that touches a robot stands this long from the contact's start and
// again from its end (s): long enough for its random walk to give up the leg
// (RandomWalkOptions::blocked_s) and turn elsewhere instead of walking
// straight back into it.
inline constexpr double kWalkerContactPauseS = 3.0;
// A walker heading for a robot stops this far (m) from the robot's bounding
// circle, as a person would in front of a moving machine: a blind walk into
// it at 0.8 m/s would leave the robot less than its braking distance (about
// 0.25 m at 0.6 m/s) and make every such meeting a collision.
inline constexpr double kWalkerMeetGapM = 0.3;
// Approach speeds (m/s) closer than this count as neither moving into the other.
inline constexpr double kApproachTieMps = 0.01;

inline double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// Points kept of each path for the top-down picture: a 60 s demo keeps every
// trajectory row, a 12 h day one every few seconds (memory flat in duration).
inline constexpr std::size_t kRobotPathPoints = 20000;
inline constexpr std::size_t kBodyPathPoints = 8192;

// One robot of a run: its simulated body and sensors, its software, and what
// the run counts and draws of it.
struct RobotRun {
  const RobotEntry* entry = nullptr;
  std::unique_ptr<sim::SimRobot> robot;
  std::unique_ptr<nav::Navigator> navigator;
  std::optional<LocalizationTracker> tracker;  // robots that localize
  std::optional<RelocalizationTracker> relocalization;
  // The shadow estimator's (Navigator::shadow_estimator), judged the same way.
  std::optional<LocalizationTracker> shadow_tracker;
  std::optional<RelocalizationTracker> shadow_relocalization;
  std::optional<SocialNavigationTracker> social;  // runs with a crowd
  std::optional<RobotDayTracker> day;             // robots that localize: the run table
  RobotMetrics tally;
  RobotTracks tracks;  // hypotheses; the paths are filled in from the buffers at the end
  // Its paths for the top-down picture (truth, odometry, estimate), bounded.
  StrideBuffer<Eigen::Vector2d> truth_path{kRobotPathPoints};
  StrideBuffer<Eigen::Vector2d> odometry_path{kRobotPathPoints};
  StrideBuffer<Eigen::Vector2d> estimate_path{kRobotPathPoints};
  bool mission_done_reported = false;
  bool kidnapped = false;  // a kidnap happened: its hypotheses are pictured
};

// What a robot's work of a tick produced (its own slot: written by one thread).
struct TickWork {
  std::optional<nav::WheelSpeeds> command;  // Control(): new wheel speeds before the step
  double control_s = 0.0;
  sim::SensorOutputs outputs;
  nav::SenseResult sensed;
  double estimator_s = 0.0;
};

// A scenario run: built by the constructor, stepped by Run(), written by Finish().
class ScenarioRun {
 public:
  ScenarioRun(const Scenario& scenario, const RunOptions& options, const RunExtensions& extensions);
  void Run();
  RunSummary Finish();

 private:
  void BuildRobots(std::vector<sim::RobotConfig> configs,
                   const std::vector<std::optional<core::RobotMap>>& maps);
  void OpenLogs();
  // The phases of a tick, in order.
  void ApplyEvents(double t);
  void EmitScripted(double t, const ScenarioEvent& e, const EventFields& fields);
  void MoveBodies(double t);
  void ControlRobots(std::int64_t tick, double t);
  void StepPhysics();
  void RecordContacts(double t_after);
  void ClassifyContact(const sim::ContactChange& c, double t_after);
  // A walker of body `b` walking at `velocity` is about to touch a robot.
  bool WalkerMeetsRobot(int b, const Eigen::Vector2d& velocity) const;
  void EmitNavigationEvents(RobotRun& r);
  // Pictures the robot that detected the run's first overlap deadlock (first_deadlock_).
  void PictureDeadlock(const RobotRun& r, double t);
  void SenseRobots(const sim::TickSnapshot& next, double t_after);
  void MergeRobot(std::size_t k, const sim::TickSnapshot& next, double t_after);
  void RecordCycle(RobotRun& r, const nav::EstimatorCycle& cycle, const core::Pose2& truth,
                   double t_after);
  void RecordTrajectories(double t, bool bodies, bool robots);
  // outputs.scan_log: auto: closes scans.bin once its robot-minutes are logged.
  void LimitScanLog(double t_after);
  bool RoutesDone() const;
  // Whether a robot's base left the floor's rectangle after the step ending
  // at t_after (it falls: the world has no floor there); records it.
  bool RobotLeftFloor(double t_after);
  void BuildCollisionClasses();
  RunMetrics CollectMetrics(double sim_s) const;

  const Scenario& scenario_;
  const RunOptions& options_;
  const RunExtensions& extensions_;
  std::filesystem::path out_;
  Clock::time_point t_start_;
  std::unique_ptr<sim::World> world_;
  RealWorldChanges real_world_;  // what `realism: realistic` added to the surveyed world
  std::vector<std::unique_ptr<sim::BodyMotion>> motions_;
  std::vector<sim::PlanarVelocity> body_commands_;  // this tick's, by body
  std::unique_ptr<sim::PlanarCaster> planar_;
  std::map<std::string, int> body_index_;
  std::map<std::string, int> robot_index_;  // world robot index by id
  std::vector<RobotRun> robots_;
  std::vector<TickWork> work_;
  std::unique_ptr<sim::WorkerPool> pool_;
  std::unique_ptr<SnapshotTaker> snapshots_;  // the scenario's `snapshots:`, if any
  // Issue 15: the fleet's coordinator (scenario `fleet:`), merged at the end
  // of each tick; none with coordination off or fewer than two mission robots.
  std::unique_ptr<nav::FleetCoordinator> fleet_;
  // Runs with two or more mission robots: their true hulls' distances.
  std::optional<RobotProximity> proximity_;
  std::vector<RobotProximity::NearMiss> near_misses_;               // scratch: one tick's
  std::vector<RobotProximity::StationConflict> station_conflicts_;  // scratch: one tick's
  std::vector<std::string> watched_stations_;  // node ids of the proximity's stations
  std::vector<core::Pose2> robot_poses_;       // scratch: one tick's true poses
  void RecordProximity(double t_after);
  // Body (robot) index of each world element, -1 for others.
  std::vector<int> body_of_element_;
  std::vector<int> robot_of_element_;
  std::vector<int> person_of_element_;   // the crowd's people, -1 for other elements
  std::vector<std::string> person_ids_;  // by person
  std::vector<BodyMetrics> body_tally_;
  std::unique_ptr<CollisionClassifier> collision_classes_;
  std::vector<bool> visitor_body_;                // random walkers: the crowd's stand-ins
  std::vector<double> walker_paused_until_s_;     // by body: stands until then after a contact
  std::vector<double> robot_radius_m_;            // by robot: its footprint\'s bounding circle
  std::vector<nav::NavigationEvent> nav_events_;  // scratch
  std::vector<StrideBuffer<Eigen::Vector2d>> body_tracks_;
  std::optional<CrowdTracker> crowd_tracker_;        // runs with a crowd
  std::optional<CrowdStrip> crowd_strip_;            // frames of the crowd around the first robot
  std::optional<DeadlockFrame> first_deadlock_;      // the run's first overlap deadlock, pictured
  std::optional<SeriesDecimator> visitors_present_;  // the report's chart, runs with a crowd
  std::unique_ptr<EventLog> events_;
  std::optional<EventExpectationMonitor> expect_monitor_;  // scenarios with `expect:`
  std::unique_ptr<EventStreams> event_streams_;
  std::vector<const ScenarioEvent*> ongoing_events_;  // processes started, in timeline order
  std::vector<double> robot_step_m_;  // by world robot index: true distance of the last step
  std::vector<KidnapNote> kidnaps_;   // scratch: this tick's
  std::unique_ptr<TrajectoryLog> trajectories_;
  std::unique_ptr<LocalizationLog> localization_log_;
  std::unique_ptr<ScanLogWriter> scan_log_;
  // The state after the last step: read by the tick's per-robot work, the
  // distance sums and the trajectory rows (one snapshot per tick).
  sim::TickSnapshot snapshot_;
  std::size_t next_event_ = 0;
  std::int64_t ticks_run_ = 0;
  RunSummary summary_;
};

}  // namespace pavilion::scenarios::detail
