#include "nav/mission/navigation_controller.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "core/geometry/segment2.h"
#include "nav/local/nf1.h"
#include "nav/reactive/swept_polygon.h"

namespace pavilion::nav {
namespace {

constexpr double kMaxStartS = 1e7;
constexpr double kMaxTimeoutS = 1e6;
// How long (s) the chosen dynamic-window arc is drawn ahead.
constexpr double kArcDrawS = 2.0;
// A clipped contour keeps this much more than the window's safety margin from
// the hull, so that its points are not on the margin's edge, m.
constexpr double kClipSlackM = 0.01;
// A contour this close to the hull blocks it as an overlap does (the
// window's 2 cm safety margin and a few centimetres of the estimate), m.
constexpr double kDeadlockTouchM = 0.05;
// The deadlock rule's yield aims this far away (about one and a half Robox
// lengths), m.
constexpr double kRetreatM = 1.0;
// While the deadlock rule clips, the blind-zone memory keeps this much, s:
// the rule's retreat delay; the robots in the deadlock are their contours.
constexpr double kDeadlockMemoryS = 2.0;
// A robot that stayed within this of where it was stood still (the
// longest_still_s figure): net displacement, so that a dither back and forth
// is not progress, m.
constexpr double kStillMoveM = 0.3;

void Require(bool ok, const std::string& field, const std::string& range) {
  if (!ok) {
    throw std::invalid_argument("NavigationControllerOptions." + field + " must be " + range);
  }
}

std::int64_t PeriodTicks(double step_s, double rate_hz) {
  return std::max<std::int64_t>(1, std::llround(1.0 / (rate_hz * step_s)));
}

// SplitMix64: one seed per plan from the robot's seed and the plan's number.
std::uint64_t PlanSeed(std::uint64_t seed, std::uint64_t plan) {
  std::uint64_t z = seed + 0x9e3779b97f4a7c15ULL * (plan + 1);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

std::unique_ptr<InitialPathPlanner> MakeInitialPlanner(const NavigationControllerOptions& o) {
  switch (o.initial_planner) {
    case InitialPlanner::kNf1:
      return std::make_unique<Nf1Planner>();
    case InitialPlanner::kOmplRrtConnect: {
      OmplPlannerOptions ompl = o.ompl;
      ompl.type = OmplPlannerType::kRrtConnect;
      return std::make_unique<OmplPathPlanner>(ompl);
    }
    case InitialPlanner::kOmplRrtStar: {
      OmplPlannerOptions ompl = o.ompl;
      ompl.type = OmplPlannerType::kRrtStar;
      return std::make_unique<OmplPathPlanner>(ompl);
    }
  }
  throw std::invalid_argument("NavigationControllerOptions.initial_planner is unknown");
}

// Points a pressed bumper zone puts on the outline (over its bearings).
constexpr int kBumperPointsPerZone = 4;

// The point of a convex outline (about the origin) at `bearing_rad`, moved in
// by a millimetre: a contact.
Eigen::Vector2d OutlineAt(const std::vector<Eigen::Vector2d>& outline, double bearing_rad) {
  constexpr double kInsideM = 1e-3;
  const Eigen::Vector2d dir(std::cos(bearing_rad), std::sin(bearing_rad));
  // A ray from the origin twice the circumradius long leaves the outline once.
  const Eigen::Vector2d end = 2.0 * Circumradius(outline) * dir;
  double t = 0.0;
  for (std::size_t i = 0; i < outline.size(); ++i) {
    const double hit = core::RaySegmentHit(Eigen::Vector2d::Zero(), end, outline[i],
                                           outline[(i + 1) % outline.size()]);
    if (std::isfinite(hit)) t = std::max(t, hit);
  }
  return std::max(0.0, t * end.norm() - kInsideM) * dir;
}

}  // namespace

void EscapeOptions::Validate() const {
  const auto require = [](bool ok, const std::string& field, const std::string& range) {
    if (!ok) throw std::invalid_argument("EscapeOptions." + field + " must be " + range);
  };
  require(after_s >= 0.0 && after_s <= 3600.0, "after_s", "in [0, 3600] s");
  require(still_m > 0.0 && still_m <= 5.0, "still_m", "in (0, 5] m");
  require(drive_s > 0.0 && drive_s <= 60.0, "drive_s", "in (0, 60] s");
  require(leave_m > 0.0 && leave_m <= 5.0, "leave_m", "in (0, 5] m");
  require(min_free_m > 0.0 && min_free_m <= 5.0, "min_free_m", "in (0, 5] m");
  require(speed_mps > 0.0 && speed_mps <= 2.0, "speed_mps", "in (0, 2] m/s");
  require(remember_s >= 0.0 && remember_s <= 3600.0, "remember_s", "in [0, 3600] s");
  require(mark_radius_m > 0.0 && mark_radius_m <= 1.0, "mark_radius_m", "in (0, 1] m");
}

void UncertaintyOptions::Validate() const {
  const auto require = [](bool ok, const std::string& field, const std::string& range) {
    if (!ok) throw std::invalid_argument("UncertaintyOptions." + field + " must be " + range);
  };
  require(reach_m >= 0.0 && reach_m <= 10.0, "reach_m", "in [0, 10] m");
  require(stop_m >= 0.0 && stop_m <= 10.0, "stop_m", "in [0, 10] m (0: off)");
  require(slow_m >= 0.0 && (stop_m == 0.0 || slow_m < stop_m), "slow_m", "in [0, stop_m) m");
  require(hold_max_s > 0.0 && hold_max_s <= 3600.0, "hold_max_s", "in (0, 3600] s");
  require(crawl_mps > 0.0 && crawl_mps <= 2.0, "crawl_mps", "in (0, 2] m/s");
}

void NavigationControllerOptions::Validate() const {
  Require(step_s > 0.0 && step_s <= 1.0, "step_s", "in (0, 1] s");
  Require(start_s >= 0.0 && start_s <= kMaxStartS, "start_s", "in [0, 1e7] s");
  Require(dwa_rate_hz >= 1.0 && dwa_rate_hz <= 1000.0, "dwa_rate_hz", "in [1, 1000] Hz");
  Require(band_rate_hz >= 0.1 && band_rate_hz <= 100.0, "band_rate_hz", "in [0.1, 100] Hz");
  Require(dwell_s >= 0.0 && dwell_s <= 3600.0, "dwell_s", "in [0, 3600] s");
  Require(timeout_s > 0.0 && timeout_s <= kMaxTimeoutS, "timeout_s", "in (0, 1e6] s");
  Require(dwa_reach_m > 0.0 && dwa_reach_m <= 20.0, "dwa_reach_m", "in (0, 20] m");
  Require(band_lookahead_m > 0.0 && band_lookahead_m <= 10.0, "band_lookahead_m", "in (0, 10] m");
  Require(approach_radius_m > 0.0 && approach_radius_m <= 5.0, "approach_radius_m", "in (0, 5] m");
  Require(blocked_node_cost_m >= 0.0 && blocked_node_cost_m <= 1e4, "blocked_node_cost_m",
          "in [0, 1e4] m");
  Require(relocalization_timeout_s >= 0.0 && relocalization_timeout_s <= 3600.0,
          "relocalization_timeout_s", "in [0, 3600] s");
  Require(bumper_hold_s >= 0.0 && bumper_hold_s <= 60.0, "bumper_hold_s", "in [0, 60] s");
  Require(contour_hold_s >= 0.0 && contour_hold_s <= 10.0, "contour_hold_s", "in [0, 10] s");
  Require(mapped_beacon_m >= 0.0 && mapped_beacon_m <= 2.0, "mapped_beacon_m", "in [0, 2] m");
  Require(explained_m >= 0.0 && explained_m <= 2.0, "explained_m", "in [0, 2] m");
  Require(lost_hull_margin_m >= 0.0 && lost_hull_margin_m <= 2.0, "lost_hull_margin_m",
          "in [0, 2] m");
  robot_contours.Validate();
  deadlock.Validate();
  Require(fleet_replan_s >= 0.1 && fleet_replan_s <= 600.0, "fleet_replan_s", "in [0.1, 600] s");
  Require(station_wait_s >= 0.0 && station_wait_s <= 3600.0, "station_wait_s", "in [0, 3600] s");
  Require(seen_station_look_m >= 0.0 && seen_station_look_m <= 20.0, "seen_station_look_m",
          "in [0, 20] m");
  Require(fleet_commit_s >= fleet_replan_s && fleet_commit_s <= 600.0, "fleet_commit_s",
          "in [fleet_replan_s, 600] s");
  Require(fleet_replan_gain_m >= 0.0 && fleet_replan_gain_m <= 1e4, "fleet_replan_gain_m",
          "in [0, 1e4] m");
  Require(fleet_station_clear_m >= 0.0 && fleet_station_clear_m <= 5.0, "fleet_station_clear_m",
          "in [0, 5] m");
  Require(fleet_claim_margin_m >= 0.0 && fleet_claim_margin_m <= 2.0, "fleet_claim_margin_m",
          "in [0, 2] m");
  Require(fleet_hull_sigmas >= 0.0 && fleet_hull_sigmas <= 5.0, "fleet_hull_sigmas", "in [0, 5]");
  Require(fleet_hull_margin_m >= 0.0 && fleet_hull_margin_m <= 0.5, "fleet_hull_margin_m",
          "in [0, 0.5] m");
  ghost_barrier.Validate();
  explore.Validate();
  escape.Validate();
  uncertainty.Validate();
  ompl.Validate();
  local.Validate();
  dwa.Validate();
  queue.Validate();
  blocked.Validate();
  graph.Validate();
}

NavigationController::NavigationController(core::RobotMap map,
                                           std::vector<Eigen::Vector2d> footprint_in_robot,
                                           MissionSequence missions,
                                           const NavigationControllerOptions& options)
    : options_(options),
      map_(std::move(map)),
      footprint_(std::move(footprint_in_robot)),
      missions_(std::move(missions)),
      graph_(map_),
      obstacles_(footprint_, GhostPositions(map_), /*blind_memory_s=*/1.0, options.ghost_barrier),
      dwa_(options.dwa, footprint_),
      queue_(options.queue),
      blocked_(options.blocked),
      deadlock_(options.deadlock, options.seed) {
  options_.Validate();
  walls_ = MapWalls(map_);
  if (options_.blind_map_outline) {
    obstacles_.SetMapOutline(
        MapOutline(map_, kOutlineSpacingM, options_.ghost_barrier.clearance_m));
  }
  for (const core::MapBeacon& b : map_.beacons) map_beacons_.push_back(b.point.position_m);
  for (const std::string& id : options_.rest_among) {
    const std::optional<int> n = graph_.FindIndex(id);
    if (!n) throw std::invalid_argument("rest_among: unknown node '" + id + "' of the map");
    rest_nodes_.push_back(*n);
  }
  queue_.SetWalls(walls_, options_.local.band.robot_radius_m);
  local_ = std::make_unique<LocalPlanner>(options_.local, MakeInitialPlanner(options_));
  dwa_period_ticks_ = PeriodTicks(options_.step_s, options_.dwa_rate_hz);
  band_period_ticks_ = PeriodTicks(options_.step_s, options_.band_rate_hz);
  figures_.min_clearance_m = std::numeric_limits<double>::infinity();
  circumradius_m_ = Circumradius(footprint_);
  margin_outline_ = InflateConvexPolygon(footprint_, options_.dwa.safety_margin_m);
  inradius_m_ = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < footprint_.size(); ++i) {
    inradius_m_ =
        std::min(inradius_m_, core::PointSegmentDistance(Eigen::Vector2d::Zero(), footprint_[i],
                                                         footprint_[(i + 1) % footprint_.size()]));
  }
}

NavigationController::~NavigationController() = default;

std::optional<WheelSpeeds> NavigationController::OnScan(const core::LaserScan& scan,
                                                        const ScanContext& context) {
  obstacles_.AddScan(scan, context.odometry);
  if (!options_.see_robots) return std::nullopt;
  // This laser's new view replaces what it saw before; markers it saw that
  // now lie in a blind zone (outside its bearings) are held a while.
  const std::vector<SeenRobot> seen = SeeRobots(scan, options_.robot_contours);
  const core::Pose2 sensor_from_odom = (context.odometry * scan.robot_from_sensor).Inverse();
  const double first = scan.readings.empty() ? 0.0 : scan.readings.front().bearing_rad;
  const double last = scan.readings.empty() ? 0.0 : scan.readings.back().bearing_rad;
  std::erase_if(markers_, [&](const SeenMarker& m) {
    if (context.now_s - m.seen_s > options_.contour_hold_s) return true;
    if (m.laser != scan.sensor_id) return false;
    const Eigen::Vector2d p = sensor_from_odom * m.marker_in_odom;
    const double bearing = std::atan2(p.y(), p.x());
    return bearing >= std::min(first, last) && bearing <= std::max(first, last);
  });
  for (const SeenRobot& r : seen) {
    markers_.push_back({context.odometry * r.marker_in_robot, context.odometry * r.centre_in_robot,
                        scan.sensor_id, context.now_s});
  }
  return std::nullopt;
}

void NavigationController::OnBumper(const core::BumperReading& reading,
                                    const ScanContext& context) {
  if (reading.zones_in_contact == 0) return;
  bumper_points_.clear();
  for (std::size_t z = 0; z < options_.bumper_zones_rad.size(); ++z) {
    if (!(reading.zones_in_contact & (1u << z))) continue;
    const auto [from, to] = options_.bumper_zones_rad[z];
    const double span = core::NormalizeAngle(to - from) < 0.0
                            ? core::NormalizeAngle(to - from) + 2.0 * std::numbers::pi
                            : core::NormalizeAngle(to - from);
    for (int k = 1; k < kBumperPointsPerZone; ++k) {
      const double bearing = from + span * k / kBumperPointsPerZone;
      bumper_points_.push_back(OutlineAt(footprint_, bearing));
    }
  }
  bumper_until_s_ = context.now_s + options_.bumper_hold_s;
  ForgetTouchesBefore(context.now_s - options_.explore.contact_memory_s);
  if (options_.explore.contact_memory_s > 0.0) {
    for (const Eigen::Vector2d& p : bumper_points_) {
      touched_in_odometry_.emplace_back(context.now_s, context.odometry * p);
    }
  }
}

// The speed controller below the dynamic window (§6.3.4: the window at
// 10 Hz, a speed controller at 1 kHz): each control tick moves the wheels'
// set-points towards the cycle's command by at most the window's acceleration
// (RampTowards), so the robot drives the arcs the window assumed.
std::optional<WheelSpeeds> NavigationController::OnTick(const ControlTick& tick) {
  if (tick.tick % dwa_period_ticks_ == 0) {
    held_ = output_;
    const ControlTick steered = Steered(tick);
    Cycle(steered);
    if (fleet_.coordinator) Publish(steered);
    if (!options_.hold_belief_at_goal || !queue_.localization_paused() || tick.localization_lost) {
      goal_hold_.reset();
    } else if (!goal_hold_) {
      goal_hold_ = HeldBelief{steered.belief, tick.odometry};
    }
  }
  // A safety stop (the window found no admissible command) and a pressed
  // bumper go to the motors at once, as Robox's security circuit stops it (A.5).
  const bool at_once = no_admissible_ || tick.now_s <= bumper_until_s_;
  const WheelVelocity next =
      at_once ? command_
              : RampTowards(output_, command_, options_.dwa.max_wheel_accel_mps2 * options_.step_s);
  if (cycled_ && next.left_mps == output_.left_mps && next.right_mps == output_.right_mps) {
    return std::nullopt;
  }
  cycled_ = true;
  output_ = next;
  return ToWheels(output_);
}

ControlTick NavigationController::Steered(const ControlTick& tick) const {
  if (!goal_hold_ || tick.localization_lost) return tick;
  ControlTick steered = tick;
  steered.belief = goal_hold_->belief * (goal_hold_->odometry.Inverse() * tick.odometry);
  return steered;
}

void NavigationController::Cycle(const ControlTick& tick) {
  const double dt_s = tick.now_s - last_cycle_s_;
  const double travelled_m = (tick.odometry.translation() - last_odometry_.translation()).norm();
  const double turned_rad =
      core::NormalizeAngle(tick.odometry.theta_rad - last_odometry_.theta_rad);
  if (cycled_) odometer_m_ += travelled_m;
  last_odometry_ = tick.odometry;
  last_cycle_s_ = tick.now_s;
  command_ = {};
  no_admissible_ = false;
  if (tick.now_s + 1e-9 < options_.start_s) return;
  // Before the states that return early: a hold ends when the robot stops driving.
  const bool hold = HoldForUncertainty(tick);
  if (state_ == State::kRelocalizing && !Relocalize(tick)) return Explore(tick);
  if (state_ == State::kLost) {
    if (tick.localization_lost) return Explore(tick);
    state_ = State::kWaiting;  // relocalized: carry on with the next mission
  }
  if (state_ == State::kDwelling && tick.now_s + 1e-9 >= dwell_until_s_) {
    queue_.Clear();
    state_ = State::kWaiting;
  }
  if (state_ == State::kWaiting) StartNextMission(tick);
  figures_.still_s = 0.0;
  if ((tick.odometry.translation() - still_anchor_).norm() > kStillMoveM) {
    still_anchor_ = tick.odometry.translation();
    still_since_s_ = tick.now_s;
  } else if (state_ == State::kDriving || (state_ == State::kWaiting && !AtRest()) ||
             state_ == State::kRelocalizing) {
    figures_.still_s = tick.now_s - still_since_s_;
    figures_.longest_still_s = std::max(figures_.longest_still_s, figures_.still_s);
  }
  if (state_ != State::kDriving) return;
  if (dt_s > 0.0) {
    // Standing for its uncertainty the robot is not blocked: the monitor rests.
    const BlockedMonitor::Step step =
        blocked_.Update(tick.now_s, travelled_m / dt_s, turned_rad / dt_s, !hold);
    if (step.became_blocked) Emit(NavigationEvent::Type::kBlocked, tick.now_s);
    if (step.abort) return EndMission(tick, false, AbortReason::kBlocked);
    if (step.replan) {
      const int avoid =
          graph_.FindIndex(queue_.empty() ? current_.goal : queue_.current().id).value_or(kNoNode);
      if (!PlanGlobal(tick, avoid)) return EndMission(tick, false, AbortReason::kUnreachable);
      PlanLocal(tick, true, "blocked");
    }
  }
  CheckProgress(tick);
  if (state_ != State::kDriving) return;
  if (hold) return ResetProgress(tick);  // stands (command_ is zero); no escape
  SwitchTakenGoal(tick);
  if (state_ != State::kDriving) return;
  if (fleet_.coordinator && tick.now_s + 1e-9 >= next_fleet_check_s_) {
    next_fleet_check_s_ = tick.now_s + options_.fleet_replan_s;
    FleetReplan(tick);
  }
  if (Escape(tick) || state_ != State::kDriving) return;
  if (tick.tick % band_period_ticks_ == 0) UpdateBand(tick);
  Drive(tick);
}

void NavigationController::StartNextMission(const ControlTick& tick) {
  std::optional<std::string> goal;
  if (fleet_.coordinator) {
    const FleetBoard& board = fleet_.coordinator->board();
    if (station_wait_since_s_ < 0.0) station_wait_since_s_ = tick.now_s;
    const bool revisit = tick.now_s - station_wait_since_s_ >= options_.station_wait_s;
    // Not the station it stands at either: a revisit there is no mission.
    const MissionSequence::Proposal p = missions_.NextFree(
        [&](const std::string& id) {
          const std::optional<int> n = graph_.FindIndex(id);
          return n && (*n == occupied_node_ || board.StationTaken(*n, fleet_.robot));
        },
        revisit);
    if (p.wait) {  // every remaining station is taken: ask again next cycle
      ++figures_.station_waits;
      if (!revisit || AtRest()) return;
      // Waited long enough: make way at a rest node, when one is free.
      const std::optional<int> rest =
          FreeRestNode(tick, [&](int n) { return board.StationTaken(n, fleet_.robot); });
      if (rest) BeginMission(tick, map_.nodes[static_cast<std::size_t>(*rest)].id, true);
      return;
    }
    goal = p.goal;
    revisit_ = p.revisit;
    if (p.revisit) ++figures_.station_revisits;
  } else {
    const MissionSequence::Proposal p = NextGoalBySight(tick);
    if (p.wait) return;
    goal = p.goal;
  }
  if (!goal) {
    state_ = State::kDone;
    status_.done = true;
    status_.done_at_s = tick.now_s;
    return;
  }
  BeginMission(tick, *goal, false);
}

void NavigationController::BeginMission(const ControlTick& tick, const std::string& goal,
                                        bool rest) {
  mission_waited_since_s_ = station_wait_since_s_ >= 0.0 ? station_wait_since_s_ : tick.now_s;
  station_wait_since_s_ = -1.0;
  ++mission_index_;
  const int node = graph_.FindIndex(goal).value_or(kNoNode);
  current_ = Mission{goal, node == kNoNode ? core::Pose2{} : map_.nodes[node].pose,
                     rest ? 0.0 : options_.dwell_s, options_.timeout_s};
  rest_trip_ = rest;
  if (rest) {
    revisit_ = false;
    ++figures_.rest_missions;
  }
  mission_start_s_ = tick.now_s;
  mission_start_odometer_m_ = odometer_m_;
  reserved_node_ = node;
  next_fleet_check_s_ = tick.now_s + options_.fleet_replan_s;
  ++figures_.missions_started;
  Emit(NavigationEvent::Type::kMissionStarted, tick.now_s);
  state_ = State::kDriving;
  blocked_.Reset();
  ResetProgress(tick);
  if (node == kNoNode || !PlanGlobal(tick, kNoNode)) {
    return EndMission(tick, false, AbortReason::kUnreachable);
  }
  PlanLocal(tick, false, "");
}

bool NavigationController::PlanGlobal(const ControlTick& tick, int avoid_node) {
  const std::vector<double> extra = NodeCosts(avoid_node);
  const std::optional<GraphPath> path =
      PlanFromPosition(graph_, map_, tick.belief.translation(),
                       graph_.FindIndex(current_.goal).value_or(kNoNode), options_.graph, extra);
  if (!path) return false;
  ++figures_.global_plans;
  std::vector<QueuedNode> nodes;
  for (int n : path->nodes) nodes.push_back({map_.nodes[n].id, map_.nodes[n].pose.translation()});
  queue_.Load(std::move(nodes), current_.goal_pose);
  queue_.Update(tick.belief);
  return true;
}

void NavigationController::PlanLocal(const ControlTick& tick, bool replan, const char* cause) {
  if (queue_.empty()) return;
  obstacles_.InWorld(tick.odometry, tick.belief, GridReachM(), &points_);
  AppendOtherRobots(tick, core::Pose2{}, GridReachM(), &points_);
  AppendPockets(tick.now_s, &points_);
  local_target_ = queue_.current().id;
  local_->Plan(tick.belief.translation(), queue_.current().position_m, points_,
               PlanSeed(options_.seed, plans_++));
  if (!replan) return;
  ++figures_.replans;
  NavigationEvent e;
  e.type = NavigationEvent::Type::kReplanned;
  e.at_s = tick.now_s;
  e.mission = mission_index_;
  e.goal = current_.goal;
  e.cause = cause;
  events_.push_back(std::move(e));
}

void NavigationController::UpdateBand(const ControlTick& tick) {
  if (queue_.empty()) return;
  if (queue_.current().id != local_target_ || !local_->has_band()) {
    PlanLocal(tick, false, "");
    return;
  }
  obstacles_.InWorld(tick.odometry, tick.belief, GridReachM(), &points_);
  AppendOtherRobots(tick, core::Pose2{}, GridReachM(), &points_);
  AppendPockets(tick.now_s, &points_);
  ++figures_.band_updates;
  switch (local_->Update(tick.belief.translation(), points_)) {
    case LocalPlanner::Status::kOk:
      break;
    case LocalPlanner::Status::kSnapped:
      ++figures_.band_snaps;
      PlanLocal(tick, true, "band_snap");
      break;
    case LocalPlanner::Status::kExtend:
    case LocalPlanner::Status::kNoBand:
      PlanLocal(tick, false, "");
      break;
  }
}

bool NavigationController::Relocalize(const ControlTick& tick) {
  if (tick.localization_lost) {
    if (tick.now_s - lost_since_s_ >= options_.relocalization_timeout_s) {
      EndMission(tick, false, AbortReason::kLost);
      state_ = State::kLost;
    } else if (tick.now_s - mission_start_s_ > current_.timeout_s) {
      EndMission(tick, false, AbortReason::kTimeout);
      state_ = State::kLost;
    }
    return false;
  }
  // Localized again, perhaps elsewhere: a new plan from where the robot is.
  state_ = State::kDriving;
  blocked_.Reset();
  ResetProgress(tick);
  if (!PlanGlobal(tick, kNoNode)) {
    EndMission(tick, false, AbortReason::kUnreachable);
    return false;
  }
  PlanLocal(tick, true, "relocalized");
  return true;
}

void NavigationController::CheckProgress(const ControlTick& tick) {
  if (tick.localization_lost) {
    lost_since_s_ = tick.now_s;
    explore_heading_.reset();
    escape_until_s_.reset();
    arc_in_world_.clear();
    if (options_.relocalization_timeout_s > 0.0) {  // hold the mission
      state_ = State::kRelocalizing;
      return;
    }
    EndMission(tick, false, AbortReason::kLost);
    state_ = State::kLost;
    return;
  }
  if (tick.now_s - mission_start_s_ > current_.timeout_s) {
    return EndMission(tick, false, AbortReason::kTimeout);
  }
  queue_.Update(tick.belief);
  if (queue_.arrived()) EndMission(tick, true, AbortReason::kUnreachable);
}

double NavigationController::UncertainErrorM(const ControlTick& tick) const {
  return 2.0 * (tick.position_sigma_m + options_.uncertainty.reach_m * tick.heading_sigma_rad);
}

double NavigationController::UncertainSpeedLimit(const ControlTick& tick) const {
  const UncertaintyOptions& o = options_.uncertainty;
  const double error_m = UncertainErrorM(tick);
  if (o.stop_m <= 0.0 || error_m <= o.slow_m) return std::numeric_limits<double>::infinity();
  const double limit_mps =
      options_.dwa.max_speed_mps * std::max(0.0, (o.stop_m - error_m) / (o.stop_m - o.slow_m));
  return uncertain_patience_out_ ? std::max(limit_mps, o.crawl_mps) : limit_mps;
}

bool NavigationController::HoldForUncertainty(const ControlTick& tick) {
  const UncertaintyOptions& o = options_.uncertainty;
  const double error_m = UncertainErrorM(tick);
  if (error_m <= o.slow_m) uncertain_patience_out_ = false;  // certain again
  const bool patience_out =
      uncertain_since_s_ && tick.now_s - *uncertain_since_s_ >= o.hold_max_s - 1e-9;
  if (patience_out) uncertain_patience_out_ = true;
  const bool hold = state_ == State::kDriving && !tick.localization_lost && o.stop_m > 0.0 &&
                    error_m >= o.stop_m && !uncertain_patience_out_;
  if (hold && !uncertain_since_s_) {
    uncertain_since_s_ = tick.now_s;
    ++figures_.uncertainty_holds;
    Emit(NavigationEvent::Type::kUncertaintyHold, tick.now_s);
  } else if (!hold && uncertain_since_s_) {
    const double held_s = tick.now_s - *uncertain_since_s_;
    figures_.uncertainty_hold_s += held_s;
    uncertain_since_s_.reset();
    Emit(NavigationEvent::Type::kUncertaintyHoldEnded, tick.now_s);
    NavigationEvent& ended = events_.back();
    ended.duration_s = held_s;
    // Why: certain again, out of patience (it drives on at a crawl), the
    // estimator declared itself lost, or the mission ended.
    ended.cause = patience_out                ? "patience"
                  : tick.localization_lost    ? "lost"
                  : state_ != State::kDriving ? "mission"
                                              : "certain";
  }
  if (hold) {
    escape_until_s_.reset();
    arc_in_world_.clear();
  }
  return hold;
}

void NavigationController::Drive(const ControlTick& tick) {
  const core::Pose2 robot_from_world = tick.belief.Inverse();
  DwaGoal goal;
  const Eigen::Vector2d goal_position = queue_.goal_pose().translation();
  const bool approach =
      queue_.at_goal_node() &&
      (goal_position - tick.belief.translation()).norm() <= options_.approach_radius_m;
  if (approach) {
    goal.pose_goal = true;
    goal.goal_in_robot = robot_from_world * goal_position;
    goal.goal_heading_in_robot_rad =
        core::NormalizeAngle(queue_.goal_pose().theta_rad - tick.belief.theta_rad);
    goal.target_in_robot = goal.goal_in_robot;
  } else {
    const Eigen::Vector2d target = local_->has_band()
                                       ? local_->TargetAhead(options_.band_lookahead_m)
                                       : queue_.current().position_m;
    goal.target_in_robot = robot_from_world * target;
  }
  GatherDrivePoints(tick);
  if (retreat_ && nearest_contour_ && nearest_contour_->norm() > 0.0) {
    // The deadlock rule's yield: away from the other robot where there is
    // room, the window choosing how among the obstacles.
    goal = DwaGoal{};
    goal.target_in_robot =
        kRetreatM * YieldDirection(*nearest_contour_, inradius_m_, kRetreatM, points_);
  }
  AddBumpersAndMeasure(tick);
  goal.speed_limit_mps = std::min(goal.speed_limit_mps, UncertainSpeedLimit(tick));
  const DwaResult result = Steer(tick, goal);
  constexpr double kStoppedMps = 0.01;
  UpdateDeadlock(
      tick, !result.admissible_found ||
                std::max(std::abs(command_.left_mps), std::abs(command_.right_mps)) < kStoppedMps);
}

void NavigationController::GatherDrivePoints(const ControlTick& tick) {
  // A robot that the deadlock rule clips for stands among robots that its
  // markers place: its blind-zone memory (kept up to kBlindMemoryCapS while
  // it stands) would hold a robot that has since driven off as a wall beside
  // it. In fallback seed 1 a Robox stood 20 s pinched between an exhibit's
  // plinth and the remembered flank of a robot gone 2 s after detection.
  if (clip_contours_) obstacles_.ForgetBefore(tick.now_s - kDeadlockMemoryS);
  obstacles_.InRobot(tick.odometry, tick.belief, options_.dwa_reach_m, &points_);
  AppendOtherRobots(tick, tick.belief.Inverse(), options_.dwa_reach_m, &points_);
  AppendContours(tick, clip_contours_, &points_);
}

void NavigationController::AddBumpersAndMeasure(const ControlTick& tick) {
  if (tick.now_s <= bumper_until_s_) {
    points_.insert(points_.end(), bumper_points_.begin(), bumper_points_.end());
  }
  const double clearance_m = PolygonClearance(footprint_, points_);
  if (std::isfinite(clearance_m)) {
    figures_.clearance_sum_m += clearance_m;
    ++figures_.clearance_samples;
    figures_.min_clearance_m = std::min(figures_.min_clearance_m, clearance_m);
  }
}

DwaResult NavigationController::Steer(const ControlTick& tick, const DwaGoal& goal) {
  const DwaResult result = dwa_.Choose(held_, points_, goal);
  ++figures_.dwa_cycles;
  if (!result.admissible_found) ++figures_.no_admissible_cycles;
  no_admissible_ = !result.admissible_found;
  command_ = result.command;
  arc_in_world_.clear();
  for (const Eigen::Vector2d& p : dwa_.ChosenArc(result, kArcDrawS)) {
    arc_in_world_.push_back(tick.belief * p);
  }
  return result;
}

void NavigationController::EndMission(const ControlTick& tick, bool completed, AbortReason reason) {
  NavigationEvent e;
  e.type =
      completed ? NavigationEvent::Type::kMissionCompleted : NavigationEvent::Type::kMissionAborted;
  e.at_s = tick.now_s;
  e.mission = mission_index_;
  e.goal = current_.goal;
  e.reason = reason;
  e.duration_s = tick.now_s - mission_start_s_;
  e.path_length_m = odometer_m_ - mission_start_odometer_m_;
  e.rest = rest_trip_;
  rest_trip_ = false;
  reserved_node_ = kNoNode;
  escape_until_s_.reset();
  if (completed) {
    occupied_node_ = graph_.FindIndex(current_.goal).value_or(kNoNode);
    ++figures_.missions_completed;
    figures_.mission_time_s += e.duration_s;
    figures_.mission_path_length_m += e.path_length_m;
    state_ = State::kDwelling;
    dwell_until_s_ = tick.now_s + current_.dwell_s;
  } else {
    ++figures_.missions_aborted[static_cast<std::size_t>(reason)];
    queue_.Clear();
    state_ = State::kWaiting;
  }
  events_.push_back(std::move(e));
  blocked_.Reset();
  command_ = {};
  arc_in_world_.clear();
  UpdateDeadlock(tick, false);  // no goal: an open deadlock episode ends
}

void NavigationController::AppendContours(const ControlTick& tick, bool clip,
                                          std::vector<Eigen::Vector2d>* points) {
  contour_overlap_ = false;
  nearest_contour_.reset();
  if (markers_.empty()) return;
  const core::Pose2 robot_from_odom = tick.odometry.Inverse();
  const core::Pose2 robot_from_world = tick.belief.Inverse();
  // The robots whose poses explain markers: none while this robot is lost
  // (its belief would place them wrongly), and never a lost one.
  std::vector<Eigen::Vector2d> known;
  if (fleet_.coordinator && !tick.localization_lost) {
    known = fleet_.coordinator->board().TrustedPositions(fleet_.robot);
    for (Eigen::Vector2d& k : known) k = robot_from_world * k;
  }
  const RobotContourOptions& o = options_.robot_contours;
  for (const SeenMarker& m : markers_) {
    const Eigen::Vector2d marker = robot_from_odom * m.marker_in_odom;
    const Eigen::Vector2d centre = robot_from_odom * m.centre_in_odom;
    const bool mapped = std::any_of(map_beacons_.begin(), map_beacons_.end(), [&](const auto& b) {
      return (robot_from_world * b - marker).norm() <= options_.mapped_beacon_m;
    });
    const bool explained = std::any_of(known.begin(), known.end(), [&](const auto& k) {
      return (k - centre).norm() <= options_.explained_m;
    });
    if (mapped || explained) continue;
    const bool overlap = ContourOverlapsHull(centre, o.contour_radius_m, footprint_, 0.0);
    // Within the window's safety margin of the hull the contour blocks as an
    // overlap does (the robots all blocked, each with a goal, §6.5).
    const bool touching =
        ContourOverlapsHull(centre, o.contour_radius_m, footprint_, kDeadlockTouchM);
    contour_overlap_ = contour_overlap_ || touching;
    if (touching && (!nearest_contour_ || centre.norm() < nearest_contour_->norm())) {
      nearest_contour_ = centre;
    }
    // The deadlock rule's model correction: the other robot cannot be inside
    // this one's hull, so its contour is shrunk to keep a margin from it.
    const double radius_m = clip && overlap ? ClipRadius(centre, o.contour_radius_m, footprint_,
                                                         options_.dwa.safety_margin_m + kClipSlackM)
                                            : o.contour_radius_m;
    AppendContour(centre, radius_m, o.point_spacing_m, points);
  }
}

void NavigationController::UpdateDeadlock(const ControlTick& tick, bool stalled) {
  if (!options_.see_robots) return;
  // A robot relocalizing holds its mission: a deadlock it is in still counts
  // (until 2026-12-05 the episode was dropped when the robot declared itself
  // lost, and a lost robot that stood 31 s in a pile was counted nowhere).
  const bool driving = state_ == State::kDriving || state_ == State::kRelocalizing;
  const DeadlockMonitor::Step step = deadlock_.Update(
      tick.now_s, driving, driving && contour_overlap_, driving && stalled, odometer_m_);
  clip_contours_ = step.clip;
  retreat_ = step.retreat;
  figures_.deadlocks_detected = deadlock_.detected();
  figures_.deadlocks_resolved = deadlock_.resolved();
  figures_.deadlocks_unresolved = deadlock_.unresolved();
  figures_.longest_deadlock_s = deadlock_.longest_resolution_s();
  if (step.detected) Emit(NavigationEvent::Type::kDeadlockDetected, tick.now_s);
  if (deadlock_.unresolved() > unresolved_reported_) {
    unresolved_reported_ = deadlock_.unresolved();
    Emit(NavigationEvent::Type::kDeadlockUnresolved, tick.now_s);
  }
  if (step.resolved) {
    NavigationEvent e;
    e.type = NavigationEvent::Type::kDeadlockResolved;
    e.at_s = tick.now_s;
    e.mission = mission_index_;
    e.goal = current_.goal;
    e.duration_s = step.resolution_s;
    events_.push_back(std::move(e));
  }
}

void NavigationController::Emit(NavigationEvent::Type type, double at_s) {
  NavigationEvent e;
  e.type = type;
  e.at_s = at_s;
  e.mission = mission_index_;
  e.goal = current_.goal;
  e.rest = rest_trip_;
  events_.push_back(std::move(e));
}

WheelSpeeds NavigationController::ToWheels(const WheelVelocity& rim) const {
  return {rim.left_mps / options_.odometry.left_wheel_radius_m,
          rim.right_mps / options_.odometry.right_wheel_radius_m};
}

std::optional<MissionStatus> NavigationController::mission() const { return status_; }

void NavigationController::TakeEvents(std::vector<NavigationEvent>* events) {
  events->insert(events->end(), events_.begin(), events_.end());
  events_.clear();
}

const NavigationFigures* NavigationController::navigation() const {
  figures_.blocked_episodes = blocked_.episodes();
  figures_.time_blocked_s = blocked_.time_blocked_s();
  figures_.longest_blocked_s = blocked_.longest_blocked_s();
  return &figures_;
}

std::optional<NavigationPicture> NavigationController::picture() const {
  NavigationPicture p;
  for (const QueuedNode& n : queue_.remaining()) p.plan.push_back(n.position_m);
  if (local_->has_band()) {
    for (const auto& b : local_->band().bubbles()) {
      p.band_centers.push_back(b.center);
      p.band_radii_m.push_back(b.radius_m);
    }
  }
  p.dwa_arc = arc_in_world_;
  return p;
}

}  // namespace pavilion::nav
