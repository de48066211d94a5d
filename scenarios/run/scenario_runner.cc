#include "scenarios/run/scenario_runner.h"

#include <algorithm>
#include <cstdio>

#include "scenarios/run/scenario_run.h"

namespace pavilion::scenarios {
namespace detail {
ScenarioRun::ScenarioRun(const Scenario& scenario, const RunOptions& options,
                         const RunExtensions& extensions)
    : scenario_(scenario),
      options_(options),
      extensions_(extensions),
      out_(options.out_dir),
      t_start_(Clock::now()) {
  std::filesystem::create_directories(out_);
  // Robots bring their own materials into the world description.
  sim::WorldDescription description = scenario.world;
  std::vector<sim::RobotConfig> configs;
  for (const RobotEntry& r : scenario.robots) {
    configs.push_back(WithWorldMaterials(r.config, &description));
  }
  // Under `realism: realistic` this is the surveyed world, rebuilt below with
  // what the survey left out; the description is kept for that.
  world_ = scenario.realism.realistic
               ? std::make_unique<sim::World>(description, scenario.physics)
               : std::make_unique<sim::World>(std::move(description), scenario.physics);
  // Maps before any body enters the world (a derived map is a survey of the
  // static geometry).
  std::vector<std::optional<core::RobotMap>> maps(scenario.robots.size());
  for (std::size_t k = 0; k < scenario.robots.size(); ++k) {
    if (NeedsMap(scenario.robots[k])) maps[k] = LoadRobotMap(scenario.robots[k], scenario, *world_);
  }
  if (scenario.realism.realistic) {
    // The real world is the surveyed one plus what the survey left out:
    // clutter against the walls, doors standing otherwise (issue 20).
    ClutterKeepOut keep_out;
    for (const RobotEntry& r : scenario.robots) keep_out.points_m.push_back(r.pose.translation());
    for (const auto& map : maps) {
      if (map) AddRoads(*map, &keep_out);
    }
    real_world_ = DrawRealWorld(scenario.realism, scenario.seed, *world_, description, keep_out);
    ApplyRealWorld(real_world_, &description);
    for (sim::RobotConfig& c : configs) c.encoders.patches = real_world_.carpets;
    world_ = std::make_unique<sim::World>(std::move(description), scenario.physics);
  }
  motions_ = SpawnBodies(scenario, world_.get());
  // The planar laser caster, shared by every robot's scanners (one slice per
  // beam height); it reads the world after each step.
  if (scenario.laser_backend == LaserBackend::kPlanar) {
    planar_ = std::make_unique<sim::PlanarCaster>(world_.get(), scenario.planar_laser);
  }
  for (int b = 0; b < world_->body_count(); ++b) body_index_[world_->body_spec(b).id] = b;
  BuildRobots(std::move(configs), maps);
  // The crowd after the robots: its people start off their footprints, and
  // their elements follow the robots'.
  if (scenario.crowd) {
    try {
      world_->AddCrowd(*scenario.crowd, scenario.seed);
    } catch (const std::invalid_argument& e) {
      throw InputError(Diagnostic{scenario_.source_file, 0, "crowd", e.what()});
    }
    crowd_tracker_.emplace();
    for (RobotRun& r : robots_) r.social.emplace(r.entry->config.description.footprint_m);
    crowd_strip_.emplace(CrowdStripOptionsFor(scenario_));
    visitors_present_.emplace();
  }
  if (!scenario.snapshots.empty()) {
    std::map<std::string, SnapshotCamera> cameras;
    for (const RobotRun& r : robots_) {
      SnapshotCamera& c = cameras[r.entry->id];
      c.robot = r.robot->index();
      for (const sim::CameraMount& m : r.entry->model_cameras) {
        if (!c.mount && m.mount.roll_rad == 0.0 && m.mount.pitch_rad == 0.0) c.mount = m;
      }
    }
    snapshots_ = std::make_unique<SnapshotTaker>(scenario.snapshots, std::move(cameras));
  }
  OpenLogs();
  pool_ = std::make_unique<sim::WorkerPool>(
      options.threads > 0 ? options.threads : sim::WorkerPool::HardwareThreads());
}

void ScenarioRun::BuildRobots(std::vector<sim::RobotConfig> configs,
                              const std::vector<std::optional<core::RobotMap>>& maps) {
  robots_.resize(scenario_.robots.size());
  const auto missions = std::count_if(scenario_.robots.begin(), scenario_.robots.end(),
                                      [](const RobotEntry& r) { return r.mission.has_value(); });
  if (scenario_.fleet.coordination && missions >= 2) {
    fleet_ = std::make_unique<nav::FleetCoordinator>(static_cast<int>(scenario_.robots.size()),
                                                     scenario_.fleet.options);
  }
  if (missions >= 2) {
    std::vector<core::Polygon2> hulls;
    for (const RobotEntry& r : scenario_.robots) {
      hulls.push_back(r.config.description.OutlineWithWheels());
    }
    proximity_.emplace(std::move(hulls));
    // The stations the missions name (a tour's candidates or a list), at
    // their nodes in the first mission robot's map (the fleet shares one).
    std::set<std::string> named;
    const core::RobotMap* map = nullptr;
    for (std::size_t k = 0; k < scenario_.robots.size(); ++k) {
      const std::optional<MissionEntry>& mission = scenario_.robots[k].mission;
      if (!mission || !maps[k]) continue;
      if (!map) map = &*maps[k];
      named.insert(mission->tour_among.begin(), mission->tour_among.end());
      named.insert(mission->stations.begin(), mission->stations.end());
    }
    std::vector<Eigen::Vector2d> stations;
    for (const core::MapNode& n : map ? map->nodes : std::vector<core::MapNode>{}) {
      if (n.station && (named.empty() || named.contains(n.id))) {
        stations.push_back(n.pose.translation());
        watched_stations_.push_back(n.id);
      }
    }
    proximity_->WatchStations(std::move(stations));
    if (fleet_) fleet_->SetStations(watched_stations_);  // claimed for passage
  }
  for (std::size_t k = 0; k < scenario_.robots.size(); ++k) {
    const RobotEntry& entry = scenario_.robots[k];
    RobotRun& run = robots_[k];
    run.entry = &entry;
    try {
      run.robot = std::make_unique<sim::SimRobot>(
          world_.get(), std::move(configs[k]),
          sim::RobotPlacement{entry.id, entry.pose, entry.wheel_model}, scenario_.seed);
      run.robot->UsePlanarCaster(planar_.get());
    } catch (const std::invalid_argument& e) {
      throw InputError(
          Diagnostic{scenario_.source_file, 0, "robots[" + std::to_string(k) + "]", e.what()});
    }
    if (extensions_.add_sensors) extensions_.add_sensors(entry, run.robot.get());
    robot_index_[entry.id] = run.robot->index();
    run.navigator =
        MakeNavigator(scenario_, k, maps[k], nav::FleetLink{fleet_.get(), static_cast<int>(k)});
    if (run.navigator->estimator()) {
      run.tracker.emplace();
      run.relocalization.emplace();
      run.day.emplace();
      if (run.navigator->shadow_estimator()) {
        run.shadow_tracker.emplace();
        run.shadow_relocalization.emplace();
      }
    }
  }
  work_.resize(robots_.size());
  robot_step_m_.assign(world_->robot_count(), 0.0);
  event_streams_ = std::make_unique<EventStreams>(scenario_.seed);
}

void ScenarioRun::OpenLogs() {
  events_ = std::make_unique<EventLog>((out_ / "events.jsonl").string());
  if (!scenario_.expectations.empty()) {
    std::vector<std::string> ids;
    for (const RobotRun& r : robots_) ids.push_back(r.entry->id);
    expect_monitor_.emplace(scenario_.expectations, std::move(ids));
    events_->SetListener([this](double t, const std::string& type, const EventFields& fields) {
      expect_monitor_->OnEvent(t, type, fields);
    });
  }
  trajectories_ = std::make_unique<TrajectoryLog>((out_ / "trajectories.csv").string());
  const bool any_localization = std::any_of(
      robots_.begin(), robots_.end(), [](const RobotRun& r) { return r.tracker.has_value(); });
  if (any_localization) {
    localization_log_ = std::make_unique<LocalizationLog>((out_ / "localization.csv").string());
  }
  if (scenario_.outputs.scan_log != ScanLogMode::kOff && !robots_.empty()) {
    std::vector<std::string> ids;
    for (const auto& e : world_->elements()) ids.push_back(e.id);
    scan_log_ = std::make_unique<ScanLogWriter>((out_ / "scans.bin").string(), ids);
  }
  const auto& elements = world_->elements();
  body_tally_.resize(world_->body_count());
  body_tracks_.assign(world_->body_count(), StrideBuffer<Eigen::Vector2d>(kBodyPathPoints));
  body_of_element_.assign(elements.size(), -1);
  for (int b = 0; b < world_->body_count(); ++b) {
    body_of_element_[world_->body_element(b)] = b;
    body_tally_[b].id = world_->body_spec(b).id;
  }
  // Parts of a robot share its group.
  robot_of_element_.assign(elements.size(), -1);
  for (std::size_t e = 0; e < elements.size(); ++e) {
    if (elements[e].group >= 0) robot_of_element_[e] = elements[e].group;
  }
  BuildCollisionClasses();
}

void ScenarioRun::BuildCollisionClasses() {
  // Walkers are the scenario's random-walk bodies (the crowd issue makes them people).
  std::map<std::string, bool> walker;
  for (const BodyEntry& b : scenario_.bodies) {
    walker[b.spec.id] = b.motion.type == MotionSpec::Type::kRandomWalk;
  }
  const auto& elements = world_->elements();
  visitor_body_.assign(world_->body_count(), false);
  walker_paused_until_s_.assign(world_->body_count(), -1.0);
  for (const RobotRun& r : robots_) {
    robot_radius_m_.push_back(nav::Circumradius(r.entry->config.description.footprint_m));
  }
  std::vector<bool> visitor_element(elements.size(), false);
  for (int b = 0; b < world_->body_count(); ++b) {
    visitor_body_[b] = walker[world_->body_spec(b).id];
    visitor_element[world_->body_element(b)] = visitor_body_[b];
  }
  person_of_element_.assign(elements.size(), -1);
  if (const sim::crowd::Crowd* crowd = world_->crowd()) {
    for (int i = 0; i < crowd->size(); ++i) {
      visitor_element[world_->person_element(i)] = true;
      person_of_element_[world_->person_element(i)] = i;
      person_ids_.push_back(elements[world_->person_element(i)].id);
    }
  }
  std::set<double> heights;
  for (const RobotRun& r : robots_) {
    for (const sim::LaserMount& l : r.entry->config.lasers) heights.insert(l.z_m);
  }
  std::vector<core::PlanarSection> sections;
  for (double h : heights) sections.push_back(world_->SectionAt(h));
  collision_classes_ = std::make_unique<CollisionClassifier>(sections, std::move(visitor_element),
                                                             robot_of_element_);
}

void ScenarioRun::Run() {
  snapshot_ = world_->Snapshot();
  events_->Emit(0.0, kRunStarted,
                EventFields{{"scenario", scenario_.name},
                            {"seed", scenario_.seed},
                            {"bodies", world_->body_count()},
                            {"robots", static_cast<int>(robots_.size())}});
  RecordTrajectories(0.0, true, true);
  const double dt = world_->step_s();
  const auto total_ticks = static_cast<std::int64_t>(std::llround(scenario_.duration_s / dt));
  sim::PeriodicSchedule schedule(scenario_.physics.physics_rate_hz);
  const int trajectory_task =
      schedule.Add("outputs.trajectory_rate_hz", scenario_.outputs.trajectory_rate_hz);
  const int body_task = schedule.Add("outputs.body_rate_hz", scenario_.outputs.body_rate_hz);
  const bool people_rows = world_->crowd() && scenario_.outputs.people_rate_hz > 0.0;
  const int people_task =
      people_rows ? schedule.Add("outputs.people_rate_hz", scenario_.outputs.people_rate_hz) : -1;
  if (people_rows) trajectories_->AddPeople(0.0, snapshot_.people, person_ids_);
  // Visitors present, once a simulated second, for the report's chart.
  const int visitors_task = visitors_present_ ? schedule.Add("visitors_present", 1.0) : -1;
  if (visitors_present_) visitors_present_->Add(0.0, world_->crowd()->present());
  ProgressLine progress(options_.progress, scenario_.duration_s);
  const auto t_loop = Clock::now();
  const double cpu_start_s = ProcessCpuSeconds();
  summary_.startup_s = Seconds(t_loop - t_start_);
  for (std::int64_t tick = 0; tick < total_ticks; ++tick) {
    const double t = static_cast<double>(tick) * dt;
    ApplyEvents(t);
    MoveBodies(t);
    ControlRobots(tick, t);
    StepPhysics();
    const double t_after = world_->time_s();
    RecordContacts(t_after);
    sim::TickSnapshot next = world_->Snapshot();
    if (crowd_tracker_) crowd_tracker_->Update(dt, *world_->crowd());
    for (int b = 0; b < world_->body_count(); ++b) {
      body_tally_[b].distance_m +=
          (next.bodies[b].pose.translation() - snapshot_.bodies[b].pose.translation()).norm();
    }
    const auto t_sensors = Clock::now();
    SenseRobots(next, t_after);
    for (std::size_t k = 0; k < robots_.size(); ++k) MergeRobot(k, next, t_after);
    summary_.sensors_s += Seconds(Clock::now() - t_sensors);
    if (fleet_) fleet_->Merge();  // seen by every robot from the next tick on
    if (proximity_) RecordProximity(t_after);
    snapshot_ = std::move(next);
    if (snapshots_) snapshots_->TakeDue(*world_, t_after);
    if (crowd_strip_ && crowd_strip_->Due(t_after)) {
      crowd_strip_->Capture(*world_, CrowdStripCentre(*world_), t_after);
    }
    const bool bodies_due = schedule.IsDue(body_task, tick + 1);
    const bool robots_due = schedule.IsDue(trajectory_task, tick + 1);
    if (bodies_due || robots_due) RecordTrajectories(t_after, bodies_due, robots_due);
    if (scan_log_ && scenario_.outputs.scan_log == ScanLogMode::kAuto) LimitScanLog(t_after);
    if (visitors_present_ && schedule.IsDue(visitors_task, tick + 1)) {
      visitors_present_->Add(t_after, world_->crowd()->present());
    }
    if (people_rows && schedule.IsDue(people_task, tick + 1)) {
      trajectories_->AddPeople(t_after, snapshot_.people, person_ids_);
    }
    if ((tick & 255) == 0) progress.Update(t_after, Seconds(Clock::now() - t_loop));
    ticks_run_ = tick + 1;
    if (RobotLeftFloor(t_after)) break;
    if (scenario_.end_when_routes_done && RoutesDone()) break;
    if (options_.stop_signal && *options_.stop_signal != 0) {
      summary_.interrupted_by = *options_.stop_signal;
      break;
    }
  }
  progress.Done();
  summary_.loop_s = Seconds(Clock::now() - t_loop);
  summary_.loop_cpu_s = ProcessCpuSeconds() - cpu_start_s;
}

void ScenarioRun::LimitScanLog(double t_after) {
  const double robot_minutes = t_after * static_cast<double>(robots_.size()) / 60.0;
  if (robot_minutes < scenario_.outputs.scan_log_robot_minutes) return;
  scan_log_->Close();
  scan_log_.reset();
  events_->Emit(t_after, kScanLogStopped,
                EventFields{{"robot_minutes", RoundForJson(robot_minutes, 3)},
                            {"reason", "outputs.scan_log: auto records up to " +
                                           FormatFigure(scenario_.outputs.scan_log_robot_minutes) +
                                           " robot-minutes"}});
}

void ScenarioRun::ApplyEvents(double t) {
  // Scripted events due by this tick happen before it is stepped; processes
  // started before (random kidnaps by distance) act first, on the last step.
  kidnaps_.clear();
  EventContext context{
      world_.get(),   &robot_index_, &body_index_, &snapshot_, event_streams_.get(),
      &robot_step_m_, &kidnaps_,     {},           {}};
  context.set_laser_fault = [this](const std::string& robot, const std::string& sensor,
                                   const sim::LaserFault& fault) {
    for (RobotRun& r : robots_) {
      if (r.entry->id == robot) return r.robot->SetLaserFault(sensor, fault);
    }
    return false;
  };
  context.sim_robot = [this](int index) { return robots_.at(index).robot.get(); };
  for (const ScenarioEvent* e : ongoing_events_) EmitScripted(t, *e, e->Continue(context));
  while (next_event_ < scenario_.events.size() &&
         scenario_.events[next_event_].at_s <= t + kDueToleranceS) {
    const ScenarioEvent& e = *scenario_.events[next_event_++].event;
    EmitScripted(t, e, e.Apply(context));
    if (e.ongoing() &&
        std::find(ongoing_events_.begin(), ongoing_events_.end(), &e) == ongoing_events_.end()) {
      ongoing_events_.push_back(&e);
    }
  }
  for (const KidnapNote& kidnap : kidnaps_) {
    for (RobotRun& r : robots_) {
      if (r.robot->index() == kidnap.robot) {
        r.kidnapped = true;
        if (snapshots_) snapshots_->OnEvent(*world_, t, r.entry->id, "kidnap");
      }
      if (r.robot->index() == kidnap.robot && r.relocalization) r.relocalization->OnKidnap(t);
      if (r.robot->index() == kidnap.robot && r.day) r.day->OnKidnap(t);
      if (r.robot->index() == kidnap.robot && r.shadow_relocalization) {
        r.shadow_relocalization->OnKidnap(t);
      }
    }
  }
}

void ScenarioRun::EmitScripted(double t, const ScenarioEvent& e, const EventFields& fields) {
  if (fields.is_null()) return;
  events_->Emit(t, e.type(), fields);
  // A push on a robot is a disturbance of the run table: the robot is judged
  // once the push is over (its motors engaged again).
  if (e.type() != "push" || !fields.contains("body")) return;
  for (RobotRun& r : robots_) {
    if (!r.day || r.entry->id != fields["body"].get<std::string>()) continue;
    const bool disengaged = fields.contains("motors") && fields["motors"] == "disengaged";
    if (fields.contains("motors") && fields["motors"] == "engaged") {
      r.day->OnMotorsEngaged(t);
    } else {
      r.day->OnPush(t, fields.value("duration_s", 0.0), disengaged);
    }
  }
}

void ScenarioRun::MoveBodies(double t) {
  // Per-body work reads the tick's snapshot; the commands are applied in body order.
  body_commands_.resize(world_->body_count());
  for (int b = 0; b < world_->body_count(); ++b) {
    if (motions_[b]) body_commands_[b] = motions_[b]->Update(t, snapshot_.bodies[b]);
  }
  for (int b = 0; b < world_->body_count(); ++b) {
    if (!motions_[b]) continue;
    // Until the crowd model, walkers stop when they meet a robot: they must not
    // shove it into an exhibit (issue 14). A walker touching a robot stands
    // for the pause, then walks on if its walk leads away from every robot:
    // standing pressed against it for good pinned a Robox to a wall for the
    // rest of a tour (expo_tour, seed 1), neither daring to move.
    const bool stop = visitor_body_[b] && (t < walker_paused_until_s_[b] ||
                                           WalkerMeetsRobot(b, body_commands_[b].linear_mps));
    if (stop && t >= walker_paused_until_s_[b]) {
      walker_paused_until_s_[b] = t + kWalkerContactPauseS;
    }
    // A walker standing for a robot yields: the robot can push it aside.
    if (visitor_body_[b]) world_->SetYielding(b, stop);
    world_->SetPlanarVelocity(b, stop ? Eigen::Vector2d::Zero() : body_commands_[b].linear_mps,
                              stop ? 0.0 : body_commands_[b].yaw_rate_radps);
  }
}

bool ScenarioRun::WalkerMeetsRobot(int b, const Eigen::Vector2d& velocity) const {
  const Eigen::Vector2d p = snapshot_.bodies[b].pose.translation();
  const double walker_radius_m = world_->body_spec(b).shape.radius_m;
  for (std::size_t k = 0; k < robots_.size(); ++k) {
    const Eigen::Vector2d to_robot = snapshot_.robots[k].pose.translation() - p;
    const double reach_m = walker_radius_m + robot_radius_m_[k] + kWalkerMeetGapM;
    // Closing in on it (its own walk or the robot's drive): the walker stops.
    const Eigen::Vector2d closing = velocity - snapshot_.robots[k].velocity_mps;
    if (to_robot.squaredNorm() <= reach_m * reach_m && closing.dot(to_robot) > 0.0) return true;
  }
  return false;
}

void ScenarioRun::ControlRobots(std::int64_t tick, double t) {
  // Each robot's controller on the worker pool, as the sensing half: a
  // navigator's Control() reads the tick's fleet board (merged at the end of
  // the last tick) and writes only itself and its own outbox
  // (nav/fleet/coordinator.h). What it did reaches the world, the events and
  // the logs afterwards, in robot order, so the outputs are the same for any
  // thread count.
  const auto control = [&](std::size_t k) {
    const auto t_control = Clock::now();
    work_[k].command = robots_[k].navigator->Control(tick, t);
    work_[k].control_s = Seconds(Clock::now() - t_control);
  };
  // Between the windows' cycles a controller only ramps its speeds: the
  // calls run inline, as handing them to the pool would cost more.
  const bool busy = std::any_of(robots_.begin(), robots_.end(),
                                [&](const RobotRun& r) { return r.navigator->ControlBusy(tick); });
  if (busy) {
    pool_->ParallelFor(robots_.size(), control);
  } else {
    for (std::size_t k = 0; k < robots_.size(); ++k) control(k);
  }
  for (std::size_t k = 0; k < robots_.size(); ++k) {
    RobotRun& r = robots_[k];
    const std::optional<nav::WheelSpeeds>& command = work_[k].command;
    summary_.control_s += work_[k].control_s;  // summed over robots: thread time
    if (command) r.robot->SetWheelSpeeds(command->left_radps, command->right_radps);
    const nav::Controller* controller = r.navigator->controller();
    const std::optional<nav::MissionStatus> mission =
        controller ? controller->mission() : std::nullopt;
    EmitNavigationEvents(r);
    if (r.entry->route && mission && mission->done && !r.mission_done_reported) {
      r.mission_done_reported = true;
      events_->Emit(t, kRouteDone,
                    EventFields{{"robot", r.entry->id},
                                {"length_m", RoundForJson(mission->path_length_m, 3)}});
    }
  }
}

void ScenarioRun::StepPhysics() {
  const auto t_physics = Clock::now();
  world_->Step();
  summary_.physics_s += Seconds(Clock::now() - t_physics);
}

void ScenarioRun::SenseRobots(const sim::TickSnapshot& next, double t_after) {
  // Each robot's sensors and stack for the tick that just ended, on the
  // tick's snapshot, each writing only its own slot, spread over the worker
  // pool; merged in robot order afterwards, so the outputs are the same for
  // any thread count. In the ticks between the lasers' sweeps (about 16 of 20
  // for 10 Hz scanners sweeping 20 ms, their sweeps in step) the robots only read
  // encoders and bumpers: the calls then run inline, and the planar slices
  // are not re-cut for casts nobody makes.
  const bool heavy = std::any_of(robots_.begin(), robots_.end(),
                                 [](const RobotRun& r) { return r.robot->HeavyTick(); });
  if (planar_ && heavy) planar_->Update();  // the slices are read-only until the next step
  const auto sense = [&](std::size_t k) {
    work_[k].outputs = robots_[k].robot->AfterStep(snapshot_.robots[k], next.robots[k]);
  };
  const auto think = [&](std::size_t k) {
    TickWork& w = work_[k];
    nav::SensorFrame frame;
    frame.now_s = t_after;
    frame.encoders = w.outputs.encoders;
    frame.bumpers = w.outputs.bumpers;
    for (const sim::ScanRecord& scan : w.outputs.scans) frame.scans.push_back(&scan.scan);
    for (const sim::ImageRecord& image : w.outputs.images) frame.images.push_back(&image.image);
    const auto t_think = Clock::now();
    w.sensed = robots_[k].navigator->Sense(frame);
    w.estimator_s = Seconds(Clock::now() - t_think);
  };
  if (!heavy) {
    for (std::size_t k = 0; k < robots_.size(); ++k) {
      sense(k);
      think(k);
    }
  } else if (planar_) {
    pool_->ParallelFor(robots_.size(), [&](std::size_t k) {
      sense(k);
      think(k);
    });
  } else {
    // Bullet serializes its ray casts (World::CastRay): threads would only
    // queue for the lock, so the scans are cast in order.
    for (std::size_t k = 0; k < robots_.size(); ++k) sense(k);
    pool_->ParallelFor(robots_.size(), think);
  }
}

void ScenarioRun::MergeRobot(std::size_t k, const sim::TickSnapshot& next, double t_after) {
  RobotRun& r = robots_[k];
  const TickWork& w = work_[k];
  const double step_m =
      (next.robots[k].pose.translation() - snapshot_.robots[k].pose.translation()).norm();
  r.tally.distance_m += step_m;
  if (r.social) r.social->Update(world_->step_s(), next.robots[k].pose, next.people);
  robot_step_m_[r.robot->index()] = step_m;
  if (r.relocalization) r.relocalization->OnStep(world_->step_s(), step_m);
  if (r.day) {
    const nav::Controller* controller = r.navigator->controller();
    const nav::NavigationFigures* navigation = controller ? controller->navigation() : nullptr;
    r.day->OnStep(t_after, world_->step_s(), next.robots[k].velocity_mps.norm(),
                  navigation ? navigation->still_s : 0.0);
  }
  if (expect_monitor_ && step_m > kMovingSpeedMps * world_->step_s()) {
    expect_monitor_->AddMotion(k, world_->step_s());
  }
  if (r.shadow_relocalization) r.shadow_relocalization->OnStep(world_->step_s(), step_m);
  for (const core::BumperReading& b : w.outputs.bumpers) {
    nlohmann::ordered_json zones = nlohmann::ordered_json::array();
    const auto& names = r.entry->config.bumpers;
    for (std::size_t z = 0; z < names.size(); ++z) {
      if (b.zones_in_contact & (1u << z)) zones.push_back(names[z].name);
    }
    if (!zones.empty()) ++r.tally.bumper_presses;
    events_->Emit(b.stamp_s, kBumper, EventFields{{"robot", r.entry->id}, {"zones", zones}});
  }
  for (const sim::ScanRecord& scan : w.outputs.scans) {
    ++r.tally.scans;
    if (scan.fallback) ++r.tally.fallback_scans;
    if (scan_log_) scan_log_->Append(r.entry->id, scan.scan, scan.truth);
  }
  // A controller's reaction to the scans holds from the next physics step.
  if (w.sensed.command)
    r.robot->SetWheelSpeeds(w.sensed.command->left_radps, w.sensed.command->right_radps);
  if (r.tracker) {
    if (w.sensed.cycle) {
      summary_.estimator_cycle_s += w.estimator_s;  // summed over robots: thread time
      ++summary_.estimator_cycles;
      RecordCycle(r, *w.sensed.cycle, next.robots[k].pose, t_after);
    } else {
      summary_.estimator_tick_s += w.estimator_s;
      ++summary_.estimator_ticks;
    }
  }
  if (r.shadow_tracker && w.sensed.shadow_cycle) {
    const LocalizationCycle& c = r.shadow_tracker->Record(
        *w.sensed.shadow_cycle, *r.navigator->shadow_estimator(), next.robots[k].pose, t_after);
    r.shadow_relocalization->OnCycle(t_after, c.mode, c.hypotheses, c.position_error_m,
                                     c.heading_error_rad);
  }
  for (RunObserver* observer : extensions_.observers) {
    observer->OnRobotOutputs(*r.entry, w.outputs, t_after);
  }
}

void ScenarioRun::RecordProximity(double t_after) {
  robot_poses_.clear();
  for (const sim::RobotState& r : snapshot_.robots) robot_poses_.push_back(r.pose);
  near_misses_.clear();
  station_conflicts_.clear();
  proximity_->Update(world_->step_s(), robot_poses_, &near_misses_, &station_conflicts_);
  for (const RobotProximity::NearMiss& n : near_misses_) {
    events_->Emit(t_after, kNearMiss,
                  EventFields{{"robot", robots_[n.a].entry->id},
                              {"with", robots_[n.b].entry->id},
                              {"distance_m", RoundForJson(n.distance_m, 4)}});
  }
  for (const RobotProximity::StationConflict& c : station_conflicts_) {
    nlohmann::ordered_json ids = nlohmann::ordered_json::array();
    for (int k : c.robots) ids.push_back(robots_[k].entry->id);
    events_->Emit(t_after, kStationConflict,
                  EventFields{{"station", watched_stations_[c.station]}, {"robots", ids}});
  }
}

bool ScenarioRun::RobotLeftFloor(double t_after) {
  const sim::Floor& floor = world_->description().floor;
  for (const RobotRun& r : robots_) {
    const core::Pose2& p = snapshot_.robots[r.robot->index()].pose;
    const Eigen::Vector2d xy = p.translation();
    if (xy.cwiseMax(floor.min_m) == xy && xy.cwiseMin(floor.max_m) == xy) continue;
    char text[160];
    std::snprintf(text, sizeof text, "robot '%s' left the floor at (%.2f, %.2f) at %.1f s",
                  r.entry->id.c_str(), p.x_m, p.y_m, t_after);
    summary_.ended_early = text;
    events_->Emit(t_after, kRobotLeftFloor,
                  EventFields{{"robot", r.entry->id},
                              {"pose",
                               {RoundForJson(p.x_m, 6), RoundForJson(p.y_m, 6),
                                RoundForJson(p.theta_rad, 6)}},
                              {"floor_min", {floor.min_m.x(), floor.min_m.y()}},
                              {"floor_max", {floor.max_m.x(), floor.max_m.y()}}});
    return true;
  }
  return false;
}

bool ScenarioRun::RoutesDone() const {
  bool any = false;
  for (const RobotRun& r : robots_) {
    const bool listed = r.entry->mission && !r.entry->mission->tour_stations;
    if (!r.entry->route && !listed) continue;
    any = true;
    const std::optional<nav::MissionStatus> mission = r.navigator->controller()->mission();
    if (!mission || !mission->done) return false;
  }
  return any;
}

RunSummary ScenarioRun::Finish() {
  const double sim_s = static_cast<double>(ticks_run_) * world_->step_s();
  EventFields finished =
      summary_.interrupted_by != 0
          ? EventFields{{"interrupted", true}, {"signal", summary_.interrupted_by}}
          : EventFields{};
  if (!summary_.ended_early.empty()) finished["ended_early"] = summary_.ended_early;
  events_->Emit(sim_s, kRunFinished, finished);
  events_->Flush();
  trajectories_->Flush();
  if (scan_log_) scan_log_->Close();
  if (localization_log_) localization_log_->Flush();
  // metrics.json: a function of scenario and seed only (metrics.md, schema 1).
  summary_.metrics = CollectMetrics(sim_s);
  summary_.metrics.interrupted = summary_.interrupted_by != 0;
  summary_.metrics.ended_early = summary_.ended_early;
  const nlohmann::ordered_json metrics_json = MetricsToJson(summary_.metrics);
  WriteFileAtomically((out_ / "metrics.json").string(), metrics_json.dump(2) + "\n");
  if (expect_monitor_) {
    summary_.expectations =
        EvaluateExpectations(scenario_.expectations, metrics_json, *expect_monitor_);
    // A run the world ended early did not show what its expectations ask of
    // the whole run, whatever its figures say.
    if (!summary_.ended_early.empty()) {
      summary_.expectations->results.push_back(
          ExpectationResult{.name = "the run reaches its end",
                            .status = ExpectationStatus::kFail,
                            .measured = FormatFigure(sim_s) + " s simulated",
                            .bound = FormatFigure(scenario_.duration_s) + " s",
                            .detail = summary_.ended_early});
    }
    WriteFileAtomically((out_ / "expectations.json").string(),
                        ExpectationsToJson(*summary_.expectations).dump(2) + "\n");
  }
  std::vector<RobotTracks> tracks;
  std::vector<RobotLocalization> localizations;
  for (const RobotRun& r : robots_) {
    tracks.push_back(r.tracks);
    tracks.back().truth = r.truth_path.items_and_last();
    tracks.back().odometry = r.odometry_path.items_and_last();
    tracks.back().estimate = r.estimate_path.items_and_last();
    if (const nav::Controller* c = r.navigator->controller())
      tracks.back().navigation = c->picture();
    if (r.tracker) localizations.push_back({r.entry->id, &*r.tracker});
  }
  std::vector<std::vector<Eigen::Vector2d>> body_paths;
  for (const auto& b : body_tracks_) body_paths.push_back(b.items_and_last());
  WriteSnapshotsAndReport(
      out_, scenario_, *world_, body_paths, tracks, localizations, summary_.metrics,
      crowd_strip_ ? &*crowd_strip_ : nullptr, visitors_present_ ? &*visitors_present_ : nullptr,
      summary_.expectations ? &*summary_.expectations : nullptr,
      first_deadlock_ ? &*first_deadlock_ : nullptr, snapshots_ ? &snapshots_->frames() : nullptr);
  summary_.sim_duration_s = sim_s;
  summary_.robot_sim_s = sim_s * static_cast<double>(robots_.size());
  summary_.ticks = ticks_run_;
  summary_.wall_time_s = Seconds(Clock::now() - t_start_);
  summary_.real_time_factor = summary_.loop_s > 0 ? sim_s / summary_.loop_s : 0.0;
  for (const RobotRun& r : robots_) {
    for (const sim::LaserScanner& laser : r.robot->lasers())
      summary_.laser_rays += laser.rays_cast();
  }
  summary_.peak_rss_mb = PeakRssMb();
  summary_.events = summary_.metrics.events();
  summary_.laser_fallback_scans = summary_.metrics.fallback_scans();
  WritePerformanceJson(out_, summary_, pool_->threads(), ToString(scenario_.laser_backend));
  return summary_;
}

}  // namespace detail

RunSummary RunScenario(const Scenario& scenario, const RunOptions& options,
                       const RunExtensions& extensions) {
  detail::ScenarioRun run(scenario, options, extensions);
  run.Run();
  return run.Finish();
}

}  // namespace pavilion::scenarios
