#include "scenarios/run/scenario_runner.h"

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
#include "scenarios/metrics/collision_classes.h"
#include "scenarios/metrics/localization_tracker.h"
#include "scenarios/metrics/relocalization_tracker.h"
#include "scenarios/metrics/social_navigation.h"
#include "scenarios/output/crowd_strip.h"
#include "scenarios/output/run_logs.h"
#include "scenarios/output/run_outputs.h"
#include "scenarios/output/scan_log.h"
#include "scenarios/run/body_spawner.h"
#include "scenarios/run/progress_line.h"
#include "scenarios/run/robot_stack.h"
#include "scenarios/version.h"
#include "sim/raycast/planar_caster.h"
#include "sim/runtime/schedule.h"
#include "sim/runtime/worker_pool.h"

namespace pavilion::scenarios {
namespace {

using Clock = std::chrono::steady_clock;

// Events are due when their time is reached up to this rounding of tick times (s).
constexpr double kDueToleranceS = 1e-9;
constexpr double kDegPerRad = 180.0 / std::numbers::pi;
// A walker that touched a robot stands this long after the contact ends (s):
// long enough for its random walk to give up the leg (RandomWalkOptions::
// blocked_s) and turn elsewhere instead of walking straight back into it.
constexpr double kWalkerContactPauseS = 3.0;
// A walker heading for a robot stops this far (m) from the robot's bounding
// circle, as a person would in front of a moving machine: a blind walk into
// it at 0.8 m/s would leave the robot less than its braking distance (about
// 0.25 m at 0.6 m/s) and make every such meeting a collision.
constexpr double kWalkerMeetGapM = 0.3;
// Approach speeds (m/s) closer than this count as neither moving into the other.
constexpr double kApproachTieMps = 0.01;

double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }

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
  RobotMetrics tally;
  RobotTracks tracks;
  bool mission_done_reported = false;
  bool kidnapped = false;  // a kidnap happened: its hypotheses are pictured
};

// What a robot's work of a tick produced (its own slot: written by one thread).
struct TickWork {
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
  void SenseRobots(const sim::TickSnapshot& next, double t_after);
  void MergeRobot(std::size_t k, const sim::TickSnapshot& next, double t_after);
  void RecordCycle(RobotRun& r, const nav::EstimatorCycle& cycle, const core::Pose2& truth,
                   double t_after);
  void RecordTrajectories(double t);
  bool RoutesDone() const;
  void BuildCollisionClasses();
  RunMetrics CollectMetrics(double sim_s) const;

  const Scenario& scenario_;
  const RunOptions& options_;
  const RunExtensions& extensions_;
  std::filesystem::path out_;
  Clock::time_point t_start_;
  std::unique_ptr<sim::World> world_;
  std::vector<std::unique_ptr<sim::BodyMotion>> motions_;
  std::vector<sim::PlanarVelocity> body_commands_;  // this tick's, by body
  std::unique_ptr<sim::PlanarCaster> planar_;
  std::map<std::string, int> body_index_;
  std::map<std::string, int> robot_index_;  // world robot index by id
  std::vector<RobotRun> robots_;
  std::vector<TickWork> work_;
  std::unique_ptr<sim::WorkerPool> pool_;
  // Body (robot) index of each world element, -1 for others.
  std::vector<int> body_of_element_;
  std::vector<int> robot_of_element_;
  std::vector<int> person_of_element_;   // the crowd's people, -1 for other elements
  std::vector<std::string> person_ids_;  // by person
  std::vector<BodyMetrics> body_tally_;
  std::unique_ptr<CollisionClassifier> collision_classes_;
  std::vector<bool> visitor_body_;                // random walkers: the crowd's stand-ins
  std::vector<int> robot_contacts_;               // by body: contacts with a robot right now
  std::vector<double> walker_paused_until_s_;     // by body: stands until then after a contact
  std::vector<double> robot_radius_m_;            // by robot: its footprint\'s bounding circle
  std::vector<nav::NavigationEvent> nav_events_;  // scratch
  std::vector<std::vector<Eigen::Vector2d>> body_tracks_;
  std::optional<CrowdTracker> crowd_tracker_;  // runs with a crowd
  std::optional<CrowdStrip> crowd_strip_;      // frames of the crowd around the first robot
  std::unique_ptr<EventLog> events_;
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
  world_ = std::make_unique<sim::World>(std::move(description), scenario.physics);
  // Maps before any body enters the world (a derived map is a survey of the
  // static geometry).
  std::vector<std::optional<core::RobotMap>> maps(scenario.robots.size());
  for (std::size_t k = 0; k < scenario.robots.size(); ++k) {
    if (NeedsMap(scenario.robots[k])) maps[k] = LoadRobotMap(scenario.robots[k], scenario, *world_);
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
  }
  OpenLogs();
  pool_ = std::make_unique<sim::WorkerPool>(
      options.threads > 0 ? options.threads : sim::WorkerPool::HardwareThreads());
}

void ScenarioRun::BuildRobots(std::vector<sim::RobotConfig> configs,
                              const std::vector<std::optional<core::RobotMap>>& maps) {
  robots_.resize(scenario_.robots.size());
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
    run.navigator = MakeNavigator(scenario_, k, maps[k]);
    if (run.navigator->estimator()) {
      run.tracker.emplace();
      run.relocalization.emplace();
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
  trajectories_ = std::make_unique<TrajectoryLog>((out_ / "trajectories.csv").string());
  const bool any_localization = std::any_of(
      robots_.begin(), robots_.end(), [](const RobotRun& r) { return r.tracker.has_value(); });
  if (any_localization) {
    localization_log_ = std::make_unique<LocalizationLog>((out_ / "localization.csv").string());
  }
  if (scenario_.outputs.scan_log && !robots_.empty()) {
    std::vector<std::string> ids;
    for (const auto& e : world_->elements()) ids.push_back(e.id);
    scan_log_ = std::make_unique<ScanLogWriter>((out_ / "scans.bin").string(), ids);
  }
  const auto& elements = world_->elements();
  body_tally_.resize(world_->body_count());
  body_tracks_.resize(world_->body_count());
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
  robot_contacts_.assign(world_->body_count(), 0);
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
  events_->Emit(0.0, "run_started",
                EventFields{{"scenario", scenario_.name},
                            {"seed", scenario_.seed},
                            {"bodies", world_->body_count()},
                            {"robots", static_cast<int>(robots_.size())}});
  RecordTrajectories(0.0);
  const double dt = world_->step_s();
  const auto total_ticks = static_cast<std::int64_t>(std::llround(scenario_.duration_s / dt));
  sim::PeriodicSchedule schedule(scenario_.physics.physics_rate_hz);
  const int trajectory_task =
      schedule.Add("outputs.trajectory_rate_hz", scenario_.outputs.trajectory_rate_hz);
  const bool people_rows = world_->crowd() && scenario_.outputs.people_rate_hz > 0.0;
  const int people_task =
      people_rows ? schedule.Add("outputs.people_rate_hz", scenario_.outputs.people_rate_hz) : -1;
  if (people_rows) trajectories_->AddPeople(0.0, snapshot_.people, person_ids_);
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
    snapshot_ = std::move(next);
    if (crowd_strip_ && crowd_strip_->Due(t_after)) {
      crowd_strip_->Capture(*world_, CrowdStripCentre(*world_), t_after);
    }
    if (schedule.IsDue(trajectory_task, tick + 1)) RecordTrajectories(t_after);
    if (people_rows && schedule.IsDue(people_task, tick + 1)) {
      trajectories_->AddPeople(t_after, snapshot_.people, person_ids_);
    }
    if ((tick & 255) == 0) progress.Update(t_after, Seconds(Clock::now() - t_loop));
    ticks_run_ = tick + 1;
    if (scenario_.end_when_routes_done && RoutesDone()) break;
  }
  progress.Done();
  summary_.loop_s = Seconds(Clock::now() - t_loop);
  summary_.loop_cpu_s = ProcessCpuSeconds() - cpu_start_s;
}

void ScenarioRun::ApplyEvents(double t) {
  // Scripted events due by this tick happen before it is stepped; processes
  // started before (random kidnaps by distance) act first, on the last step.
  kidnaps_.clear();
  EventContext context{world_.get(),         &robot_index_,  &body_index_, &snapshot_,
                       event_streams_.get(), &robot_step_m_, &kidnaps_,    {}};
  context.set_laser_fault = [this](const std::string& robot, const std::string& sensor,
                                   const sim::LaserFault& fault) {
    for (RobotRun& r : robots_) {
      if (r.entry->id == robot) return r.robot->SetLaserFault(sensor, fault);
    }
    return false;
  };
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
      if (r.robot->index() == kidnap.robot) r.kidnapped = true;
      if (r.robot->index() == kidnap.robot && r.relocalization) r.relocalization->OnKidnap(t);
      if (r.robot->index() == kidnap.robot && r.shadow_relocalization) {
        r.shadow_relocalization->OnKidnap(t);
      }
    }
  }
}

void ScenarioRun::EmitScripted(double t, const ScenarioEvent& e, const EventFields& fields) {
  if (!fields.is_null()) events_->Emit(t, e.type(), fields);
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
    // shove it into an exhibit (issue 14).
    const bool stop =
        visitor_body_[b] && (robot_contacts_[b] > 0 || t < walker_paused_until_s_[b] ||
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
  for (RobotRun& r : robots_) {
    const auto t_control = Clock::now();
    const std::optional<nav::WheelSpeeds> command = r.navigator->Control(tick, t);
    summary_.control_s += Seconds(Clock::now() - t_control);
    if (command) r.robot->SetWheelSpeeds(command->left_radps, command->right_radps);
    const nav::Controller* controller = r.navigator->controller();
    const std::optional<nav::MissionStatus> mission =
        controller ? controller->mission() : std::nullopt;
    EmitNavigationEvents(r);
    if (r.entry->route && mission && mission->done && !r.mission_done_reported) {
      r.mission_done_reported = true;
      events_->Emit(t, "route_done",
                    EventFields{{"robot", r.entry->id},
                                {"length_m", RoundForJson(mission->path_length_m, 3)}});
    }
  }
}

void ScenarioRun::EmitNavigationEvents(RobotRun& r) {
  nav::Controller* controller = r.navigator->mutable_controller();
  if (!controller) return;
  nav_events_.clear();
  controller->TakeEvents(&nav_events_);
  for (const nav::NavigationEvent& e : nav_events_) {
    EventFields fields{{"robot", r.entry->id}, {"mission", e.mission}, {"goal", e.goal}};
    if (e.type == nav::NavigationEvent::Type::kMissionAborted) {
      fields["reason"] = nav::ToString(e.reason);
    }
    if (e.type == nav::NavigationEvent::Type::kMissionCompleted ||
        e.type == nav::NavigationEvent::Type::kMissionAborted) {
      fields["duration_s"] = RoundForJson(e.duration_s, 3);
      fields["path_length_m"] = RoundForJson(e.path_length_m, 3);
    }
    if (e.type == nav::NavigationEvent::Type::kReplanned) fields["cause"] = e.cause;
    events_->Emit(e.at_s, nav::ToString(e.type), fields);
  }
}

void ScenarioRun::StepPhysics() {
  const auto t_physics = Clock::now();
  world_->Step();
  summary_.physics_s += Seconds(Clock::now() - t_physics);
}

void ScenarioRun::RecordContacts(double t_after) {
  const auto& elements = world_->elements();
  for (const sim::ContactChange& c : world_->TakeContactChanges()) {
    ClassifyContact(c, t_after);
    if (!c.began) continue;
    for (int element : {c.a, c.b}) {
      if (body_of_element_[element] >= 0) ++body_tally_[body_of_element_[element]].collisions;
      if (robot_of_element_[element] >= 0) ++robots_[robot_of_element_[element]].tally.collisions;
    }
    events_->Emit(t_after, "collision",
                  EventFields{{"a", elements[c.a].id},
                              {"b", elements[c.b].id},
                              {"impulse_ns", RoundForJson(c.impulse_ns)},
                              {"point_m",
                               {RoundForJson(c.point_m.x(), 4), RoundForJson(c.point_m.y(), 4),
                                RoundForJson(c.point_m.z(), 4)}}});
  }
}

void ScenarioRun::ClassifyContact(const sim::ContactChange& c, double t_after) {
  const int ra = robot_of_element_[c.a];
  const int rb = robot_of_element_[c.b];
  // Walkers touching a robot (they stop meanwhile).
  for (auto [robot, other] : {std::pair{ra, c.b}, std::pair{rb, c.a}}) {
    const int body = body_of_element_[other];
    if (robot >= 0 && body >= 0 && visitor_body_[body]) {
      robot_contacts_[body] += c.began ? 1 : -1;
      walker_paused_until_s_[body] = t_after + kWalkerContactPauseS;
    }
  }
  if (!c.began || (ra >= 0 && ra == rb)) return;
  // Who moved into whom: the larger speed towards the contact point.
  const Eigen::Vector2d at = c.point_m.head<2>();
  const auto approach = [&](int element) {
    Eigen::Vector2d position, velocity;
    if (robot_of_element_[element] >= 0) {
      const sim::RobotState& s = snapshot_.robots[robot_of_element_[element]];
      position = s.pose.translation();
      velocity = s.velocity_mps;
    } else if (body_of_element_[element] >= 0) {
      const sim::BodyState& s = snapshot_.bodies[body_of_element_[element]];
      position = s.pose.translation();
      velocity = s.velocity_mps;
    } else if (person_of_element_[element] >= 0) {
      const sim::crowd::PersonState& s = snapshot_.people[person_of_element_[element]];
      position = s.position_m;
      velocity = s.velocity_mps;
    } else {
      return 0.0;
    }
    const Eigen::Vector2d d = at - position;
    return d.norm() > 0.0 ? velocity.dot(d.normalized()) : 0.0;
  };
  for (auto [robot, self, other] : {std::tuple{ra, c.a, c.b}, std::tuple{rb, c.b, c.a}}) {
    if (robot < 0) continue;
    CollisionCounts& counts = robots_[robot].tally.collisions_by_class;
    const CollisionClass kind = collision_classes_->Classify(other);
    ++counts.by_class[static_cast<std::size_t>(kind)];
    // A tie (both at rest: a resting contact flickering) is not the robot's doing.
    const bool robot_moved = approach(self) > approach(other) + kApproachTieMps;
    if (kind == CollisionClass::kVisitor) {
      ++(robot_moved ? counts.robot_into_visitor : counts.visitor_into_robot);
    } else if (kind == CollisionClass::kRobot) {
      ++(robot_moved ? counts.robot_into_robot : counts.robot_hit_by_robot);
    }
  }
}

void ScenarioRun::SenseRobots(const sim::TickSnapshot& next, double t_after) {
  // Each robot's sensors and stack for the tick that just ended, on the
  // tick's snapshot, each writing only its own slot, spread over the worker
  // pool; merged in robot order afterwards, so the outputs are the same for
  // any thread count.
  if (planar_) planar_->Update();  // the slices are read-only until the next step
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
    const auto t_think = Clock::now();
    w.sensed = robots_[k].navigator->Sense(frame);
    w.estimator_s = Seconds(Clock::now() - t_think);
  };
  if (planar_) {
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
  if (r.shadow_relocalization) r.shadow_relocalization->OnStep(world_->step_s(), step_m);
  for (const core::BumperReading& b : w.outputs.bumpers) {
    nlohmann::ordered_json zones = nlohmann::ordered_json::array();
    const auto& names = r.entry->config.bumpers;
    for (std::size_t z = 0; z < names.size(); ++z) {
      if (b.zones_in_contact & (1u << z)) zones.push_back(names[z].name);
    }
    if (!zones.empty()) ++r.tally.bumper_presses;
    events_->Emit(b.stamp_s, "bumper", EventFields{{"robot", r.entry->id}, {"zones", zones}});
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

void ScenarioRun::RecordCycle(RobotRun& r, const nav::EstimatorCycle& cycle,
                              const core::Pose2& truth, double t_after) {
  const nav::PoseEstimator& estimator = *r.navigator->estimator();
  const LocalizationCycle& c = r.tracker->Record(cycle, estimator, truth, t_after);
  localization_log_->Add(r.entry->id, static_cast<std::int64_t>(r.tracker->cycles().size()) - 1, c);
  const RelocalizationChange change = r.relocalization->OnCycle(
      t_after, c.mode, c.hypotheses, c.position_error_m, c.heading_error_rad);
  const auto error_fields = [&](EventFields fields) {
    fields["position_error_m"] = RoundForJson(c.position_error_m, 4);
    fields["heading_error_deg"] = RoundForJson(c.heading_error_rad * kDegPerRad, 3);
    return fields;
  };
  // The largest hypothesis set after a kidnap, for the report's picture.
  const std::size_t pictured = r.tracks.hypotheses ? r.tracks.hypotheses->hypotheses.size() : 0;
  if (r.kidnapped && c.mode == nav::LocalizationMode::kNotLocalized &&
      static_cast<std::size_t>(c.hypotheses) > pictured) {
    r.tracks.hypotheses = HypothesisSnapshot{t_after, truth, estimator.hypotheses()};
  }
  if (change.hypotheses_changed) {
    events_->Emit(t_after, "hypotheses",
                  EventFields{{"robot", r.entry->id},
                              {"n", c.hypotheses},
                              {"mode", nav::LocalizationModeName(c.mode)}});
  }
  // A lost situation (metrics.md: the truth's or the estimator's) begins, or
  // the estimator declares itself lost during one.
  if (r.tracker->lost_started() || change.lost) {
    const bool declared = c.mode == nav::LocalizationMode::kLost;
    events_->Emit(
        t_after, "lost",
        error_fields({{"robot", r.entry->id},
                      {"reason", declared ? estimator.lost_reason() : r.tracker->lost_reason()},
                      {"declared", declared}}));
  }
  if (change.localized) {
    events_->Emit(t_after, "localized",
                  EventFields{{"robot", r.entry->id}, {"hypotheses", c.hypotheses}});
  }
  if (change.relocalized) {
    events_->Emit(t_after, "relocalized",
                  error_fields({{"robot", r.entry->id}, {"correct", change.correct}}));
  }
}

void ScenarioRun::RecordTrajectories(double t) {
  for (int b = 0; b < world_->body_count(); ++b) {
    const core::Pose2& p = snapshot_.bodies[b].pose;
    trajectories_->AddBody(t, world_->body_spec(b).id, p);
    body_tracks_[b].push_back(p.translation());
  }
  for (std::size_t k = 0; k < robots_.size(); ++k) {
    RobotRun& r = robots_[k];
    const core::Pose2& p = snapshot_.robots[k].pose;
    const core::Pose2& o = r.navigator->odometry_pose();
    const nav::PoseEstimator* estimator = r.navigator->estimator();
    trajectories_->AddRobot(t, r.entry->id, p, o, estimator ? &estimator->estimate() : nullptr);
    if (estimator) r.tracks.estimate.push_back(estimator->estimate().pose.translation());
    r.tracks.truth.push_back(p.translation());
    r.tracks.odometry.push_back(o.translation());
  }
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

RunMetrics ScenarioRun::CollectMetrics(double sim_s) const {
  RunMetrics m;
  m.scenario = scenario_.name;
  m.seed = scenario_.seed;
  m.pavilion_version = kVersion;
  m.world = scenario_.world.name;
  m.sim_duration_s = sim_s;
  m.physics_rate_hz = scenario_.physics.physics_rate_hz;
  m.ticks = ticks_run_;
  m.bodies = body_tally_;
  m.laser_backend = ToString(scenario_.laser_backend);
  m.event_counts = events_->counts();
  for (std::size_t k = 0; k < robots_.size(); ++k) {
    const RobotRun& r = robots_[k];
    RobotMetrics robot = r.tally;
    robot.id = r.entry->id;
    robot.model = r.entry->config.description.model;
    const core::Pose2& truth = snapshot_.robots[k].pose;
    const core::Pose2& odo = r.navigator->odometry_pose();
    robot.odometry_final_position_error_m = (odo.translation() - truth.translation()).norm();
    robot.odometry_final_heading_error_rad =
        std::abs(core::NormalizeAngle(odo.theta_rad - truth.theta_rad));
    if (r.tracker) robot.localization = r.tracker->Figures();
    if (const nav::PoseEstimator* estimator = r.navigator->estimator()) {
      robot.estimator_counters = estimator->counters();
    }
    if (r.relocalization && r.relocalization->active()) {
      robot.relocalization = r.relocalization->Figures();
    }
    if (r.social && r.social->active()) robot.social = r.social->Figures();
    if (r.shadow_tracker) {
      robot.shadow = RobotMetrics::Shadow{"mcl", r.shadow_tracker->Figures(), std::nullopt};
      if (r.shadow_relocalization->active()) {
        robot.shadow->relocalization = r.shadow_relocalization->Figures();
      }
    }
    const nav::Controller* controller = r.navigator->controller();
    if (controller && controller->navigation()) robot.navigation = *controller->navigation();
    if (r.entry->route) {
      const nav::MissionStatus mission = *r.navigator->controller()->mission();
      robot.route = RouteMetrics{r.entry->route->stops, mission.path_length_m, mission.done,
                                 mission.done ? mission.done_at_s : sim_s};
    }
    m.robots.push_back(std::move(robot));
  }
  if (crowd_tracker_) m.crowd = crowd_tracker_->Figures();
  return m;
}

RunSummary ScenarioRun::Finish() {
  const double sim_s = static_cast<double>(ticks_run_) * world_->step_s();
  events_->Emit(sim_s, "run_finished");
  events_->Flush();
  trajectories_->Flush();
  if (scan_log_) scan_log_->Close();
  if (localization_log_) localization_log_->Flush();
  // metrics.json: a function of scenario and seed only (metrics.md, schema 1).
  summary_.metrics = CollectMetrics(sim_s);
  WriteFileAtomically((out_ / "metrics.json").string(),
                      MetricsToJson(summary_.metrics).dump(2) + "\n");
  std::vector<RobotTracks> tracks;
  std::vector<RobotLocalization> localizations;
  for (const RobotRun& r : robots_) {
    tracks.push_back(r.tracks);
    if (const nav::Controller* c = r.navigator->controller())
      tracks.back().navigation = c->picture();
    if (r.tracker) localizations.push_back({r.entry->id, &*r.tracker});
  }
  WriteSnapshotsAndReport(out_, scenario_, *world_, body_tracks_, tracks, localizations,
                          summary_.metrics, crowd_strip_ ? &*crowd_strip_ : nullptr);
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

}  // namespace

RunSummary RunScenario(const Scenario& scenario, const RunOptions& options,
                       const RunExtensions& extensions) {
  ScenarioRun run(scenario, options, extensions);
  run.Run();
  return run.Finish();
}

}  // namespace pavilion::scenarios
