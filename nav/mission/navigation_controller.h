#pragma once

// The three-layer navigation of Expo.02 (thesis chapter 6, Fig. 6.5) as a
// robot-stack controller: missions from a MissionSequence; global planning on
// the map's topology (§6.3.2) when a mission starts or when blocked; the
// command queue (§6.3.3) handing the plan's nodes down one by one; the local
// path planner — initial path and elastic band at `band_rate_hz` (§6.3.4); and
// the dynamic window in (v_l, v_r) at `dwa_rate_hz` commanding the wheels. It
// sees only the robot's belief, its odometry and raw scans, never ground truth.

#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/localization/encoder_odometry.h"
#include "core/map/robot_map.h"
#include "nav/control/controller.h"
#include "nav/fleet/coordinator.h"
#include "nav/fleet/deadlock_monitor.h"
#include "nav/local/local_planner.h"
#include "nav/local/ompl_path_planner.h"
#include "nav/local/robot_contours.h"
#include "nav/local/scan_obstacles.h"
#include "nav/mission/blocked_monitor.h"
#include "nav/mission/command_queue.h"
#include "nav/mission/mission_sequence.h"
#include "nav/planning/graph_planner.h"
#include "nav/planning/topology_graph.h"
#include "nav/reactive/dynamic_window.h"
#include "nav/reactive/explore_direction.h"

namespace pavilion::nav {

// Which planner gives the band its initial path (§6.3.4: NF1).
enum class InitialPlanner { kNf1, kOmplRrtConnect, kOmplRrtStar };

// The way out of a pocket: a robot driving a mission whose position stays
// within `still_m` of one place for `after_s` backs out towards the freest
// bearing its senses and the map show (ExploreBearing over the dynamic
// window's points, outline and others' hulls included) or, where it cannot
// turn, straight back the way it came (StraightFreeTravel), for `drive_s` or
// until it is `leave_m` away, then plans again from there, the node it was
// heading for made dearer (blocked_node_cost_m). The window alone can dither
// for minutes where the band's next point lies past an obstacle it must
// first turn away from (expo_tours: a Robox stood 330 s 4 cm from column_2,
// each blocked episode ended by a few centimetres of motion). Robots touching
// another's contour are the deadlock rule's (§6.5), not this.
struct EscapeOptions {
  // No net progress this long starts an escape, s, [0, 3600]; 0: never.
  // Chosen: past two blocked replans (10 s each), below the 45 s abort.
  double after_s = 20.0;
  double still_m = 0.3;  // progress is leaving a disc this wide, m, (0, 5]
  double drive_s = 6.0;  // the escape drives at most this long, s, (0, 60]
  double leave_m = 0.5;  // ... or until this far from where it began, m, (0, 5]
  // A bearing free for less than this is not taken, m, (0, 5]. Chosen: less
  // than ExploreOptions::min_free_m — the robot is in a pocket.
  double min_free_m = 0.3;
  double speed_mps = 0.3;  // translation limit while escaping, m/s, (0, 2]
  // Where an escape began is closed to the band and its initial path (a
  // disc of virtual points, `mark_radius_m`, in the map frame) for
  // `remember_s`, so the replan does not lead straight back into the pocket
  // the local grid sees as open (a gap 3 cm wider than the planning circle,
  // which the window's margins do not fit), s, [0, 3600]; m, (0, 1].
  double remember_s = 120.0;
  double mark_radius_m = 0.1;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// A localized robot whose belief has grown too uncertain to place what its
// lasers do not show — the map's ghost barriers (glass, the exits), the
// stations the others hold, the others' hulls — slows, then stands with its
// mission held until a match shrinks the uncertainty again or the estimator
// declares itself lost. The uncertainty is the 2-sigma error of a point
// `reach_m` ahead: 2 (position sigma + reach_m * heading sigma). In
// expo_rush (seed 1, 301.8 s) a visitor's shove turned a Robox 24.5° while
// its wheels turned 3.4°; its heading sigma grew to 6.8° (collision noise),
// it matched nothing for 14 s among the crowd and drove on its mission at
// 0.4 m/s on that belief, 1.1 m off by the time it was declared lost, 35 cm
// from an exit its misplaced barrier did not close, and left the floor. A
// robot standing keeps the error the shove left (0.11 m there); the
// blocked monitor and the escape wait while it stands. A hold lasts at most
// hold_max_s: a robot standing among visitors who hide its walls may wait
// for minutes (expo_rush seed 1 with the hold unbounded: robox_17 stood
// 500 s 1.5 cm from its belief, its position sigma 13 cm, matching nothing
// among the crowd), so it then drives on at crawl_mps at most, to see its
// walls from elsewhere, until its error falls to slow_m again.
struct UncertaintyOptions {
  double reach_m = 1.0;  // m, [0, 10]. Chosen: the band's look-ahead
  // Above this error the translation limit falls linearly from the window's
  // top speed to zero at stop_m, m, [0, stop_m). Chosen: ten times a
  // tracking Robox' (8 mm, 0.1°: about 1 cm), and the margin the dynamic
  // window keeps.
  double slow_m = 0.1;
  // At this error and above the robot stands, m; 0: off. Chosen: the error a
  // collision's noise reaches for a few cycles before a match (expo_rush
  // seed 2: 472 of 116,495 cycles above it, most under 5 s).
  double stop_m = 0.3;
  // s, (0, 3600]. Chosen: the thesis' robots recovered from 5-10 s without
  // a match (§4.5.3.1); twice that.
  double hold_max_s = 20.0;
  // m/s, (0, 2]. Chosen: a quarter of Robox' top speed; 5 m of travel without
  // a match (LocalizerOptions::lost_no_match_travel_m) then takes half a minute.
  double crawl_mps = 0.15;

  void Validate() const;  // throws std::invalid_argument naming the field
};

struct NavigationControllerOptions {
  double step_s = 0.005;      // the physics step: the control ticks' period, s, (0, 1]
  double start_s = 0.0;       // the first mission starts then, s, [0, 1e7]
  double dwa_rate_hz = 10.0;  // Fig. 6.5 loop 3: the dynamic window, Hz, [1, 1000]
  double band_rate_hz = 5.0;  // Fig. 6.5 loop 2: band updates ("several Hz"), Hz, [0.1, 100]
  double dwell_s = 0.0;       // wait at each goal after arrival, s, [0, 3600]
  double timeout_s =
      300.0;  // a mission not completed this long after its start is aborted, s, (0, 1e6]
  // Obstacle points within this of the robot go to the dynamic window, m, (0, 20].
  double dwa_reach_m = 3.0;
  double band_lookahead_m =
      1.0;  // the dynamic window steers to the band this far ahead, m, (0, 10]
  // Within this of the final goal the dynamic window steers to the goal pose
  // itself (its pose mode), m, (0, 5].
  double approach_radius_m = 1.0;
  // A blocked replan raises the cost of the node the robot was heading for by
  // this much (m of path), so the global planner may pick another way, [0, 1e4].
  double blocked_node_cost_m = 20.0;
  // A robot that declares itself lost during a mission holds the mission
  // while it relocalizes (explore_when_lost: driving towards open space) and,
  // once localized again, replans from where it is and carries on; the
  // mission is aborted as lost only when this long passes first. 0: aborted
  // at once. s, [0, 3600]. Chosen: the kidnap recovery bound of 30 s.
  double relocalization_timeout_s = 30.0;
  // Near the goal (CommandQueueOptions::localization_pause_radius_m) the
  // thesis deactivates localization (§6.3.3), "because localization causes
  // the robot pose estimates to be noisy such that for any position
  // controller the goal cannot be reached". true: the controller steers by
  // the belief it held on entering that radius, carried on by odometry,
  // while the estimator runs on, so a robot kidnapped at its goal is noticed
  // there (kidnap_recovery: one kidnapped while turning onto its goal
  // heading stood blocked, its localization paused, for good). false: the
  // thesis' pause (localization_paused()).
  bool hold_belief_at_goal = true;
  // While not localized (lost or several hypotheses), after explore.settle_s
  // of standing, the controller drives by its senses alone: towards the
  // freest bearing (ExploreBearing) through the dynamic window, with the
  // laser points, the blind zones' memory, the map's ghost barriers (glass
  // the laser cannot see), other robots' contours and the bumpers, and with a
  // coordinator the others' published hulls (grown, below) and the rings of
  // the stations they hold — ghost barriers, hulls and rings placed where it
  // was last localized, carried on by odometry (Placement), and the ghost
  // barriers also by a lone hypothesis (ControlTick::lone_hypothesis) — not
  // the map outline, which a wrong belief would misplace. Off: the robot
  // stands.
  bool explore_when_lost = false;
  ExploreOptions explore;
  // While it explores, the others' published hulls are placed (Placement)
  // grown by this, m, [0, 2]: a robot falsely lost is most often within
  // decimetres of where it believes (expo_tours: nearly all losses under
  // 5 cm, up to 0.26 m after exploring), and its lasers see only the others'
  // recessed bodies. Points of them that fall inside its own outline are
  // dropped (the belief is that far off). A kidnapped robot sees them where
  // they are not: it avoids a phantom. (A Robox exploring at 0.3 m/s drove
  // its flank into another standing 0.8 m off, seed 4, 3,431 s.) The hull a
  // robot that declared itself lost publishes is drawn as much larger by the
  // others: its belief is as uncertain (expo_tours seed 1, 3,068 s: a robot
  // declared lost drew its hull 0.3 m from where it stood, and another,
  // passing at 0.5 m/s, touched it).
  double lost_hull_margin_m = 0.3;
  EscapeOptions escape;
  UncertaintyOptions uncertainty;
  // Fleet (§6.3.5), with a coordinator only: every this often while driving
  // the robot plans again on the others' current weights from where it is —
  // pushed aside, blocked or merely crossed by another's plan — and takes the
  // new plan when it is cheaper than the rest of the current one (its leg
  // from here included) by more than fleet_replan_gain_m. s, [0.1, 600].
  double fleet_replan_s = 2.0;
  double fleet_replan_gain_m = 2.0;  // m of path, [0, 1e4]
  // A plan taken by that replan is kept at least this long, so that two robots
  // reacting to each other's weights do not swap ways back and forth, s,
  // [fleet_replan_s, 600]. Chosen: the time to drive about two graph arcs.
  double fleet_commit_s = 10.0;
  // The others' hulls, placed at their published poses, are drawn this much
  // larger: the estimates' errors and the 0.1 s a pose is old at most, m, [0, 0.5].
  double fleet_hull_margin_m = 0.03;
  // ... or, when larger, this many sigmas of the two beliefs' combined
  // uncertainty where the hull is drawn (this robot's position sigma plus its
  // heading sigma times the distance, and the other's published outline
  // sigma, FleetMessage::outline_sigma_m), at most lost_hull_margin_m; [0, 5].
  // Tracking, a Robox's sigma is millimetres and the margin rules; a
  // collision grows it for a few cycles (CollisionNoiseOptions), and a robot
  // a visitor's bump left 8-13 cm off along its way, without a wall across
  // it to fix that, drove twice into a hull drawn by that belief with 3 cm
  // (expo_day seed 1, 24,689.5 s: robox_03, its sigma 9-15 cm). Chosen:
  // 2 sigmas hold a 2D error 86 % of the time; the ratchet (the growth stops
  // short of this robot's own hull) keeps the growth from trapping it.
  double fleet_hull_sigmas = 2.0;
  // A station another robot claims (FleetBoard::ResolveClaims: passing,
  // arriving or standing there) is kept clear: this robot's centre stays this
  // far from the node (a ring of virtual points its hull must not cross), m,
  // [0, 5]. A robot already inside a ring draws none (it leaves, never
  // trapped), and a robot heading for its own station waits outside that
  // station's ring while another robot is inside. A robot standing within
  // this distance of a station of its tour claims it. Chosen: the issue's
  // "never two robots within 1 m of the same station node" plus 5 cm.
  double fleet_station_clear_m = 1.05;
  // A station the band passes this much further than fleet_station_clear_m
  // from, within FleetOptions::claim_ahead_m along the band, is claimed for
  // passage too, m, [0, 2]. Chosen: the dynamic window steers to the band
  // 1 m ahead and cuts its corners by up to a few decimetres.
  double fleet_claim_margin_m = 0.3;
  // Every remaining station of the round taken this long: the robot proposes
  // a free station it visited before (MissionSequence::NextFree's revisit),
  // s, [0, 3600]. Chosen: a dwell — robots standing each at the station
  // another still has to visit otherwise wait for good.
  double station_wait_s = 10.0;
  // Where the robot waits out of the way (ours; the fleet's charging docks,
  // thesis Fig. 6.6): node ids of the map. With the coordination on, a robot
  // that finds no station free after station_wait_s (no revisit either) and
  // is not resting already drives to the nearest free one of these and waits
  // there, its station free for another robot — a mission like any other
  // (NavigationEvent::rest, NavigationFigures::rest_missions), with no dwell.
  // A robot starting within FleetOptions::release_distance_m of one rests
  // there. Without them, a fleet with more robots than stations stands still
  // for good once every station is held (expo_rush: 20 Robox, 15 stations,
  // all standing from the 280th second). Waiting at rest is not standing
  // still with a mission. Empty: a robot waits where it stands.
  std::vector<std::string> rest_among;
  // With the coordination off, goal coordination from the robot's own
  // sensing (the fall-back of §6.5): a robot this close to its goal station
  // that sees another robot (a marker's implied centre, §6.3.5.1) within
  // fleet_station_clear_m of the station gives it back to its round and
  // drives on to a station it does not see occupied, m, [0, 20]; 0: off.
  // Chosen: about four robot lengths, where a robot that turns away still
  // has room, and within the markers' 6 m range. Without it, four robots
  // bound for one station piled up around it (expo_tours_fallback seed 5,
  // a deadlock unresolved for 30 s).
  double seen_station_look_m = 3.0;
  // The dynamic window's blind zones get the map's segments and columns
  // (ScanObstacles::SetMapOutline), placed by the belief and drawn
  // ghost_barrier.clearance_m off them.
  bool blind_map_outline = true;
  // Robots seeing robots (§6.3.5.1): the markers of other robots in the scans
  // become virtual robot contours for the dynamic window and the band, held
  // `contour_hold_s` after their laser last saw them (the blind zones). Off
  // for a lone robot. Markers within `mapped_beacon_m` of a beacon of the map
  // are the map's (a foil-wrapped column), not a robot. With a coordinator, a
  // marker explained by a robot whose pose it publishes (its implied centre
  // within `explained_m`) gives way to that robot's hull.
  bool see_robots = false;
  RobotContourOptions robot_contours;
  double contour_hold_s = 1.0;   // s, [0, 10]
  double mapped_beacon_m = 0.3;  // m, [0, 2]
  double explained_m = 0.5;      // m, [0, 2]. Chosen: marker_offset_m and a marker seen obliquely
  DeadlockOptions deadlock;      // the overlap deadlock of §6.5
  InitialPlanner initial_planner = InitialPlanner::kNf1;
  GhostBarrier ghost_barrier;  // the dynamic window's filled ghost barriers (scan_obstacles.h)
  OmplPlannerOptions ompl;
  LocalPlannerOptions local;
  DynamicWindowOptions dwa;
  CommandQueueOptions queue;
  BlockedMonitorOptions blocked;
  GraphPlannerOptions graph;
  // Wheel radii that turn the window's rim speeds into wheel speeds: the
  // robot's calibrated odometry model.
  core::EncoderOdometryOptions odometry;
  std::uint64_t seed = 1;  // the sampling planners' seeds (scenario seed and robot)
  // The bumper zones' bearings from the robot's origin (rad, counter-clockwise
  // from `from` to `to`), bit i of a reading = zone i. A pressed zone becomes
  // obstacle points on the robot's outline for the dynamic window, held
  // `bumper_hold_s` after release: contact in a laser's blind zone.
  std::vector<std::pair<double, double>> bumper_zones_rad;
  double bumper_hold_s = 1.0;  // s, [0, 60]

  void Validate() const;  // throws std::invalid_argument naming the field
};

class NavigationController : public Controller {
 public:
  // `footprint_in_robot`: the robot's convex outline (counter-clockwise); the
  // map's nodes name the missions' goals.
  NavigationController(core::RobotMap map, std::vector<Eigen::Vector2d> footprint_in_robot,
                       MissionSequence missions, const NavigationControllerOptions& options);
  ~NavigationController() override;

  // The window's cycle (dwa_rate_hz); between cycles OnTick only ramps.
  bool BusyTick(std::int64_t tick) const override { return tick % dwa_period_ticks_ == 0; }
  std::optional<WheelSpeeds> OnTick(const ControlTick& tick) override;
  std::optional<WheelSpeeds> OnScan(const core::LaserScan& scan,
                                    const ScanContext& context) override;
  void OnBumper(const core::BumperReading& reading, const ScanContext& context) override;
  std::optional<MissionStatus> mission() const override;
  bool localization_paused() const override {
    return !options_.hold_belief_at_goal && queue_.localization_paused();
  }
  void TakeEvents(std::vector<NavigationEvent>* events) override;
  const NavigationFigures* navigation() const override;
  std::optional<NavigationPicture> picture() const override;

  // Joins the fleet (§6.3.5): the robot reserves its stations, plans on the
  // others' weights, publishes its plan, stations and pose each cycle, and its
  // dynamic window sees the others' hulls at their published poses. The
  // coordinator must outlive the controller; all robots share one map.
  void SetFleet(FleetLink link);

 private:
  // kRelocalizing: the mission is held while the estimator relocalizes
  // (relocalization_timeout_s); kLost: no mission, waiting to be localized.
  enum class State { kWaiting, kDriving, kDwelling, kRelocalizing, kLost, kDone };
  void Cycle(const ControlTick& tick);
  void StartNextMission(const ControlTick& tick);
  // Starts the mission to `goal` (a node id; rest: a trip to a rest node).
  void BeginMission(const ControlTick& tick, const std::string& goal, bool rest);
  // The robot stands at (occupies) one of its rest nodes.
  bool AtRest() const;
  // The free rest node nearest the robot's belief, none when all are taken.
  std::optional<int> FreeRestNode(const ControlTick& tick,
                                  const std::function<bool(int)>& taken) const;
  // Publish's first cycle: a robot standing at a rest node occupies it.
  void OccupyRestAtStart(const ControlTick& tick);
  // kRelocalizing: true once localized again and replanned (driving on).
  bool Relocalize(const ControlTick& tick);
  bool PlanGlobal(const ControlTick& tick, int avoid_node);
  void PlanLocal(const ControlTick& tick, bool replan, const char* cause);
  void UpdateBand(const ControlTick& tick);
  void Drive(const ControlTick& tick);
  // The 2-sigma error of a point uncertainty.reach_m ahead (UncertaintyOptions).
  double UncertainErrorM(const ControlTick& tick) const;
  // The translation limit that error allows (infinite below uncertainty.slow_m,
  // at least crawl_mps once a hold ran out of patience).
  double UncertainSpeedLimit(const ControlTick& tick) const;
  // Starts or ends the hold for uncertainty (events, figures); true while
  // the robot, driving, stands for it.
  bool HoldForUncertainty(const ControlTick& tick);
  // Where the robot places the map and the others while not localized: where
  // it was last localized, carried on by odometry (ControlTick::last_localized),
  // else its belief.
  static core::Pose2 Placement(const ControlTick& tick) {
    return tick.last_localized ? *tick.last_localized : tick.belief;
  }
  // `tick` with the belief held at the goal (hold_belief_at_goal) while
  // the queue would pause localization and the estimator is localized.
  ControlTick Steered(const ControlTick& tick) const;
  // Not localized: drives towards open space (explore_when_lost).
  void Explore(const ControlTick& tick);
  // Drops the bumper contacts the explorer remembers from before `s`.
  void ForgetTouchesBefore(double s);
  // Explore's drive; true when the robot stands (settling, nowhere open, or
  // no admissible command).
  bool ExploreStep(const ControlTick& tick);
  // Driving: starts, drives or ends an escape (EscapeOptions); true while
  // the escape has the wheels.
  bool Escape(const ControlTick& tick);
  // Keeps or chooses escape_way_ on points_; the bearing when kBearing.
  std::optional<double> ChooseEscapeWay(const ControlTick& tick);
  // The dynamic window's obstacle points for a localized robot (points_,
  // robot frame): senses, map outline, the others' hulls and contours.
  void GatherDrivePoints(const ControlTick& tick);
  // Adds the pressed bumpers' points to points_ and records the clearance.
  void AddBumpersAndMeasure(const ControlTick& tick);
  // The mission made progress (or starts afresh): the escape's clock restarts.
  void ResetProgress(const ControlTick& tick);
  // One dynamic-window cycle on points_ towards `goal`: the command, the
  // window's figures and the arc drawn (Drive and Explore).
  DwaResult Steer(const ControlTick& tick, const DwaGoal& goal);
  // The window's target along `bearing_rad` (robot frame), band_lookahead_m off.
  Eigen::Vector2d AheadAlong(double bearing_rad) const;
  void EndMission(const ControlTick& tick, bool completed, AbortReason reason);
  // Fleet: the others' costs per node, publishing, the periodic replan and
  // the others' hulls as obstacle points in the frame `frame_from_world`.
  std::vector<double> NodeCosts(int avoid_node) const;
  void Publish(const ControlTick& tick);
  // The passage claims after this cycle, the robot at `at` (map frame).
  void UpdateClaims(const Eigen::Vector2d& at);
  // The current goal is given back and another station proposed, the same
  // mission driving on (or waiting when none is free); `taken` by node index.
  void SwitchGoal(const ControlTick& tick, const std::function<bool(int)>& taken,
                  const char* cause);
  // With the coordination off: whether the robot sees another robot within
  // fleet_station_clear_m of the station `node` (markers' implied centres).
  bool SeesRobotAt(const ControlTick& tick, int node) const;
  // Switches the goal when the board took its station (coordination on) or a
  // robot is seen at it (off, seen_station_look_m).
  void SwitchTakenGoal(const ControlTick& tick);
  // Whether the goal station, within seen_station_look_m, is seen taken.
  bool GoalSeenTaken(const ControlTick& tick) const;
  // The next goal without the coordinator: the sequence's next, or another
  // when a robot is seen at it (wait when every remaining one is seen taken).
  MissionSequence::Proposal NextGoalBySight(const ControlTick& tick);
  void FleetReplan(const ControlTick& tick);
  double RemainingPathCost(const Eigen::Vector2d& position, const std::vector<double>& costs) const;
  void AppendOtherRobots(const ControlTick& tick, const core::Pose2& frame_from_world,
                         double reach_m, std::vector<Eigen::Vector2d>* points) const;
  // The others' hulls alone, placed by the tick's belief, grown by `margin_m`
  // or the beliefs' uncertainty (fleet_hull_sigmas) and swept by their speeds.
  void AppendOtherHulls(const ControlTick& tick, const core::Pose2& frame_from_world,
                        double reach_m, double margin_m,
                        std::vector<Eigen::Vector2d>* points) const;
  // One of them, `m`'s robot of outline `hull`, drawn at `at`.
  void AppendOtherHull(const ControlTick& tick, const core::Pose2& frame_from_world, double reach_m,
                       double margin_m, const FleetMessage& m,
                       const std::vector<Eigen::Vector2d>& hull, const core::Pose2& at,
                       std::vector<Eigen::Vector2d>* points) const;
  // Rings of virtual points that keep this robot out of the stations the
  // others hold (fleet_station_clear_m), in the frame `frame_from_world`.
  void AppendStationRings(const core::Pose2& belief, const core::Pose2& frame_from_world,
                          double reach_m, std::vector<Eigen::Vector2d>* points) const;
  // The others' markers blown up into contours (§6.3.5.1), robot frame; sets
  // contour_overlap_ when one reaches into the own hull.
  void AppendContours(const ControlTick& tick, bool clip, std::vector<Eigen::Vector2d>* points);
  void UpdateDeadlock(const ControlTick& tick, bool stalled);
  void CheckProgress(const ControlTick& tick);
  void Emit(NavigationEvent::Type type, double at_s);
  WheelSpeeds ToWheels(const WheelVelocity& rim) const;
  // Obstacle points this near the robot go to the local grid: its half-diagonal.
  double GridReachM() const { return kGridReachPerSide * options_.local.grid.size_m; }
  static constexpr double kGridReachPerSide = 0.75;  // > sqrt(2) / 2
  static constexpr int kNoNode = -1;                 // a station goal the map does not name

  NavigationControllerOptions options_;
  core::RobotMap map_;
  std::vector<Eigen::Vector2d> footprint_;
  double inradius_m_ = 0.0;      // the footprint's nearest side from the robot's origin
  double circumradius_m_ = 0.0;  // its farthest corner
  std::vector<Eigen::Vector2d> margin_outline_;  // the footprint grown by the window's margin
  // ... and by the ratchet's gap: where a localized robot's hull points
  // within the margin are moved (ClearMargin; set with the fleet).
  std::vector<Eigen::Vector2d> ratchet_outline_;
  MissionSequence missions_;
  TopologyGraph graph_;
  ScanObstacles obstacles_;
  std::unique_ptr<LocalPlanner> local_;
  DynamicWindow dwa_;
  CommandQueue queue_;
  BlockedMonitor blocked_;
  std::int64_t dwa_period_ticks_ = 1;
  std::int64_t band_period_ticks_ = 1;

  State state_ = State::kWaiting;
  // The belief and odometry when the queue paused localization at the goal
  // (hold_belief_at_goal); none elsewhere.
  struct HeldBelief {
    core::Pose2 belief;
    core::Pose2 odometry;
  };
  std::optional<HeldBelief> goal_hold_;
  std::optional<double> uncertain_since_s_;  // standing for its uncertainty since
  bool uncertain_patience_out_ = false;      // held hold_max_s; crawls until certain again
  Mission current_;
  int mission_index_ = -1;
  double mission_start_s_ = 0.0;
  double lost_since_s_ = 0.0;  // kRelocalizing, kLost: when the estimator declared the loss
  std::optional<double> explore_heading_;  // Explore's bearing, odometry frame
  double mission_start_odometer_m_ = 0.0;
  double dwell_until_s_ = 0.0;
  std::string local_target_;    // the queue node the band was planned to
  std::uint64_t plans_ = 0;     // initial paths planned: the sampling planners' seed counter
  WheelVelocity command_;       // rim speeds the last cycle chose
  WheelVelocity held_;          // rim speeds sent to the wheels when the last cycle began
  WheelVelocity output_;        // rim speeds sent to the wheels now (ramped towards command_)
  bool no_admissible_ = false;  // the last cycle's window found no admissible command
  core::Pose2 last_odometry_;
  double last_cycle_s_ = 0.0;
  bool cycled_ = false;
  double odometer_m_ = 0.0;
  std::vector<Eigen::Vector2d> points_;  // scratch: obstacle points of a cycle
  // Virtual points of pressed bumper zones (robot frame) and when they lapse.
  std::vector<Eigen::Vector2d> bumper_points_;
  double bumper_until_s_ = -1.0;
  // Pressed bumper points (odometry frame) and when, for explore.contact_memory_s.
  std::vector<std::pair<double, Eigen::Vector2d>> touched_in_odometry_;
  std::vector<Eigen::Vector2d> arc_in_world_;
  std::vector<NavigationEvent> events_;
  mutable NavigationFigures figures_;  // blocked figures filled in on reading
  MissionStatus status_;
  FleetLink fleet_;
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> walls_;  // the map's, for sight
  int reserved_node_ = -1;               // the station this robot heads for
  int occupied_node_ = -1;               // the station it stands at or is leaving
  double station_wait_since_s_ = -1.0;   // every remaining station taken since; < 0: not waiting
  double mission_waited_since_s_ = 0.0;  // the current mission's robot waited since (or began)
  bool revisit_ = false;                 // the current goal is a revisit (not of the round)
  bool rest_trip_ = false;               // the current goal is a rest node
  bool rest_checked_ = false;            // OccupyRestAtStart has run
  std::vector<int> rest_nodes_;          // options_.rest_among as node indices
  std::vector<int> claimable_;           // node indices of the stations it may claim, ascending
  std::vector<int> claims_;              // the stations it holds for passage, ascending
  double next_fleet_check_s_ = 0.0;
  // Markers seen (odometry frame), the laser and when.
  struct SeenMarker {
    Eigen::Vector2d marker_in_odom;
    Eigen::Vector2d centre_in_odom;
    std::string laser;
    double seen_s = 0.0;
  };
  std::vector<SeenMarker> markers_;
  std::vector<Eigen::Vector2d> map_beacons_;  // world frame
  DeadlockMonitor deadlock_;
  bool contour_overlap_ = false;
  bool clip_contours_ = false;
  bool retreat_ = false;  // the deadlock rule's yield (DeadlockMonitor::Step::retreat)
  // The nearest contour touching the hull this cycle (robot frame).
  std::optional<Eigen::Vector2d> nearest_contour_;
  int unresolved_reported_ = 0;
  Eigen::Vector2d still_anchor_ = Eigen::Vector2d::Zero();  // odometry position, kStillMoveM
  double still_since_s_ = 0.0;
  // Escape: the mission's last progress (odometry position, when), and the
  // escape under way (where it began, its bearing in the odometry frame, end).
  Eigen::Vector2d progress_anchor_ = Eigen::Vector2d::Zero();
  double progress_since_s_ = 0.0;
  std::optional<double> escape_until_s_;
  Eigen::Vector2d escape_from_ = Eigen::Vector2d::Zero();
  // How it escapes: turned to a bearing (escape_heading_, odometry frame),
  // straight back or straight on.
  // kCreep: straight back (creep_reverse_) or on with the margin cut, where
  // the window held the robot standing for escape_stalls_ cycles.
  enum class EscapeWay { kNone, kBearing, kReverse, kForward, kCreep };
  EscapeWay escape_way_ = EscapeWay::kNone;
  bool creep_reverse_ = true;
  // The creep began with a point inside the outline (a contact): it judges
  // with no margin and lets such points get kCreepContactSlackM deeper.
  bool creep_from_contact_ = false;
  // kBearing: cycles held turning towards it with a point near the circle
  // the corners sweep (then it turns with the creep's margin).
  int creep_turn_cycles_ = 0;
  int escape_stalls_ = 0;
  double escape_heading_ = 0.0;
  struct PocketMark {
    Eigen::Vector2d at_in_map;
    double until_s = 0.0;
  };
  std::vector<PocketMark> pockets_;  // escapes' starts, closed to the band
  // Virtual points of the remembered pockets (map frame) for the local planner.
  void AppendPockets(double now_s, std::vector<Eigen::Vector2d>* points);
};

}  // namespace pavilion::nav
