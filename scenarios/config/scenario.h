#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "nav/control/drive_profile.h"
#include "nav/control/path_follower.h"
#include "nav/control/wander_controller.h"
#include "nav/fleet/coordinator.h"
#include "nav/mission/navigation_controller.h"
#include "scenarios/config/realism.h"
#include "scenarios/config/run_reference.h"
#include "scenarios/config/snapshot_options.h"
#include "scenarios/events/event.h"
#include "scenarios/expect/expectation.h"
#include "sim/bodies/body_motion.h"
#include "sim/raycast/planar_caster.h"
#include "sim/robot/robot_config.h"
#include "sim/world/world.h"
#include "sim/world/world_description.h"

namespace pavilion::scenarios {

// How a body moves: not at all by itself, a scripted profile, or a random walk.
struct MotionSpec {
  enum class Type { kNone, kScripted, kRandomWalk } type = Type::kNone;
  sim::ScriptedMotionOptions scripted;
  sim::RandomWalkOptions random_walk;
};

// A body of the scenario; groups are expanded into bodies at load time with
// positions drawn later from the run's seeded stream.
struct BodyEntry {
  sim::BodySpec spec;
  MotionSpec motion;
  std::string spawn_area;  // place name (or key path of an inline polygon)
  std::optional<core::Polygon2> spawn_polygon;
};

// One step of a robot's scripted drive: wheel speeds held from `at_s` until
// the next step (rad/s, positive forward).
using DriveCommand = nav::DriveStep;

// A robot's EKF pose tracking (thesis §4.4): the map it is given, how often it
// localizes and where its estimate starts.
struct LocalizationEntry {
  bool enabled = false;
  std::string map_file;  // the robot's map.yaml (default: the world's)
  // `map: derive`: instead of a file, the map is derived from the world at
  // start-up (pavilion map derive) with tape-measure noise of this sigma drawn
  // from the scenario's seed: a fresh survey per seed, so that runs over
  // several seeds sample the map's error as well (consistency checks, NEES).
  // Key map_noise_m, m, [0, 0.1].
  std::optional<double> derive_map_noise_m;
  // Localization cycles per second: each laser's scans are integrated at most
  // this often (the thesis: 2 Hz, §4.5.2). Hz, [0.01, 1000].
  double rate_hz = 2.0;
  // The estimate starts at the true start pose plus `initial_offset` (x, y in
  // the world frame, theta), with standard deviations `initial_sigma`.
  core::Pose2 initial_offset;
  Eigen::Vector3d initial_sigma{0.01, 0.01, 0.0175};  // m, m, rad; each finite and > 0
  double significance = 0.95;  // of the validation gate (eq. 4.16), [0.5, 0.999999]
  // The extracted lines' covariance floor (core::LineExtractionOptions'
  // r_sigma_floor_m, alpha_sigma_floor_rad; §2.2.1.3 correlated error): the
  // filter's answer to errors that repeat from scan to scan. Unset: the laser
  // preset's (LMS 200: 1 mm, 0.02°). Keys line_floor_r_m, m, [0, 0.1], and
  // line_floor_alpha_deg, [0, 5] deg.
  std::optional<double> line_floor_r_m;
  std::optional<double> line_floor_alpha_rad;
  std::vector<std::string> lasers;  // lasers that feed it; empty: all
  // Cameras whose vertical edges it integrates after the lasers' lines (§4.4,
  // issue 19); empty: none. Only these cameras render (cameras are off
  // unless a scenario asks for them).
  std::vector<std::string> cameras;
  // Scans and images wait this long and are then integrated in time-stamp
  // order (nav::EkfPoseEstimatorOptions::hold_s): a camera's images arrive
  // its grabber's delay late. Key hold_ms; unset: 100 ms with cameras, 0
  // without. s, [0, 1].
  std::optional<double> hold_s;
  // The filter's wheel-space noise (k_L, k_R, k_turn of §2.3) is this many
  // times the calibrated plus injected one: its answer to slip it has no
  // term for (`realism: realistic`'s acceleration slip and carpet). Key
  // odometry_k_scale, [1, 1000].
  double odometry_k_scale = 1.0;
  // A cycle that pairs nothing is matched again with the pose's uncertainty
  // grown by these standard deviations (core::LocalizerOptions::
  // slip_covariance): the filter's answer to a slip or shove the bumpers did
  // not feel (thesis §4.6). 3 cm and 1° admit, within the gate's 2.45σ,
  // the slips the simulated robots show in quick turn reversals (0.6-0.8°
  // for Pygmalion, 1-3° for Robox after fast turns) and keep a kidnap's
  // metres out. Key slip_sigma: [x, y, theta] (m, m, rad), each in
  // [0, 0.5]; [0, 0, 0]: the thesis' single match.
  Eigen::Vector3d slip_sigma{0.03, 0.03, 0.0175};
  // `method: global`: global localization (thesis chapter 5, Fig. 5.17) —
  // lost is not final, the robot relocalizes itself; `ekf` (default): the
  // chapter-4 pose tracking alone.
  bool global = false;
  // `initial: unknown`: the robot does not know where it starts (global only).
  bool initial_unknown = false;
  // `shadow: mcl`: Monte Carlo localization runs beside it on the same
  // readings, never driving the robot (the baseline of issue 18).
  bool shadow_mcl = false;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// A tour through the stops of the robot's map topology, driven by the path
// follower from the robot's estimate (localization, or odometry without it).
struct RouteEntry {
  std::vector<std::string> stops;  // node ids of the map
  double start_s = 0.0;            // s, [0, 1e7]
  nav::PathFollowerOptions follower;
  double control_rate_hz = 20.0;  // path follower updates per second, Hz, [0.1, 1000]

  // start_s and control_rate_hz (the follower validates its own).
  void Validate() const;  // throws std::invalid_argument naming the field
};

// An obstacle-avoiding random walk reacting to each scan of one of the robot's
// lasers: the hall benchmark's "wander" (nav/control/wander_controller.h). Its draws
// come from the stream (scenario seed, "<robot id>/wander").
struct WanderEntry {
  std::string laser;  // a laser id of the robot model
  nav::WanderOptions options;
};

// The chapter 6 navigation's goals and options (`mission:`, issue 14): a list
// of stations, or a tour of `tour_stations` per round drawn from the seed
// among `tour_among` (the map's station nodes by default).
struct MissionEntry {
  std::vector<std::string> stations;
  std::optional<int> tour_stations;
  bool tour_repeat = false;
  std::vector<std::string> tour_among;
  // dwell_s, timeout_s, rates, planners; the run fills in the physics step,
  // the odometry model and the seed.
  nav::NavigationControllerOptions navigation;
};

// A robot of the scenario: its model (robots/<name>/robot.yaml), start pose,
// and at most one of a scripted wheel-speed profile, a route, a mission or a wander.
struct RobotEntry {
  std::string id;
  std::string model;  // as written in the scenario
  sim::RobotConfig config;
  core::Pose2 pose;
  std::vector<DriveCommand> drive;  // sorted by time
  // How its wheels meet the floor: the entry's `wheel_model`, else the
  // scenario's `physics.wheel_model`.
  sim::WheelModel wheel_model = sim::WheelModel::kArticulated;
  LocalizationEntry localization;
  // Every camera of its model; config.cameras keeps only those the scenario
  // turned on (LocalizationEntry::cameras). Snapshots may use any level one.
  std::vector<sim::CameraMount> model_cameras;
  std::optional<RouteEntry> route;
  std::optional<MissionEntry> mission;
  std::optional<WanderEntry> wander;
};

// scans.bin: off, every scan, or (auto, the default) every scan until the run
// has logged `scan_log_robot_minutes` robot-minutes, then no more (an event
// `scan_log_stopped` says so): about 18 MB per robot-minute, so a 12 h
// ten-robot day would otherwise write 130 GB.
enum class ScanLogMode { kOff, kOn, kAuto };

// The defaults keep a 12 h ten-robot day among ~100 visitors under 1 GB of
// outputs (docs/benchmarks.md, "Outputs that scale"); scenarios that want
// finer rows ask for them.
struct OutputOptions {
  double trajectory_rate_hz = 2.0;  // rows of trajectories.csv per robot per s, Hz, [1e-3, 1e4]
  // Rows per scripted or walking body per s, Hz, [1e-3, 1e4]; a scenario
  // that does not set it gets its trajectory_rate_hz.
  double body_rate_hz = 2.0;
  double section_height_m = 0.5;              // height of the top-down picture's cut, m, [0, 100]
  int image_width_px = 900;                   // top-down picture width, px, [100, 8000]
  ScanLogMode scan_log = ScanLogMode::kAuto;  // scans.bin (the robots' scans with ground truth)
  double scan_log_robot_minutes = 10.0;       // auto's budget, robot-min, [0, 1e6]
  // Rows of trajectories.csv per present crowd visitor per s (people are many:
  // a lower rate than the robots'), Hz, [0, 1e4]; 0 leaves people out.
  double people_rate_hz = 1.0;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// Who finds the laser rays' hits: the planar caster (sim/raycast/planar_caster.h; falls
// back to Bullet for tilted beam planes) or Bullet for every ray (the reference).
enum class LaserBackend { kPlanar, kBullet };
const char* ToString(LaserBackend backend);

// A fully loaded, validated scenario.
// The scenario's `fleet:` block (issue 15, thesis §6.3.5): multi-robot
// planning through a coordinator shared by the robots with missions.
struct FleetEntry {
  // `coordination: on | off`. Off: no coordinator — each robot plans alone
  // and sees the others only through their markers (§6.3.5.1), as on the
  // days Expo.02's server was down (§6.5). A coordinator runs only with at
  // least two mission robots.
  bool coordination = true;
  // `deadlock_resolution: on | off`: the robots resolve overlap deadlocks
  // (nav/fleet/deadlock_monitor.h); off, they are only detected.
  bool deadlock_resolution = true;
  nav::FleetOptions options;
};

struct Scenario {
  std::string name;
  std::string description;
  std::string source_file;
  std::uint64_t seed = 1;
  double duration_s = 60.0;
  // End the run early once every robot with a route or a mission list has finished it.
  bool end_when_routes_done = false;
  std::string world_file;  // the world.yaml (its folder holds the default map.yaml)
  sim::WorldOptions physics;
  LaserBackend laser_backend = LaserBackend::kPlanar;  // key laser_backend
  sim::PlanarCasterOptions planar_laser;               // laser_max_tilt_deg
  // physics.wheel_model: the robots' wheel model unless an entry names its own.
  sim::WheelModel wheel_model = sim::WheelModel::kArticulated;
  sim::WorldDescription world;
  std::vector<BodyEntry> bodies;
  std::vector<RobotEntry> robots;
  // The scenario's `crowd:` block: visitors of sim/crowd/, with the world's
  // places resolved (entrance, exit, roam area, attractions).
  std::optional<sim::CrowdSpec> crowd;
  std::vector<TimedEvent> events;  // sorted by time, stable
  // `expect:`: what the run must show to pass (scenarios/expect/expectation.h).
  std::vector<Expectation> expectations;
  // What loading changed that a user should hear of (events skipped by a
  // shorter --duration), one line each; the command line prints them.
  std::vector<std::string> notes;
  OutputOptions outputs;
  FleetEntry fleet;
  // `realism: ideal | realistic` (scenarios/config/realism.h): the robots'
  // draws are applied at load time; the world's (clutter, doors, the survey's
  // wall offsets) when the run builds its world.
  RealismProfile realism;
  // `snapshots:`: camera and overview pictures at times and events (issue 19).
  SnapshotOptions snapshots;
  // `reference:`: a real run's figures the report sets beside this run's (issue 21).
  RunReference reference;
};

// Command-line adjustments applied before validation.
struct ScenarioOverrides {
  std::optional<std::uint64_t> seed;
  std::optional<double> duration_s;
  std::vector<std::string> assignments;  // "key.path=value"
};

// Reads and validates a scenario file and the world it names. Throws InputError
// listing every problem (file:line: key.path: message).
Scenario LoadScenarioFile(const std::string& path, const ScenarioOverrides& overrides = {});

}  // namespace pavilion::scenarios
