#include "scenarios/run/robot_stack.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <string>

#include "core/geometry/segment2.h"
#include "core/random/random_stream.h"
#include "nav/control/drive_profile.h"
#include "nav/control/route_controller.h"
#include "nav/control/wander_scan_controller.h"
#include "nav/local/scan_obstacles.h"
#include "nav/mission/navigation_controller.h"
#include "nav/reactive/swept_polygon.h"
#include "nav/route/route_planner.h"
#include "nav/stack/ekf_pose_estimator.h"
#include "nav/stack/global_pose_estimator.h"
#include "nav/stack/mcl_pose_estimator.h"
#include "scenarios/config/input_error.h"
#include "scenarios/maps/closed_doors.h"
#include "scenarios/maps/map_derivation.h"
#include "scenarios/maps/map_file.h"

namespace pavilion::scenarios {
namespace {

core::LocalizerOptions LocalizerOptionsFor(const RobotEntry& robot) {
  core::LocalizerOptions o;
  o.odometry = robot.config.odometry;
  // The calibration measured the physics' own error with encoder noise off;
  // injected encoder noise is independent of it, so the variances add (§2.3:
  // Var = k|s| per wheel, hence the k add).
  const sim::EncoderOptions& encoders = robot.config.encoders;
  if (encoders.noise) {
    o.odometry.k_left_m += encoders.k_left_m;
    o.odometry.k_right_m += encoders.k_right_m;
    o.odometry.k_turn_m += encoders.k_turn_m;  // acceleration slip has no term: unmodelled
  }
  // The filter's answer to slip it has no term for (acceleration slip,
  // carpet): its wheel-space noise scaled up (issue 19, office_tour_vision).
  const double k_scale = robot.localization.odometry_k_scale;
  o.odometry.k_left_m *= k_scale;
  o.odometry.k_right_m *= k_scale;
  o.odometry.k_turn_m *= k_scale;
  o.significance = robot.localization.significance;
  const Eigen::Vector3d slip_var =
      robot.localization.slip_sigma.cwiseProduct(robot.localization.slip_sigma);
  o.slip_covariance = slip_var.asDiagonal();
  for (const sim::LaserMount& mount : robot.config.lasers) {
    core::LaserSensorOptions laser;
    laser.id = mount.id;
    if (robot.localization.line_floor_r_m) {
      laser.lines.r_sigma_floor_m = *robot.localization.line_floor_r_m;
    }
    if (robot.localization.line_floor_alpha_rad) {
      laser.lines.alpha_sigma_floor_rad = *robot.localization.line_floor_alpha_rad;
    }
    o.lasers.push_back(laser);
  }
  // The cameras the scenario turned on (only those left in the config): the
  // software's calibration is the lens' true model (§2.4), its noise known.
  for (const sim::CameraMount& mount : robot.config.cameras) {
    core::CameraSensorOptions camera;
    camera.id = mount.id;
    camera.intrinsics = mount.Intrinsics();
    camera.robot_from_sensor = mount.mount.pose;
    camera.edges.image_noise_sigma_grey = mount.noise_grey;
    camera.edges.calibration_sigma_px = mount.calibration_sigma_px;
    o.cameras.push_back(camera);
  }
  return o;
}

std::vector<std::string> EstimatorLasers(const RobotEntry& robot) {
  const LocalizationEntry& entry = robot.localization;
  std::vector<std::string> lasers;
  for (const sim::LaserMount& mount : robot.config.lasers) {
    if (entry.lasers.empty() ||
        std::find(entry.lasers.begin(), entry.lasers.end(), mount.id) != entry.lasers.end()) {
      lasers.push_back(mount.id);
    }
  }
  return lasers;
}

// The estimate's start: the true start pose plus the entry's offset.
core::PoseWithCovariance InitialEstimate(const RobotEntry& robot) {
  const LocalizationEntry& entry = robot.localization;
  const Eigen::Vector3d var = entry.initial_sigma.cwiseProduct(entry.initial_sigma);
  return {{robot.pose.x_m + entry.initial_offset.x_m, robot.pose.y_m + entry.initial_offset.y_m,
           core::NormalizeAngle(robot.pose.theta_rad + entry.initial_offset.theta_rad)},
          var.asDiagonal().toDenseMatrix()};
}

// Global localization's defaults for a simulated robot (issue 18): the
// chapter-4 EKF's lost detection made quicker — six failed cycles (1.5 s with
// two lasers at 2 Hz) instead of twenty — since a loss is no longer final but
// starts a new generation.
constexpr int kGlobalLostFailedCycles = 6;

// With a camera, scans and images wait for each other this long (s): longer
// than a grabber's delay (Pygmalion's: 40 ms) plus a sweep.
constexpr double kCameraHoldS = 0.1;

std::unique_ptr<nav::PoseEstimator> MakeEstimator(const RobotEntry& robot, core::RobotMap map) {
  const LocalizationEntry& entry = robot.localization;
  if (entry.global) {
    nav::GlobalPoseEstimatorOptions options;
    options.localizer.tracking = LocalizerOptionsFor(robot);
    options.localizer.tracking.lost_failed_cycles = kGlobalLostFailedCycles;
    options.localizer.tree.significance = entry.significance;
    options.rate_hz = entry.rate_hz;
    options.lasers = EstimatorLasers(robot);
    if (!entry.initial_unknown) options.initial = InitialEstimate(robot);
    return std::make_unique<nav::GlobalPoseEstimator>(std::move(map), options);
  }
  nav::EkfPoseEstimatorOptions options;
  options.localizer = LocalizerOptionsFor(robot);
  options.rate_hz = entry.rate_hz;
  options.lasers = EstimatorLasers(robot);
  options.hold_s = entry.hold_s.value_or(entry.cameras.empty() ? 0.0 : kCameraHoldS);
  const core::PoseWithCovariance initial = InitialEstimate(robot);
  options.initial_pose = initial.pose;
  options.initial_covariance = initial.covariance;
  return std::make_unique<nav::EkfPoseEstimator>(std::move(map), options);
}

// The hall benchmark's wander on `laser`, its draws from "<robot id>/wander".
std::unique_ptr<nav::WanderScanController> MakeWander(const Scenario& scenario,
                                                      const RobotEntry& entry,
                                                      const std::string& laser,
                                                      const nav::WanderOptions& options) {
  nav::WanderController wander(
      options, core::RandomStream(scenario.seed,
                                  core::RandomStream::StreamId((entry.id + "/wander").c_str())));
  return std::make_unique<nav::WanderScanController>(std::move(wander), laser,
                                                     entry.config.odometry);
}

// Monte Carlo localization in shadow (issue 18's baseline): the same lasers,
// the same start knowledge, its draws from "<robot id>/mcl".
std::unique_ptr<nav::PoseEstimator> MakeShadowMcl(const Scenario& scenario, const RobotEntry& robot,
                                                  core::RobotMap map) {
  nav::MclPoseEstimatorOptions options;
  options.mcl.seed = scenario.seed;
  options.mcl.stream_id = core::RandomStream::StreamId((robot.id + "/mcl").c_str());
  options.lasers = EstimatorLasers(robot);
  options.global_start = robot.localization.initial_unknown;
  const core::PoseWithCovariance initial = InitialEstimate(robot);
  options.initial_pose = initial.pose;
  options.initial_covariance = initial.covariance;
  return std::make_unique<nav::MclPoseEstimator>(std::move(map),
                                                 LocalizerOptionsFor(robot).odometry, options);
}

// The path of a robot's route over its map's topology, from its start pose.
std::vector<Eigen::Vector2d> RoutePath(const Scenario& scenario, std::size_t index,
                                       const core::RobotMap& map) {
  const RobotEntry& entry = scenario.robots[index];
  const std::string key = "robots[" + std::to_string(index) + "].route.stops";
  try {
    std::vector<Eigen::Vector2d> path = nav::TourPath(map, entry.route->stops);
    path.insert(path.begin(), entry.pose.translation());
    return path;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(Diagnostic{scenario.source_file, 0, key, e.what()});
  }
}

// The circle the local planner plans for (§6.3.4: "the robot is assumed to
// be circular"): midway between the footprint's inscribed and circumscribed
// circles about the robot's origin. The circumscribed circle alone would call
// a square robot standing 5 cm from a wall trapped; the dynamic window checks
// the true polygon anyway.
double PlanningRadius(const std::vector<Eigen::Vector2d>& footprint) {
  double outer = 0.0;
  double inner = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < footprint.size(); ++i) {
    const Eigen::Vector2d& a = footprint[i];
    const Eigen::Vector2d& b = footprint[(i + 1) % footprint.size()];
    outer = std::max(outer, a.norm());
    inner = std::min(inner, core::PointSegmentDistance(Eigen::Vector2d::Zero(), a, b));
  }
  return 0.5 * (inner + outer);
}

// The chapter 6 navigation of a `mission:` robot: its options completed from
// the robot (shape, wheels, calibrated odometry), the physics step and the seed.
std::unique_ptr<nav::Controller> MakeNavigationController(const Scenario& scenario,
                                                          std::size_t index, core::RobotMap map,
                                                          nav::FleetLink fleet) {
  const RobotEntry& entry = scenario.robots[index];
  const MissionEntry& mission = *entry.mission;
  const sim::RobotDescription& robot = entry.config.description;
  nav::NavigationControllerOptions o = mission.navigation;
  o.step_s = 1.0 / scenario.physics.physics_rate_hz;
  o.odometry = entry.config.odometry;
  o.seed = core::RandomStream(scenario.seed,
                              core::RandomStream::StreamId((entry.id + "/planner").c_str()))
               .NextU64();
  // The polygon that must clear obstacles: chassis, wheels and casters.
  const std::vector<Eigen::Vector2d> outline = robot.OutlineWithWheels();
  const double radius_m = PlanningRadius(outline);
  for (const sim::BumperZone& z : entry.config.bumpers) {
    o.bumper_zones_rad.emplace_back(z.from_rad, z.to_rad);
  }
  o.local.grid.robot_radius_m = radius_m;
  o.local.band.robot_radius_m = radius_m;
  o.dwa.wheelbase_m = entry.config.odometry.wheelbase_m;
  const double wheel_radius_m = std::min(entry.config.odometry.left_wheel_radius_m,
                                         entry.config.odometry.right_wheel_radius_m);
  // The window stays within the motors' limits (never above the options' own).
  o.dwa.max_wheel_speed_mps =
      std::min(o.dwa.max_wheel_speed_mps, robot.max_wheel_speed_radps * wheel_radius_m);
  o.dwa.max_wheel_accel_mps2 =
      std::min(o.dwa.max_wheel_accel_mps2, robot.max_wheel_accel_radps2 * wheel_radius_m);
  o.dwa.max_speed_mps = std::min(o.dwa.max_speed_mps, o.dwa.max_wheel_speed_mps);
  // A fleet's robots see each other's markers (§6.3.5.1) and resolve overlap
  // deadlocks unless the scenario turns that off (issue 15).
  const auto missions = std::count_if(scenario.robots.begin(), scenario.robots.end(),
                                      [](const RobotEntry& r) { return r.mission.has_value(); });
  o.see_robots = missions >= 2;
  o.deadlock.resolve = scenario.fleet.deadlock_resolution;
  // A robot with global localization drives by its senses while it is not
  // localized, so that new views let it find its location (issue 18).
  o.explore_when_lost = entry.localization.enabled && entry.localization.global;
  RemoveEdgesThroughClosedDoors(scenario.world.doors, &map);
  std::vector<std::string> among = mission.tour_among;
  if (among.empty()) {  // a derived map: every station node it has
    for (const core::MapNode& n : map.nodes) {
      if (n.station) among.push_back(n.id);
    }
  }
  nav::MissionSequence sequence =
      mission.tour_stations
          ? nav::MissionSequence::Tour(
                among, *mission.tour_stations, mission.tour_repeat,
                core::RandomStream(scenario.seed,
                                   core::RandomStream::StreamId((entry.id + "/tour").c_str())))
          : nav::MissionSequence::List(mission.stations);
  try {
    auto controller = std::make_unique<nav::NavigationController>(std::move(map), outline,
                                                                  std::move(sequence), o);
    controller->SetFleet(fleet);
    return controller;
  } catch (const std::invalid_argument& e) {
    throw InputError(Diagnostic{scenario.source_file, 0,
                                "robots[" + std::to_string(index) + "].mission", e.what()});
  }
}

std::unique_ptr<nav::Controller> MakeController(const Scenario& scenario, std::size_t index,
                                                const std::optional<core::RobotMap>& map,
                                                nav::FleetLink fleet) {
  const RobotEntry& entry = scenario.robots[index];
  const core::EncoderOdometryOptions& odometry = entry.config.odometry;
  if (entry.route) {
    nav::RouteControllerOptions options;
    options.follower = entry.route->follower;
    options.start_s = entry.route->start_s;
    options.period_ticks = std::max<std::int64_t>(
        1, std::llround(scenario.physics.physics_rate_hz / entry.route->control_rate_hz));
    options.step_s = 1.0 / scenario.physics.physics_rate_hz;
    options.odometry = odometry;
    return std::make_unique<nav::RouteController>(RoutePath(scenario, index, *map), options);
  }
  if (entry.mission) return MakeNavigationController(scenario, index, *map, fleet);
  if (entry.wander) return MakeWander(scenario, entry, entry.wander->laser, entry.wander->options);
  if (!entry.drive.empty()) return std::make_unique<nav::DriveProfileController>(entry.drive);
  return nullptr;
}

}  // namespace

bool NeedsMap(const RobotEntry& robot) {
  return robot.localization.enabled || robot.route.has_value() || robot.mission.has_value();
}

core::RobotMap LoadRobotMap(const RobotEntry& robot, const Scenario& scenario,
                            const sim::World& world) {
  const LocalizationEntry& entry = robot.localization;
  try {
    if (entry.derive_map_noise_m) {
      MapDerivationOptions options;
      options.noise_sigma_m = *entry.derive_map_noise_m;
      if (scenario.realism.realistic) {
        options.wall_offset_sigma_m = scenario.realism.wall_offset_sigma_m;
      }
      options.seed = scenario.seed;
      options.vertical_edges = !entry.cameras.empty();  // the camera's features (§4.2)
      return DeriveRobotMap(world, options);
    }
    std::string file = entry.map_file;
    if (file.empty()) {
      file = (std::filesystem::path(scenario.world_file).parent_path() / "map.yaml").string();
    }
    return LoadMapFile(file);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(
        Diagnostic{scenario.source_file, 0, "robots." + robot.id + ".localization.map", e.what()});
  }
}

std::unique_ptr<nav::Navigator> MakeNavigator(const Scenario& scenario, std::size_t index,
                                              const std::optional<core::RobotMap>& map,
                                              nav::FleetLink fleet) {
  const RobotEntry& entry = scenario.robots[index];
  nav::NavigatorOptions options;
  options.odometry = entry.config.odometry;
  options.start_pose = entry.pose;
  std::unique_ptr<nav::PoseEstimator> estimator;
  if (entry.localization.enabled) estimator = MakeEstimator(entry, *map);
  auto navigator = std::make_unique<nav::Navigator>(options, std::move(estimator),
                                                    MakeController(scenario, index, map, fleet));
  if (entry.localization.enabled && entry.localization.shadow_mcl) {
    navigator->SetShadowEstimator(MakeShadowMcl(scenario, entry, *map));
  }
  return navigator;
}

}  // namespace pavilion::scenarios
