#include "scenarios/run/scenario_runner.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <numbers>

#include "core/odometry/diff_drive.h"
#include "core/random/random_stream.h"
#include "nav/control/path_follower.h"
#include "nav/control/wander_controller.h"
#include "nav/route/route_planner.h"
#include "scenarios/config/input_error.h"
#include "scenarios/config/robot_setup.h"
#include "scenarios/maps/map_file.h"
#include "scenarios/output/localization_plot.h"
#include "scenarios/output/output_files.h"
#include "scenarios/output/png.h"
#include "scenarios/output/report.h"
#include "scenarios/output/scan_log.h"
#include "scenarios/run/localization_run.h"
#include "scenarios/version.h"
#include "sim/render/top_down_view.h"
#include "sim/robot/sim_robot.h"
#include "sim/runtime/schedule.h"
#include "sim/runtime/worker_pool.h"

namespace pavilion::scenarios {
namespace {

using Json = nlohmann::ordered_json;
using Clock = std::chrono::steady_clock;

// Free space kept between a spawned body and anything else (m).
constexpr double kSpawnClearanceM = 0.05;
constexpr int kSpawnAttempts = 2000;
// Heights at which spawn clearance is checked, besides the body's mid-height (m).
constexpr double kSpawnCheckLowM = 0.05;
// Stream ids that are not bodies.
constexpr std::uint64_t kSpawnStream = 0x5350415749ULL;  // "SPAWN"
// Wall seconds between progress line updates.
constexpr double kProgressPeriodS = 0.25;

double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

// CPU seconds this process has used: beside wall time, a figure that holds on a
// machine shared with other work (the run itself is single-threaded).
double ProcessCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

std::string Fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v == 0.0 ? 0.0 : v);  // no "-0.000"
  return buf;
}

// One CSV row built field by field (GCC 12 warns falsely, -Wrestrict, on long
// chains of string `+`).
class CsvRow {
 public:
  CsvRow& Add(const std::string& field) {
    if (!row_.empty() || fields_ > 0) row_ += ',';
    row_ += field;
    ++fields_;
    return *this;
  }
  CsvRow& Add(double value, int decimals) { return Add(Fixed(value, decimals)); }
  CsvRow& Add(std::int64_t value) { return Add(std::to_string(value)); }
  CsvRow& Empty(int count) {
    for (int k = 0; k < count; ++k) Add(std::string());
    return *this;
  }
  // The six distinct entries of a 3x3 covariance, %.6e.
  CsvRow& Covariance(const Eigen::Matrix3d& c) {
    for (const auto& [i, j] : {std::pair{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}}) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.6e", c(i, j));
      Add(std::string(buf));
    }
    return *this;
  }
  const std::string& str() const { return row_; }

 private:
  std::string row_;
  int fields_ = 0;
};

double FootprintRadius(const sim::BodyShape& s) {
  if (s.type == sim::BodyShapeType::kBox) return 0.5 * s.box_size_m.head<2>().norm();
  return s.radius_m;
}

double PointSegmentDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                            const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / std::max(ab.squaredNorm(), 1e-18), 0.0, 1.0);
  return (a + t * ab - p).norm();
}

bool Clear(const core::PlanarSection& section, const Eigen::Vector2d& p, double r) {
  for (const auto& s : section.segments) {
    if (PointSegmentDistance(p, s.a_m, s.b_m) < r) return false;
  }
  for (const auto& c : section.circles) {
    if ((c.center_m - p).norm() < r + c.radius_m) return false;
  }
  return true;
}

// Draws a pose inside the body's spawn area that is clear of the world and of
// the bodies placed before it.
core::Pose2 DrawSpawnPose(const sim::World& world, const BodyEntry& entry,
                          const std::string& scenario_file, core::RandomStream* stream) {
  const core::Polygon2& area = *entry.spawn_polygon;
  Eigen::Vector2d lo = area.front(), hi = area.front();
  for (const auto& p : area) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double r = FootprintRadius(entry.spec.shape) + kSpawnClearanceM;
  const double h = 2.0 * entry.spec.shape.HalfHeight();
  const core::PlanarSection low = world.SectionAt(std::min(kSpawnCheckLowM, 0.5 * h));
  const core::PlanarSection mid = world.SectionAt(0.5 * h);
  std::vector<std::pair<Eigen::Vector2d, double>> others;
  for (int b = 0; b < world.body_count(); ++b) {
    others.emplace_back(world.body_state(b).pose.translation(),
                        FootprintRadius(world.body_spec(b).shape));
  }
  for (int attempt = 0; attempt < kSpawnAttempts; ++attempt) {
    const Eigen::Vector2d p(stream->Uniform(lo.x(), hi.x()), stream->Uniform(lo.y(), hi.y()));
    const double yaw = stream->Uniform(-std::numbers::pi, std::numbers::pi);
    if (!core::Contains(area, p) || !Clear(low, p, r) || !Clear(mid, p, r)) continue;
    bool free = true;
    for (const auto& [q, rq] : others) {
      if ((q - p).norm() < r + rq) {
        free = false;
        break;
      }
    }
    if (free) return {p.x(), p.y(), yaw};
  }
  throw InputError(Diagnostic{scenario_file, 0, "bodies",
                              "cannot place body '" + entry.spec.id + "' in area '" +
                                  entry.spawn_area + "' after " + std::to_string(kSpawnAttempts) +
                                  " tries: the area is too small or too crowded"});
}

std::unique_ptr<sim::BodyMotion> MakeMotion(const BodyEntry& entry, std::uint64_t seed) {
  switch (entry.motion.type) {
    case MotionSpec::Type::kScripted:
      return std::make_unique<sim::ScriptedMotion>(entry.motion.scripted);
    case MotionSpec::Type::kRandomWalk: {
      sim::RandomWalkOptions options = entry.motion.random_walk;
      options.roam_area = entry.spawn_polygon;  // walkers stay where they were spawned
      return std::make_unique<sim::RandomWalkMotion>(
          options, core::RandomStream(seed, core::RandomStream::StreamId(entry.spec.id.c_str())));
    }
    case MotionSpec::Type::kNone:
      break;
  }
  return nullptr;
}

// Dead reckoning from encoder counts with the robot's calibrated odometry
// (what the localization will integrate, eqs. 2.6–2.8).
class EncoderOdometry {
 public:
  EncoderOdometry(const sim::OdometryCalibration& calibration, const core::Pose2& start)
      : calibration_(calibration), pose_(start) {}
  void Update(const core::EncoderReading& r) {
    if (started_) {
      const double per_tick = 2.0 * std::numbers::pi / r.ticks_per_revolution;
      const core::WheelTravel travel{
          static_cast<double>(r.left_ticks - left_) * per_tick * calibration_.left_wheel_radius_m,
          static_cast<double>(r.right_ticks - right_) * per_tick *
              calibration_.right_wheel_radius_m};
      pose_ = core::DiffDriveStep(pose_, travel, calibration_.wheelbase_m);
    }
    started_ = true;
    left_ = r.left_ticks;
    right_ = r.right_ticks;
  }
  const core::Pose2& pose() const { return pose_; }
  // A kidnapped robot's odometry carries on from where it believed it was.

 private:
  sim::OdometryCalibration calibration_;
  core::Pose2 pose_;
  bool started_ = false;
  std::int64_t left_ = 0;
  std::int64_t right_ = 0;
};

// Per-robot state of a run.
struct RobotRun {
  RobotRun(std::unique_ptr<sim::SimRobot> r, const RobotEntry* e)
      : robot(std::move(r)), entry(e), odometry(e->config.odometry, e->pose) {}
  std::unique_ptr<sim::SimRobot> robot;
  const RobotEntry* entry = nullptr;
  EncoderOdometry odometry;
  std::size_t next_drive = 0;
  double distance_m = 0.0;
  std::int64_t collisions = 0;
  std::int64_t scans = 0;
  std::int64_t fallback_scans = 0;  // scans cast partly with Bullet (planar backend)
  std::int64_t bumper_presses = 0;
  std::vector<Eigen::Vector2d> track;
  std::vector<Eigen::Vector2d> odometry_track;
  std::vector<Eigen::Vector2d> estimate_track;
  std::unique_ptr<LocalizationRun> localization;
  std::unique_ptr<nav::PathFollower> follower;
  std::unique_ptr<nav::WanderController> wander;  // reacts to each scan of entry->wander->laser
  std::int64_t control_period_ticks = 1;
  bool route_done = false;
  double route_done_s = 0.0;
};

// The path of a robot's route over its map's topology; errors name the
// scenario key.
std::vector<Eigen::Vector2d> RoutePath(const RobotEntry& entry, const core::RobotMap& map,
                                       const Scenario& scenario, std::size_t index) {
  const std::string key = "robots[" + std::to_string(index) + "].route.stops";
  try {
    std::vector<Eigen::Vector2d> path = nav::TourPath(map, entry.route->stops);
    // From the robot's start to the first stop.
    path.insert(path.begin(), entry.pose.translation());
    return path;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(Diagnostic{scenario.source_file, 0, key, e.what()});
  }
}

// Shows "sim 12.3/60.0 s  RTF 41.2x  ETA 1.2 s" on one updating line.
class ProgressLine {
 public:
  ProgressLine(bool enabled, double total_s) : enabled_(enabled), total_s_(total_s) {}
  void Update(double sim_s, double wall_s) {
    if (!enabled_ || wall_s - last_wall_s_ < kProgressPeriodS) return;
    last_wall_s_ = wall_s;
    const double rtf = wall_s > 0 ? sim_s / wall_s : 0.0;
    const double eta = rtf > 0 ? (total_s_ - sim_s) / rtf : 0.0;
    std::fprintf(stderr, "\r  sim %.1f/%.1f s  RTF %.1fx  ETA %.1f s   ", sim_s, total_s_, rtf,
                 eta);
    std::fflush(stderr);
  }
  void Done() {
    if (enabled_ && last_wall_s_ > 0.0) std::fprintf(stderr, "\r%60s\r", "");
  }

 private:
  bool enabled_;
  double total_s_;
  double last_wall_s_ = 0.0;
};

}  // namespace

RunSummary RunScenario(const Scenario& scenario, const RunOptions& options) {
  namespace fs = std::filesystem;
  const auto t_start = Clock::now();
  const fs::path out(options.out_dir);
  fs::create_directories(out);

  // Robots bring their own materials into the world description.
  sim::WorldDescription description = scenario.world;
  std::vector<sim::SimRobotSetup> robot_setups;
  for (const RobotEntry& r : scenario.robots) {
    robot_setups.push_back(MakeSimRobotSetup(r.id, r.config, r.pose, &description));
    robot_setups.back().spec.wheel_model = r.wheel_model;
  }
  sim::World world(std::move(description), scenario.physics);
  // Maps before any body enters the world (a derived map is a survey of the
  // static geometry).
  std::vector<std::optional<core::RobotMap>> robot_maps(scenario.robots.size());
  for (std::size_t k = 0; k < scenario.robots.size(); ++k) {
    const RobotEntry& entry = scenario.robots[k];
    if (entry.localization.enabled || entry.route) {
      robot_maps[k] = LoadRobotMap(entry, scenario, world);
    }
  }
  core::RandomStream spawn_stream(scenario.seed, kSpawnStream);
  std::vector<std::unique_ptr<sim::BodyMotion>> motions;
  for (const BodyEntry& entry : scenario.bodies) {
    sim::BodySpec spec = entry.spec;
    if (entry.spawn_polygon)
      spec.pose = DrawSpawnPose(world, entry, scenario.source_file, &spawn_stream);
    world.AddBody(spec);
    motions.push_back(MakeMotion(entry, scenario.seed));
  }
  // The planar laser caster, shared by every robot's scanners (one slice per
  // beam height); it reads the world after each step.
  std::unique_ptr<sim::PlanarCaster> planar;
  if (scenario.laser_backend == LaserBackend::kPlanar) {
    planar = std::make_unique<sim::PlanarCaster>(&world, scenario.planar_laser);
  }
  std::map<std::string, int> body_index;
  for (int b = 0; b < world.body_count(); ++b) body_index[world.body_spec(b).id] = b;
  std::vector<RobotRun> robots;
  std::map<std::string, int> robot_index;
  for (std::size_t k = 0; k < scenario.robots.size(); ++k) {
    const RobotEntry& entry = scenario.robots[k];
    try {
      auto robot = std::make_unique<sim::SimRobot>(&world, robot_setups[k], scenario.seed);
      robot->UsePlanarCaster(planar.get());
      robots.emplace_back(std::move(robot), &entry);
    } catch (const std::invalid_argument& e) {
      throw InputError(
          Diagnostic{scenario.source_file, 0, "robots[" + std::to_string(k) + "]", e.what()});
    }
    robot_index[entry.id] = static_cast<int>(k);
    RobotRun& run = robots.back();
    if (entry.localization.enabled) {
      run.localization = std::make_unique<LocalizationRun>(entry, *robot_maps[k]);
    }
    if (entry.route) {
      run.follower = std::make_unique<nav::PathFollower>(
          RoutePath(entry, *robot_maps[k], scenario, k), entry.route->follower);
      run.control_period_ticks = std::max<std::int64_t>(
          1, std::llround(scenario.physics.physics_rate_hz / entry.route->control_rate_hz));
    }
    if (entry.wander) {
      run.wander = std::make_unique<nav::WanderController>(
          entry.wander->options,
          core::RandomStream(scenario.seed,
                             core::RandomStream::StreamId((entry.id + "/wander").c_str())));
    }
  }

  const double dt = world.step_s();
  const auto total_ticks = static_cast<std::int64_t>(std::llround(scenario.duration_s / dt));
  sim::PeriodicSchedule schedule(scenario.physics.physics_rate_hz);
  const int trajectory_task =
      schedule.Add("outputs.trajectory_rate_hz", scenario.outputs.trajectory_rate_hz);

  LineWriter events(fs::path(out / "events.jsonl").string());
  LineWriter trajectories(fs::path(out / "trajectories.csv").string());
  trajectories.Append(
      "time_s,id,true_x_m,true_y_m,true_theta_rad,odom_x_m,odom_y_m,odom_theta_rad,est_x_m,est_y_"
      "m,est_theta_rad,cov_xx,cov_xy,cov_xtheta,cov_yy,cov_ytheta,cov_thetatheta");
  const bool any_localization = std::any_of(
      robots.begin(), robots.end(), [](const RobotRun& r) { return r.localization != nullptr; });
  std::unique_ptr<LineWriter> localization_log;
  if (any_localization) {
    localization_log = std::make_unique<LineWriter>((out / "localization.csv").string());
    localization_log->Append(
        "time_s,id,cycle,true_x_m,true_y_m,true_theta_rad,est_x_m,est_y_m,est_theta_rad,cov_xx,"
        "cov_xy,cov_xtheta,cov_yy,cov_ytheta,cov_thetatheta,position_error_m,heading_error_rad,"
        "nees,two_sigma_frontal_m,two_sigma_lateral_m,two_sigma_heading_rad,predictions,"
        "observations,matched_lines,matched_beacons,lost");
  }

  std::unique_ptr<ScanLogWriter> scan_log;
  if (scenario.outputs.scan_log && !robots.empty()) {
    std::vector<std::string> ids;
    for (const auto& e : world.elements()) ids.push_back(e.id);
    scan_log = std::make_unique<ScanLogWriter>((out / "scans.bin").string(), ids);
  }
  std::map<std::string, std::int64_t> event_counts;
  auto emit = [&](Json e) {
    ++event_counts[e["type"].get<std::string>()];
    events.Append(e.dump());
  };
  const auto& elements = world.elements();

  std::vector<sim::PlanarVelocity> commands(world.body_count());
  std::vector<double> distance_m(world.body_count(), 0.0);
  std::vector<std::int64_t> collisions(world.body_count(), 0);
  std::vector<std::vector<Eigen::Vector2d>> tracks(world.body_count());
  // Body index of each element, -1 for static elements.
  std::vector<int> body_of_element(elements.size(), -1);
  for (int b = 0; b < world.body_count(); ++b) body_of_element[world.body_element(b)] = b;
  // Robot index of each element, -1 for others (parts of a robot share its group).
  std::vector<int> robot_of_element(elements.size(), -1);
  for (std::size_t e = 0; e < elements.size(); ++e) {
    if (elements[e].group >= 0) robot_of_element[e] = elements[e].group;
  }
  // The state after the last step: read by this tick's per-body work, the
  // distance sums and the trajectory rows (one snapshot per tick).
  sim::TickSnapshot snapshot = world.Snapshot();
  auto record = [&](double t) {
    for (int b = 0; b < world.body_count(); ++b) {
      const core::Pose2& p = snapshot.bodies[b].pose;
      trajectories.Append(CsvRow()
                              .Add(t, 3)
                              .Add(world.body_spec(b).id)
                              .Add(p.x_m, 6)
                              .Add(p.y_m, 6)
                              .Add(p.theta_rad, 6)
                              .Empty(12)
                              .str());
      tracks[b].push_back(p.translation());
    }
    for (std::size_t k = 0; k < robots.size(); ++k) {
      const core::Pose2& p = snapshot.robots[k].pose;
      const core::Pose2& o = robots[k].odometry.pose();
      CsvRow row;
      row.Add(t, 3)
          .Add(robots[k].entry->id)
          .Add(p.x_m, 6)
          .Add(p.y_m, 6)
          .Add(p.theta_rad, 6)
          .Add(o.x_m, 6)
          .Add(o.y_m, 6)
          .Add(o.theta_rad, 6);
      if (robots[k].localization) {
        const core::PoseWithCovariance& e = robots[k].localization->localizer().estimate();
        row.Add(e.pose.x_m, 6).Add(e.pose.y_m, 6).Add(e.pose.theta_rad, 6).Covariance(e.covariance);
        robots[k].estimate_track.push_back(e.pose.translation());
      } else {
        row.Empty(9);
      }
      trajectories.Append(row.str());
      robots[k].track.push_back(p.translation());
      robots[k].odometry_track.push_back(o.translation());
    }
  };

  emit(Json{{"time_s", 0.0},
            {"type", "run_started"},
            {"scenario", scenario.name},
            {"seed", scenario.seed},
            {"bodies", world.body_count()},
            {"robots", static_cast<int>(robots.size())}});
  record(0.0);

  // What each robot's work of a tick produced (its own slot, see below).
  struct TickWork {
    sim::SensorOutputs outputs;
    bool cycle = false;  // a localization cycle completed
    double localization_s = 0.0;
  };
  std::vector<TickWork> work(robots.size());
  sim::WorkerPool pool(options.threads > 0 ? options.threads : sim::WorkerPool::HardwareThreads());
  const auto t_loop = Clock::now();
  const double cpu_loop_start_s = ProcessCpuSeconds();
  const double startup_s = Seconds(t_loop - t_start);
  double physics_s = 0.0;
  double sensors_s = 0.0;       // robots' sensors, laser rays included
  double localization_s = 0.0;  // extraction and EKF (part of sensors_s)
  std::int64_t localization_cycles = 0;
  std::int64_t ticks_run = 0;
  ProgressLine progress(options.progress, scenario.duration_s);
  std::size_t next_event = 0;
  for (std::int64_t tick = 0; tick < total_ticks; ++tick) {
    const double t = static_cast<double>(tick) * dt;
    // Scripted events due by this tick happen before it is stepped.
    while (next_event < scenario.events.size() && scenario.events[next_event].at_s <= t + 1e-9) {
      const ScriptedEvent& e = scenario.events[next_event++];
      Json j{{"time_s", std::stod(Fixed(t, 6))}};
      switch (e.type) {
        case ScriptedEvent::Type::kPush:
          if (robot_index.contains(e.target)) {
            world.ApplyRobotImpulse(robots[robot_index.at(e.target)].robot->index(), e.impulse_ns);
          } else {
            world.ApplyImpulse(body_index.at(e.target), e.impulse_ns);
          }
          j["type"] = "push";
          j["body"] = e.target;
          j["impulse_ns"] = {e.impulse_ns.x(), e.impulse_ns.y()};
          break;
        case ScriptedEvent::Type::kTeleport:
          if (robot_index.contains(e.target)) {
            const int index = robots[robot_index.at(e.target)].robot->index();
            world.TeleportRobot(index, e.pose);
            snapshot.robots[index] = world.robot_state(index);
          } else {
            world.Teleport(body_index.at(e.target), e.pose);
            snapshot.bodies[body_index.at(e.target)] = world.body_state(body_index.at(e.target));
          }
          j["type"] = "teleport";
          j["body"] = e.target;
          j["pose"] = {e.pose.x_m, e.pose.y_m, e.pose.theta_rad};
          break;
        case ScriptedEvent::Type::kDoor:
          world.SetDoorOpen(e.target, e.open);
          j["type"] = "door";
          j["door"] = e.target;
          j["state"] = e.open ? "open" : "closed";
          break;
      }
      emit(j);
    }
    // Per-body work reads the tick's snapshot and writes only its own slot;
    // the results are applied in body order (parallel-ready, architecture.md).
    for (int b = 0; b < world.body_count(); ++b) {
      if (motions[b]) commands[b] = motions[b]->Update(t, snapshot.bodies[b]);
    }
    for (int b = 0; b < world.body_count(); ++b) {
      if (motions[b])
        world.SetPlanarVelocity(b, commands[b].linear_mps, commands[b].yaw_rate_radps);
    }
    for (RobotRun& r : robots) {
      if (!r.follower || r.route_done || t + 1e-9 < r.entry->route->start_s ||
          tick % r.control_period_ticks != 0) {
        continue;
      }
      // Steer from what the robot believes: its estimate, or odometry without it.
      const core::Pose2 believed =
          r.localization ? r.localization->localizer().estimate().pose : r.odometry.pose();
      const double period_s = static_cast<double>(r.control_period_ticks) * dt;
      const nav::VelocityCommand command = r.follower->Update(believed, period_s);
      const sim::OdometryCalibration& c = r.entry->config.odometry;
      const nav::WheelSpeeds w =
          nav::ToWheelSpeeds(command, c.left_wheel_radius_m, c.right_wheel_radius_m, c.wheelbase_m);
      r.robot->SetWheelSpeeds(w.left_radps, w.right_radps);
      if (r.follower->done()) {
        r.route_done = true;
        r.route_done_s = t;
        emit(Json{{"time_s", std::stod(Fixed(t, 6))},
                  {"type", "route_done"},
                  {"robot", r.entry->id},
                  {"length_m", std::stod(Fixed(r.follower->length_m(), 3))}});
      }
    }
    for (RobotRun& r : robots) {
      const auto& drive = r.entry->drive;
      while (r.next_drive < drive.size() && drive[r.next_drive].at_s <= t + 1e-9) {
        r.robot->SetWheelSpeeds(drive[r.next_drive].left_radps, drive[r.next_drive].right_radps);
        ++r.next_drive;
      }
    }
    const auto t_physics = Clock::now();
    world.Step();
    physics_s += Seconds(Clock::now() - t_physics);
    const double t_after = world.time_s();

    for (const sim::ContactChange& c : world.TakeContactChanges()) {
      if (!c.began) continue;
      for (int element : {c.a, c.b}) {
        if (body_of_element[element] >= 0) ++collisions[body_of_element[element]];
        if (robot_of_element[element] >= 0) ++robots[robot_of_element[element]].collisions;
      }
      emit(Json{{"time_s", std::stod(Fixed(t_after, 6))},
                {"type", "collision"},
                {"a", elements[c.a].id},
                {"b", elements[c.b].id},
                {"impulse_ns", std::stod(Fixed(c.impulse_ns, 6))},
                {"point_m",
                 {std::stod(Fixed(c.point_m.x(), 4)), std::stod(Fixed(c.point_m.y(), 4)),
                  std::stod(Fixed(c.point_m.z(), 4))}}});
    }
    sim::TickSnapshot next = world.Snapshot();
    for (int b = 0; b < world.body_count(); ++b) {
      distance_m[b] +=
          (next.bodies[b].pose.translation() - snapshot.bodies[b].pose.translation()).norm();
    }
    // Robots' sensors and localization for the tick that just ended: per-robot
    // work on the tick's snapshot, each robot writing only its own slot, spread
    // over the worker pool; then merged in robot order (events, logs), so the
    // outputs are the same for any thread count.
    const auto t_sensors = Clock::now();
    if (planar) planar->Update();  // the slices are read-only until the next step
    const auto sense = [&](std::size_t k) {
      RobotRun& r = robots[k];
      TickWork& w = work[k];
      w.outputs = r.robot->AfterStep(snapshot.robots[k], next.robots[k]);
      for (const core::EncoderReading& reading : w.outputs.encoders) r.odometry.Update(reading);
    };
    const auto localize = [&](std::size_t k) {
      RobotRun& r = robots[k];
      TickWork& w = work[k];
      w.cycle = false;
      if (!r.localization) return;
      const auto t_localization = Clock::now();
      std::vector<const core::LaserScan*> scans;
      for (const sim::ScanRecord& scan : w.outputs.scans) scans.push_back(&scan.scan);
      w.cycle = r.localization->Update(w.outputs.encoders, scans, next.robots[k].pose, t_after);
      w.localization_s = Seconds(Clock::now() - t_localization);
    };
    if (planar) {
      pool.ParallelFor(robots.size(), [&](std::size_t k) {
        sense(k);
        localize(k);
      });
    } else {
      // Bullet serializes its ray casts (World::CastRay): threads would only
      // queue for the lock, so the scans are cast in order.
      for (std::size_t k = 0; k < robots.size(); ++k) sense(k);
      pool.ParallelFor(robots.size(), localize);
    }
    for (std::size_t k = 0; k < robots.size(); ++k) {
      RobotRun& r = robots[k];
      const TickWork& w = work[k];
      r.distance_m +=
          (next.robots[k].pose.translation() - snapshot.robots[k].pose.translation()).norm();
      for (const core::BumperReading& b : w.outputs.bumpers) {
        Json zones = Json::array();
        const auto& names = r.entry->config.bumpers;
        for (std::size_t z = 0; z < names.size(); ++z) {
          if (b.zones_in_contact & (1u << z)) zones.push_back(names[z].name);
        }
        if (!zones.empty()) ++r.bumper_presses;
        emit(Json{{"time_s", std::stod(Fixed(b.stamp_s, 6))},
                  {"type", "bumper"},
                  {"robot", r.entry->id},
                  {"zones", zones}});
      }
      for (const sim::ScanRecord& scan : w.outputs.scans) {
        ++r.scans;
        if (scan.fallback) ++r.fallback_scans;
        if (scan_log) scan_log->Append(r.entry->id, scan.scan, scan.truth);
        if (r.wander && scan.scan.sensor_id == r.entry->wander->laser) {
          // The new command holds from the next physics step until the next scan.
          const nav::VelocityCommand command = r.wander->Update(scan.scan.readings);
          const sim::OdometryCalibration& c = r.entry->config.odometry;
          const nav::WheelSpeeds w = nav::ToWheelSpeeds(command, c.left_wheel_radius_m,
                                                        c.right_wheel_radius_m, c.wheelbase_m);
          r.robot->SetWheelSpeeds(w.left_radps, w.right_radps);
        }
      }
      if (r.localization) {
        localization_s += w.localization_s;  // summed over robots: thread time
        if (w.cycle) {
          ++localization_cycles;
          const LocalizationCycle& c = r.localization->last_cycle();
          localization_log->Append(
              CsvRow()
                  .Add(c.time_s, 3)
                  .Add(r.entry->id)
                  .Add(static_cast<std::int64_t>(r.localization->cycles().size()) - 1)
                  .Add(c.truth.x_m, 6)
                  .Add(c.truth.y_m, 6)
                  .Add(c.truth.theta_rad, 6)
                  .Add(c.estimate.x_m, 6)
                  .Add(c.estimate.y_m, 6)
                  .Add(c.estimate.theta_rad, 6)
                  .Covariance(c.covariance)
                  .Add(c.position_error_m, 6)
                  .Add(c.heading_error_rad, 6)
                  .Add(c.nees, 4)
                  .Add(c.two_sigma_frontal_m, 6)
                  .Add(c.two_sigma_lateral_m, 6)
                  .Add(c.two_sigma_heading_rad, 6)
                  .Add(std::int64_t{c.predictions})
                  .Add(std::int64_t{c.observations})
                  .Add(std::int64_t{c.matched_lines})
                  .Add(std::int64_t{c.matched_beacons})
                  .Add(std::int64_t{c.lost ? 1 : 0})
                  .str());
          if (r.localization->lost_started()) {
            emit(Json{{"time_s", std::stod(Fixed(t_after, 6))},
                      {"type", "lost"},
                      {"robot", r.entry->id},
                      {"reason", r.localization->lost_reason()},
                      {"position_error_m", std::stod(Fixed(c.position_error_m, 4))},
                      {"heading_error_deg",
                       std::stod(Fixed(c.heading_error_rad * 180.0 / std::numbers::pi, 3))}});
          }
        }
      }
    }
    sensors_s += Seconds(Clock::now() - t_sensors);
    snapshot = std::move(next);
    if (schedule.IsDue(trajectory_task, tick + 1)) record(t_after);
    if ((tick & 255) == 0) progress.Update(t_after, Seconds(Clock::now() - t_loop));
    ticks_run = tick + 1;
    if (scenario.end_when_routes_done &&
        std::any_of(robots.begin(), robots.end(),
                    [](const RobotRun& r) { return r.follower != nullptr; }) &&
        std::all_of(robots.begin(), robots.end(),
                    [](const RobotRun& r) { return !r.follower || r.route_done; })) {
      break;
    }
  }
  progress.Done();
  const double loop_s = Seconds(Clock::now() - t_loop);
  const double loop_cpu_s = ProcessCpuSeconds() - cpu_loop_start_s;
  const double sim_s = static_cast<double>(ticks_run) * dt;
  emit(Json{{"time_s", std::stod(Fixed(sim_s, 6))}, {"type", "run_finished"}});
  events.Flush();
  trajectories.Flush();
  if (scan_log) scan_log->Close();
  if (localization_log) localization_log->Flush();

  std::int64_t summary_fallback_scans = 0;
  // metrics.json: a function of scenario and seed only (metrics.md, schema 1).
  Json metrics;
  metrics["schema_version"] = 1;
  metrics["scenario"] = scenario.name;
  metrics["seed"] = scenario.seed;
  metrics["pavilion_version"] = kVersion;
  metrics["world"] = scenario.world.name;
  metrics["sim_duration_s"] = sim_s;
  metrics["physics"] = {{"rate_hz", scenario.physics.physics_rate_hz}, {"ticks", ticks_run}};
  if (world.body_count() > 0) {
    Json bodies;
    double total_distance = 0.0;
    std::int64_t total_collisions = 0;
    for (int b = 0; b < world.body_count(); ++b) {
      bodies[world.body_spec(b).id] = {{"distance_m", std::stod(Fixed(distance_m[b], 6))},
                                       {"collisions", collisions[b]}};
      total_distance += distance_m[b];
      total_collisions += collisions[b];
    }
    metrics["bodies_summary"] = {{"count", world.body_count()},
                                 {"distance_m", std::stod(Fixed(total_distance, 6))},
                                 {"collisions", total_collisions}};
    metrics["bodies"] = bodies;
  }
  if (!robots.empty()) {
    Json robot_metrics;
    for (std::size_t k = 0; k < robots.size(); ++k) {
      const RobotRun& r = robots[k];
      const core::Pose2& truth = snapshot.robots[k].pose;
      const core::Pose2& odo = r.odometry.pose();
      robot_metrics[r.entry->id] = {
          {"model", r.entry->config.description.model},
          {"distance_m", std::stod(Fixed(r.distance_m, 6))},
          {"collisions", r.collisions},
          {"bumper_presses", r.bumper_presses},
          {"scans", r.scans},
          {"odometry_final_error",
           {{"position_m", std::stod(Fixed((odo.translation() - truth.translation()).norm(), 6))},
            {"heading_rad",
             std::stod(
                 Fixed(std::abs(core::NormalizeAngle(odo.theta_rad - truth.theta_rad)), 6))}}}};
      if (r.localization) {
        const LocalizationFigures f = r.localization->Figures();
        const auto n = [](double v) { return std::stod(Fixed(v, 6)); };
        robot_metrics[r.entry->id]["localization"] = {
            {"cycles", f.cycles},
            {"position_rmse_m", n(f.position_rmse_m)},
            {"position_median_m", n(f.position_median_m)},
            {"position_max_m", n(f.position_max_m)},
            {"heading_rmse_deg", n(f.heading_rmse_deg)},
            {"heading_median_deg", n(f.heading_median_deg)},
            {"heading_max_deg", n(f.heading_max_deg)},
            {"two_sigma_frontal_m", n(f.two_sigma_frontal_m)},
            {"two_sigma_lateral_m", n(f.two_sigma_lateral_m)},
            {"two_sigma_heading_deg", n(f.two_sigma_heading_deg)},
            {"anees", n(f.anees)},
            {"nees_below_95_bound_ratio", n(f.nees_below_95_bound_ratio)},
            {"matched_lines_per_cycle", n(f.matched_lines_per_cycle)},
            {"matched_beacons_per_cycle", n(f.matched_beacons_per_cycle)},
            {"cycles_without_match", f.cycles_without_match},
            {"lost_situations", f.lost_situations}};
      }
      if (r.follower) {
        robot_metrics[r.entry->id]["route"] = {
            {"stops", r.entry->route->stops},
            {"length_m", std::stod(Fixed(r.follower->length_m(), 3))},
            {"done", r.route_done},
            {"done_at_s", r.route_done ? std::stod(Fixed(r.route_done_s, 3)) : sim_s}};
      }
    }
    metrics["robots"] = robot_metrics;
    std::int64_t scans = 0, fallback_scans = 0;
    for (const RobotRun& r : robots) {
      scans += r.scans;
      fallback_scans += r.fallback_scans;
    }
    // Scans the planar backend handed to Bullet (tilted beam planes, bodies
    // the plane does not cut exactly); a function of scenario and seed.
    metrics["laser"] = {{"backend", ToString(scenario.laser_backend)},
                        {"scans", scans},
                        {"fallback_scans", fallback_scans}};
    summary_fallback_scans = fallback_scans;
  }
  metrics["events"] = event_counts;
  WriteFileAtomically((out / "metrics.json").string(), metrics.dump(2) + "\n");

  // Snapshot and report.
  std::vector<sim::TopDownTrack> top_tracks;
  for (const auto& t : tracks) top_tracks.push_back({t, {200, 40, 40}, 0.4});
  for (const RobotRun& r : robots) {
    top_tracks.push_back({r.odometry_track, {230, 150, 20}, 0.8});  // what the encoders believe
    top_tracks.push_back({r.track, {20, 60, 220}, 0.9});            // the true path
    if (!r.estimate_track.empty()) {
      top_tracks.push_back({r.estimate_track, {30, 160, 60}, 0.7});  // the localization estimate
    }
  }
  sim::TopDownOptions view;
  view.width_px = scenario.outputs.image_width_px;
  view.section_height_m = scenario.outputs.section_height_m;
  const core::RgbImage image = sim::RenderTopDown(world, top_tracks, view);
  const std::vector<std::uint8_t> png = EncodePng(image);
  WriteFileAtomically((out / "snapshots" / "topdown_final.png").string(),
                      std::string(png.begin(), png.end()));
  std::vector<LocalizationPlot> localization_plots;
  for (const RobotRun& r : robots) {
    if (!r.localization) continue;
    LocalizationPlot plot{r.entry->id, EncodePng(PlotTwoSigmaOverTime(r.localization->cycles()))};
    WriteFileAtomically((out / "snapshots" / ("two_sigma_" + r.entry->id + ".png")).string(),
                        std::string(plot.png.begin(), plot.png.end()));
    localization_plots.push_back(std::move(plot));
  }
  WriteFileAtomically((out / "report.html").string(),
                      RenderReportHtml(scenario, metrics, png, localization_plots));

  RunSummary summary;
  summary.sim_duration_s = sim_s;
  summary.ticks = ticks_run;
  summary.startup_s = startup_s;
  summary.wall_time_s = Seconds(Clock::now() - t_start);
  summary.real_time_factor = loop_s > 0 ? sim_s / loop_s : 0.0;
  summary.loop_s = loop_s;
  summary.loop_cpu_s = loop_cpu_s;
  summary.physics_s = physics_s;
  summary.sensors_s = sensors_s;
  std::int64_t laser_rays = 0;  // counted by the scanners, either backend
  for (const RobotRun& r : robots) {
    for (const sim::LaserScanner& laser : r.robot->lasers()) laser_rays += laser.rays_cast();
  }
  summary.laser_rays = laser_rays;
  summary.peak_rss_mb = PeakRssMb();
  for (const auto& [type, n] : event_counts) summary.events += n;
  summary.laser_fallback_scans = summary_fallback_scans;

  // performance.json: the one output with wall-clock figures.
  Json perf;
  perf["schema_version"] = 1;
  perf["wall_time_s"] = summary.wall_time_s;
  perf["startup_s"] = startup_s;
  perf["real_time_factor"] = summary.real_time_factor;
  perf["loop_cpu_s"] = loop_cpu_s;
  perf["peak_rss_mb"] = summary.peak_rss_mb;
  perf["threads"] = pool.threads();
  perf["physics_steps_per_s"] = physics_s > 0 ? static_cast<double>(ticks_run) / physics_s : 0.0;
  perf["laser_backend"] = ToString(scenario.laser_backend);
  perf["laser_rays"] = laser_rays;
  perf["laser_fallback_scans"] = summary.laser_fallback_scans;
  if (localization_cycles > 0) {
    // Line extraction, matching and estimation per localization cycle.
    perf["localization_us_per_cycle"] = 1e6 * localization_s / localization_cycles;
  }
  perf["laser_rays_per_s"] = sensors_s > 0 ? static_cast<double>(laser_rays) / sensors_s : 0.0;
  perf["stages_s"] = {{"startup", startup_s},
                      {"physics", physics_s},
                      {"sensors", sensors_s},
                      {"loop_other", loop_s - physics_s - sensors_s},
                      {"outputs", summary.wall_time_s - startup_s - loop_s}};
  WriteFileAtomically((out / "performance.json").string(), perf.dump(2) + "\n");
  return summary;
}

}  // namespace pavilion::scenarios
