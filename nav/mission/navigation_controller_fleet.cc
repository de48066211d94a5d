// The fleet part of the navigation controller (thesis §6.3.5): goal and path
// coordination through the coordinator's board, the others' hulls at their
// published poses, and the rings that keep the stations the others hold clear.

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include "core/geometry/polygon.h"
#include "core/geometry/segment2.h"
#include "nav/mission/navigation_controller.h"
#include "nav/reactive/swept_polygon.h"

namespace pavilion::nav {
namespace {

// Another robot's published pose is this old at most (one cycle), s; its
// swept hull is drawn in copies this far apart, m.
constexpr double kPoseAgeS = 0.1;
constexpr double kSweepStepM = 0.1;
// A robot less than this inside the ring of a station another robot holds
// slipped in while braking (the claim appeared as it arrived) rather than
// crossing the node: it sees the ring drawn just outside its hull, which lets
// it back out but not in, m. Chosen: the 3 cm slip seen in the hour's one
// such conflict (docs/benchmarks.md) with room to spare, while a robot this
// close to the ring is still not near the node another robot crosses.
constexpr double kRingSlipM = 0.25;
// That ring, and a lost robot's hull grown for its uncertainty, keep this gap
// to the hull, m; the growth is found to 0.3 m / 2^10 = 0.3 mm.
constexpr double kRatchetGapM = 0.005;
constexpr int kRatchetBisections = 10;

// How much to grow `hull`, placed in the robot frame by `robot_from_other`:
// `uncertain_m`, or less so that it stays kRatchetGapM off `footprint`, but
// never less than `certain_m`. `reaches_in`: even that reaches into it.
double RatchetedGrowth(const core::Polygon2& hull, const core::Pose2& robot_from_other,
                       const core::Polygon2& footprint, double certain_m, double uncertain_m,
                       bool* reaches_in) {
  const auto gap_at = [&](double grow_m) {
    core::Polygon2 other = InflateConvexPolygon(hull, grow_m);
    for (Eigen::Vector2d& c : other) c = robot_from_other * c;
    return core::ConvexPolygonGap(footprint, other);
  };
  *reaches_in = false;
  if (uncertain_m <= certain_m || gap_at(uncertain_m) >= kRatchetGapM) return uncertain_m;
  if (gap_at(certain_m) < kRatchetGapM) {
    *reaches_in = true;
    return certain_m;
  }
  double lo = certain_m;  // the largest growth found that leaves the gap
  double hi = uncertain_m;
  for (int i = 0; i < kRatchetBisections; ++i) {
    const double mid = 0.5 * (lo + hi);
    (gap_at(mid) >= kRatchetGapM ? lo : hi) = mid;
  }
  return lo;
}

// Where the ray from the origin (inside the convex, counter-clockwise
// `outline`) through `p` leaves it; `p` itself at the origin.
Eigen::Vector2d OntoOutline(const core::Polygon2& outline, const Eigen::Vector2d& p) {
  double t = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < outline.size(); ++i) {
    const Eigen::Vector2d& a = outline[i];
    const Eigen::Vector2d edge = outline[(i + 1) % outline.size()] - a;
    const Eigen::Vector2d normal(edge.y(), -edge.x());  // outward
    const double towards = normal.dot(p);
    if (towards > 0.0) t = std::min(t, normal.dot(a) / towards);
  }
  return std::isfinite(t) ? Eigen::Vector2d(t * p) : p;
}

// The points of `points` from `first` on (in a frame that `robot_from_frame`
// maps to this robot's) within this robot's `margin_outline`: left out, or,
// with `pushed_outline`, moved out onto it (the ray from the robot's centre).
// A lost robot's belief may be decimetres off and its points are left out
// (its lasers and markers show it as it is); a localized robot's is
// centimetres off: its points are moved, so that the window still sees the
// other's face and backs off straight rather than turning its corners into it.
void ClearMargin(const core::Polygon2& margin_outline, const core::Polygon2* pushed_outline,
                 const core::Pose2& robot_from_frame, std::size_t first,
                 std::vector<Eigen::Vector2d>* points) {
  const auto begin = points->begin() + static_cast<std::ptrdiff_t>(first);
  if (pushed_outline == nullptr) {
    points->erase(std::remove_if(begin, points->end(),
                                 [&](const Eigen::Vector2d& p) {
                                   return core::Contains(margin_outline, robot_from_frame * p);
                                 }),
                  points->end());
    return;
  }
  const core::Pose2 frame_from_robot = robot_from_frame.Inverse();
  for (auto it = begin; it != points->end(); ++it) {
    const Eigen::Vector2d q = robot_from_frame * *it;
    if (core::Contains(margin_outline, q)) *it = frame_from_robot * OntoOutline(*pushed_outline, q);
  }
}

}  // namespace

void NavigationController::SwitchGoal(const ControlTick& tick,
                                      const std::function<bool(int)>& taken, const char* cause) {
  // The station goes back to the round and the robot proposes another, the
  // same mission driving on to a new goal (or waiting when none is free). A
  // rest trip drives on to another free rest node.
  const auto taken_or_left = [&](int n) { return taken(n) || n == reserved_node_; };
  MissionSequence::Proposal p;
  if (rest_trip_) {
    if (const std::optional<int> rest = FreeRestNode(tick, taken_or_left)) {
      p.goal = map_.nodes[static_cast<std::size_t>(*rest)].id;
    }
  } else {
    if (!revisit_) missions_.GiveBack(current_.goal);
    revisit_ = false;
    p = missions_.NextFree([&](const std::string& id) {
      const std::optional<int> n = graph_.FindIndex(id);
      return n && taken_or_left(*n);
    });
  }
  const int node = p.goal ? graph_.FindIndex(*p.goal).value_or(kNoNode) : kNoNode;
  if (node == kNoNode) {  // nothing else free: stand until the board changes
    if (p.goal && !rest_trip_) missions_.GiveBack(*p.goal);
    // Still waiting since before this mission: a robot that loses every
    // race for a freed station still gets to revisit or rest.
    station_wait_since_s_ = mission_waited_since_s_;
    reserved_node_ = kNoNode;
    queue_.Clear();
    command_ = {};
    state_ = State::kWaiting;
    --figures_.missions_started;  // started again when a station is free
    if (rest_trip_) --figures_.rest_missions;
    rest_trip_ = false;
    --mission_index_;
    return;
  }
  current_.goal = *p.goal;
  current_.goal_pose = map_.nodes[node].pose;
  reserved_node_ = node;
  if (!PlanGlobal(tick, kNoNode)) return EndMission(tick, false, AbortReason::kUnreachable);
  PlanLocal(tick, true, cause);
}

bool NavigationController::SeesRobotAt(const ControlTick& tick, int node) const {
  const core::Pose2 world_from_odom = tick.belief * tick.odometry.Inverse();
  const Eigen::Vector2d station = map_.nodes[static_cast<std::size_t>(node)].pose.translation();
  return std::any_of(markers_.begin(), markers_.end(), [&](const SeenMarker& m) {
    return (world_from_odom * m.centre_in_odom - station).norm() < options_.fleet_station_clear_m;
  });
}

void NavigationController::SwitchTakenGoal(const ControlTick& tick) {
  if (fleet_.coordinator) {
    // Another robot chose the same station in the same cycle and keeps it.
    const FleetBoard& board = fleet_.coordinator->board();
    if (reserved_node_ != kNoNode && board.ReservationLost(reserved_node_, fleet_.robot)) {
      SwitchGoal(
          tick, [&](int n) { return board.StationTaken(n, fleet_.robot); }, "station_taken");
    }
  } else if (GoalSeenTaken(tick)) {
    SwitchGoal(
        tick, [&](int n) { return SeesRobotAt(tick, n); }, "station_seen_taken");
  }
}

bool NavigationController::GoalSeenTaken(const ControlTick& tick) const {
  return options_.seen_station_look_m > 0.0 && reserved_node_ != kNoNode &&
         (tick.belief.translation() - current_.goal_pose.translation()).norm() <
             options_.seen_station_look_m &&
         SeesRobotAt(tick, reserved_node_);
}

MissionSequence::Proposal NavigationController::NextGoalBySight(const ControlTick& tick) {
  MissionSequence::Proposal p{missions_.Next(), false, false};
  // A station where another robot is seen is not proposed while another one
  // is free.
  const auto seen_taken = [&](const std::string& id) {
    const std::optional<int> n = graph_.FindIndex(id);
    return options_.seen_station_look_m > 0.0 && n && SeesRobotAt(tick, *n);
  };
  if (!p.goal || !seen_taken(*p.goal)) return p;
  missions_.GiveBack(*p.goal);
  p = missions_.NextFree(seen_taken);
  if (p.wait) ++figures_.station_waits;  // every remaining station is seen taken
  return p;
}

bool NavigationController::AtRest() const {
  return occupied_node_ != kNoNode &&
         std::find(rest_nodes_.begin(), rest_nodes_.end(), occupied_node_) != rest_nodes_.end();
}

std::optional<int> NavigationController::FreeRestNode(const ControlTick& tick,
                                                      const std::function<bool(int)>& taken) const {
  std::optional<int> best;
  double best_m = std::numeric_limits<double>::infinity();
  for (int n : rest_nodes_) {  // the nearest; ties to the first listed
    const double d_m = (graph_.position(n) - tick.belief.translation()).norm();
    if (!taken(n) && d_m < best_m) {
      best = n;
      best_m = d_m;
    }
  }
  return best;
}

void NavigationController::OccupyRestAtStart(const ControlTick& tick) {
  rest_checked_ = true;
  const FleetBoard& board = fleet_.coordinator->board();
  const std::optional<int> rest =
      FreeRestNode(tick, [&](int n) { return board.StationTaken(n, fleet_.robot); });
  if (occupied_node_ == kNoNode && rest &&
      (graph_.position(*rest) - tick.belief.translation()).norm() <=
          fleet_.coordinator->options().release_distance_m) {
    occupied_node_ = *rest;
  }
}

void NavigationController::SetFleet(FleetLink link) {
  fleet_ = link;
  claimable_.clear();
  if (!fleet_.coordinator) return;
  fleet_.coordinator->Join(fleet_.robot, footprint_);
  ratchet_outline_ = InflateConvexPolygon(footprint_, options_.dwa.safety_margin_m + kRatchetGapM);
  // The fleet's shared stations, or else those of the own missions.
  const std::vector<std::string>& shared = fleet_.coordinator->stations();
  for (const std::string& id : shared.empty() ? missions_.stations() : shared) {
    if (const std::optional<int> n = graph_.FindIndex(id)) claimable_.push_back(*n);
  }
  std::sort(claimable_.begin(), claimable_.end());
  claimable_.erase(std::unique(claimable_.begin(), claimable_.end()), claimable_.end());
}

std::vector<double> NavigationController::NodeCosts(int avoid_node) const {
  std::vector<double> costs(map_.nodes.size(), 0.0);
  if (avoid_node != kNoNode) costs[avoid_node] = options_.blocked_node_cost_m;
  if (fleet_.coordinator) {
    fleet_.coordinator->board().AddOthersCosts(
        fleet_.robot, fleet_.coordinator->options().occupied_station_cost_m, &costs);
  }
  return costs;
}

void NavigationController::Publish(const ControlTick& tick) {
  const FleetOptions& o = fleet_.coordinator->options();
  if (!rest_checked_ && !tick.localization_lost) OccupyRestAtStart(tick);
  // The station it stood at is free once the robot is well away from it.
  if (occupied_node_ != kNoNode && !tick.localization_lost &&
      (tick.belief.translation() - graph_.position(occupied_node_)).norm() > o.release_distance_m) {
    occupied_node_ = kNoNode;
  }
  // Lost, the robot neither claims nor releases: it does not know where it is.
  if (!tick.localization_lost) UpdateClaims(tick.belief.translation());
  FleetMessage m;
  m.reserved_station = reserved_node_;
  m.occupied_station = occupied_node_;
  m.claims = claims_;
  // Lost, it sends where it was last localized, carried on by its odometry
  // (ControlTick::last_localized; its belief without one) and says it is
  // lost: the others keep its hull there (a robot that declared itself lost
  // on gate failures is most often where it was) but no longer explain its
  // markers by it, so they also see its contour where it really is, as with
  // the coordination down. Its belief, once lost, follows the hypotheses of
  // global localization, look-alikes among them: others drove into lost
  // robots standing a median 0.98 m from the hulls they drew there, 0.08 m
  // from the last localized pose carried on (expo_rush seed 1, 2 h: 73 of
  // the 100 robot contacts were a localized robot driving into a lost one).
  m.pose = tick.localization_lost ? Placement(tick) : tick.belief;
  m.lost = tick.localization_lost;
  // With one hypothesis it may just as well be there (a kidnapped robot's
  // pose carried on is wrong, its lone hypothesis often right: expo_rush
  // seed 2, 989.7 s, robox_13 drove into robox_09 kidnapped 12 m and not
  // yet localized again, its hypothesis 2 mm off).
  if (tick.localization_lost && tick.lone_hypothesis && tick.last_localized) {
    m.also_at = tick.belief;
  }
  m.speed_mps = 0.5 * (command_.left_mps + command_.right_mps);
  m.turn_rate_radps = (command_.right_mps - command_.left_mps) / options_.dwa.wheelbase_m;
  m.outline_sigma_m = tick.position_sigma_m + circumradius_m_ * tick.heading_sigma_rad;
  if (state_ == State::kDriving && !queue_.empty()) {
    std::vector<int> nodes;
    std::vector<Eigen::Vector2d> positions;
    for (const QueuedNode& n : queue_.remaining()) {
      if (const std::optional<int> i = graph_.FindIndex(n.id)) {
        nodes.push_back(*i);
        positions.push_back(n.position_m);
      }
    }
    m.path = PlanWeights(tick.belief.translation(), nodes, positions, o);
  }
  fleet_.coordinator->Send(fleet_.robot, std::move(m));
}

void NavigationController::UpdateClaims(const Eigen::Vector2d& at) {
  const FleetOptions& o = fleet_.coordinator->options();
  const auto claimable = [&](int node) {
    return std::binary_search(claimable_.begin(), claimable_.end(), node);
  };
  // Stations whose ring it stands in, and those it holds and drives near.
  std::vector<int> wanted;
  const bool driving = state_ == State::kDriving;
  for (int s : claimable_) {
    const double d_m = (at - graph_.position(s)).norm();
    const bool held = std::binary_search(claims_.begin(), claims_.end(), s);
    if (d_m <= options_.fleet_station_clear_m || (driving && held && d_m <= o.claim_radius_m)) {
      wanted.push_back(s);
    }
  }
  // A station another robot holds: the robot waits before it and holds
  // nothing beyond it (no claim on a way it cannot take yet).
  const auto held_by_other = [&](int node) {
    return !std::binary_search(claims_.begin(), claims_.end(), node) &&
           fleet_.coordinator->board().ClaimedByOther(node, fleet_.robot);
  };
  // Stations its plan reaches soon (the distance along the plan, as the weights).
  if (driving) {
    double along_m = 0.0;
    Eigen::Vector2d from = at;
    for (const QueuedNode& n : queue_.remaining()) {
      along_m += (n.position_m - from).norm();
      from = n.position_m;
      if (along_m > o.claim_ahead_m) break;
      const std::optional<int> i = graph_.FindIndex(n.id);
      if (!i || !claimable(*i)) continue;
      if (held_by_other(*i)) break;
      wanted.push_back(*i);
    }
  }
  // Stations its band passes near soon. The band, not the plan's straight
  // legs, is the way the robot drives: in an hour-long expo_tours run a
  // robot bound for station_05 went 2 m off its leg round an exhibit and
  // crossed station_14's ring unclaimed in the same cycle as another passer.
  if (driving && local_->has_band()) {
    const double near_m = options_.fleet_station_clear_m + options_.fleet_claim_margin_m;
    // Claims the stations near the stretch a-b; false at one another robot holds.
    const auto claim_near = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
      for (int s : claimable_) {
        if (core::PointSegmentDistance(graph_.position(s), a, b) > near_m) continue;
        if (held_by_other(s)) return false;
        wanted.push_back(s);
      }
      return true;
    };
    double along_m = 0.0;
    Eigen::Vector2d from = at;
    for (const Bubble& b : local_->band().bubbles()) {
      if (along_m >= o.claim_ahead_m) break;
      // The band's stretch to this bubble, cut at claim_ahead_m.
      const double length_m = (b.center - from).norm();
      const Eigen::Vector2d to =
          along_m + length_m <= o.claim_ahead_m
              ? b.center
              : Eigen::Vector2d(from +
                                (b.center - from) * ((o.claim_ahead_m - along_m) / length_m));
      if (!claim_near(from, to)) break;
      along_m += length_m;
      from = b.center;
    }
  }
  std::sort(wanted.begin(), wanted.end());
  wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
  // A rest node is not a station of the tours: no claim, no ring (the docks
  // stand 0.95 m apart, within each other's rings).
  claims_ = fleet_.coordinator->board().ResolveClaims(
      fleet_.robot, wanted, claims_, claimable(occupied_node_) ? occupied_node_ : kNoNode);
}

double NavigationController::RemainingPathCost(const Eigen::Vector2d& position,
                                               const std::vector<double>& costs) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const std::span<const QueuedNode> rest = queue_.remaining();
  if (rest.empty()) return kInf;
  // The straight leg to the next node, as PlanFromPosition joins a position.
  for (const auto& [a, b] : walls_) {
    if (core::SegmentsCross(position, rest.front().position_m, a, b)) return kInf;
  }
  double cost = (rest.front().position_m - position).norm();
  std::optional<int> from = graph_.FindIndex(rest.front().id);
  if (!from) return kInf;
  cost += graph_.node_cost(*from) + costs[*from];
  for (std::size_t i = 1; i < rest.size(); ++i) {
    const std::optional<int> to = graph_.FindIndex(rest[i].id);
    if (!to) return kInf;
    double arc = kInf;
    for (const GraphArc& a : graph_.arcs_from(*from)) {
      if (a.to == *to && !a.blocked) arc = std::min(arc, a.weight);
    }
    cost += arc + graph_.node_cost(*to) + costs[*to];
    from = to;
  }
  return cost;
}

void NavigationController::FleetReplan(const ControlTick& tick) {
  const std::vector<double> costs = NodeCosts(kNoNode);
  const int goal = graph_.FindIndex(current_.goal).value_or(kNoNode);
  if (goal == kNoNode) return;
  const std::optional<GraphPath> path =
      PlanFromPosition(graph_, map_, tick.belief.translation(), goal, options_.graph, costs);
  if (!path) return;
  const double current = RemainingPathCost(tick.belief.translation(), costs);
  if (!(path->cost + options_.fleet_replan_gain_m < current)) return;
  const std::span<const QueuedNode> rest = queue_.remaining();
  const bool same =
      rest.size() == path->nodes.size() &&
      std::equal(rest.begin(), rest.end(), path->nodes.begin(),
                 [&](const QueuedNode& q, int n) { return q.id == map_.nodes[n].id; });
  if (same) return;
  ++figures_.global_plans;
  ++figures_.fleet_replans;
  std::vector<QueuedNode> nodes;
  for (int n : path->nodes) nodes.push_back({map_.nodes[n].id, map_.nodes[n].pose.translation()});
  queue_.Load(std::move(nodes), current_.goal_pose);
  queue_.Update(tick.belief);
  next_fleet_check_s_ = tick.now_s + options_.fleet_commit_s;
  PlanLocal(tick, true, "fleet");
}

void NavigationController::AppendOtherRobots(const ControlTick& tick,
                                             const core::Pose2& frame_from_world, double reach_m,
                                             std::vector<Eigen::Vector2d>* points) const {
  if (!fleet_.coordinator) return;
  AppendStationRings(tick.belief, frame_from_world, reach_m, points);
  AppendOtherHulls(tick, frame_from_world, reach_m, options_.fleet_hull_margin_m, points);
}

void NavigationController::AppendOtherHulls(const ControlTick& tick,
                                            const core::Pose2& frame_from_world, double reach_m,
                                            double margin_m,
                                            std::vector<Eigen::Vector2d>* points) const {
  if (!fleet_.coordinator) return;
  const FleetBoard& board = fleet_.coordinator->board();
  for (int r = 0; r < board.robots(); ++r) {
    const FleetMessage& m = board.message(r);
    if (r == fleet_.robot || !m.pose || board.footprint(r).empty()) continue;
    // A robot not localized may be at either pose it sends: drawn at both.
    AppendOtherHull(tick, frame_from_world, reach_m, margin_m, m, board.footprint(r), *m.pose,
                    points);
    if (m.also_at) {
      AppendOtherHull(tick, frame_from_world, reach_m, margin_m, m, board.footprint(r), *m.also_at,
                      points);
    }
  }
}

void NavigationController::AppendOtherHull(const ControlTick& tick,
                                           const core::Pose2& frame_from_world, double reach_m,
                                           double margin_m, const FleetMessage& m,
                                           const std::vector<Eigen::Vector2d>& hull,
                                           const core::Pose2& at,
                                           std::vector<Eigen::Vector2d>* points) const {
  const core::Pose2& belief = tick.belief;
  // Outline points at most this far apart (the ghost barriers' fill).
  const double spacing_m = options_.ghost_barrier.fill_m;
  // A robot that declared itself lost publishes a belief that may be as far
  // off as the one a lost robot has of the others (lost_hull_margin_m).
  // Otherwise both beliefs' sigmas say how far off the hull may be drawn
  // (fleet_hull_sigmas): this robot's heading error swings it about this
  // robot by the distance between them.
  const double distance_m = (m.pose->translation() - belief.translation()).norm();
  const double sigma_m =
      std::hypot(tick.position_sigma_m + distance_m * tick.heading_sigma_rad, m.outline_sigma_m);
  const double uncertain_m = m.lost
                                 ? std::max(margin_m, options_.lost_hull_margin_m)
                                 : std::max(margin_m, std::min(options_.fleet_hull_sigmas * sigma_m,
                                                               options_.lost_hull_margin_m));
  const double radius_m = Circumradius(hull) + uncertain_m;
  if (distance_m > reach_m + radius_m) return;
  const core::Pose2 frame_from_robot = frame_from_world * at;
  // The growth for uncertainty never covers this robot: it stops
  // kRatchetGapM short of its hull, a ratchet that lets it move away but
  // not closer. A hull drawn that much larger around a robot that declared
  // itself lost beside this one covered its centre, and it stood 17 minutes
  // (expo_tours seed 4, 2,596 s: robox_08 lost 0.4 m off its belief, its
  // lone hypothesis never pinned while robox_02 hid the crossing walls).
  // Where even the hull grown by margin_m reaches into this robot (a belief
  // that far off), that outline's points within its margin are left out,
  // as a lost robot leaves out the others' (Explore); its lasers and
  // markers show the other as it is.
  // A localized robot's hull is grown by margin_m the same way: the growth
  // stops short of this robot, and where its bare hull reaches in (the two
  // touched: beliefs a centimetre off, the recessed bodies of §6.3.5.1
  // hiding their true size from the lasers) its points within the margin
  // are moved out onto it (ClearMargin). Drawn whole, it held two robots
  // face to face for 470 s (expo_day seed 3, 4,430 s: robox_01 and robox_08).
  bool drop_inside = false;
  core::Polygon2 grown = InflateConvexPolygon(hull, uncertain_m);
  const bool near = distance_m < Circumradius(grown) + circumradius_m_ + kRatchetGapM;
  if (near) {
    const double certain_m = m.lost ? margin_m : 0.0;
    const double grow_m = RatchetedGrowth(hull, belief.Inverse() * at, footprint_, certain_m,
                                          uncertain_m, &drop_inside);
    if (grow_m != uncertain_m) grown = InflateConvexPolygon(hull, grow_m);
  }
  // A moving robot is drawn also where it will be when it has stopped: on
  // the arc of its commanded speed and turn rate, as the dynamic window
  // models a command (held a cycle, then both wheels braked in proportion
  // at the limit, so the robot stops on the same arc), plus the age of the
  // pose. Two robots closing in on each other then do not each brake only
  // for where the other is now, nor for where it would go straight on
  // while it turns (expo_tours seed 5, 1,650 s: two robots turning into
  // each other touched).
  const double v = m.speed_mps;
  const double w = m.turn_rate_radps;
  const double half_b = 0.5 * options_.dwa.wheelbase_m;
  const double brake_s = std::max(std::abs(v - w * half_b), std::abs(v + w * half_b)) /
                         options_.dwa.max_wheel_accel_mps2;
  // Braking in proportion halves the mean speeds: the stop is where the
  // command held for half the braking time leads.
  const double ahead_s = 1.0 / options_.dwa_rate_hz + kPoseAgeS + 0.5 * brake_s;
  const std::size_t first = points->size();
  AppendSweptOutline(grown, BodyTwist{v, w}, ahead_s, kSweepStepM, spacing_m, frame_from_robot,
                     points);
  if (!drop_inside) return;
  ClearMargin(margin_outline_, m.lost ? nullptr : &ratchet_outline_,
              (frame_from_world * belief).Inverse(), first, points);
}

void NavigationController::AppendStationRings(const core::Pose2& belief,
                                              const core::Pose2& frame_from_world, double reach_m,
                                              std::vector<Eigen::Vector2d>* points) const {
  // The ring keeps this robot's centre fleet_station_clear_m from the node:
  // its radius is that less the footprint's inradius (the hull's nearest side).
  const double ring_m = options_.fleet_station_clear_m - inradius_m_;
  if (ring_m <= 0.0) return;
  const FleetBoard& board = fleet_.coordinator->board();
  const auto inside = [&](int station, const Eigen::Vector2d& p) {
    return (p - graph_.position(station)).norm() <= options_.fleet_station_clear_m;
  };
  const Eigen::Vector2d self = belief.translation();
  std::vector<int> own = claims_;
  if (reserved_node_ != kNoNode && !rest_trip_) own.push_back(reserved_node_);
  std::vector<int> rings, ratchets;
  for (int r = 0; r < board.robots(); ++r) {
    const FleetMessage& m = board.message(r);
    if (r == fleet_.robot || !m.pose) continue;
    // The stations the others claim. A robot already well inside (crossing
    // the node when the other claimed it) is not trapped: it sees no ring and
    // leaves, the other waits. One that slipped less than kRingSlipM past the
    // ring sees it drawn just outside its hull: a ratchet that lets it out,
    // not in. A station claimed by both in the same cycle is settled by the
    // claim rule within a cycle.
    for (int station : m.claims) {
      if (station < 0 || station >= graph_.node_count()) continue;
      if (std::binary_search(claims_.begin(), claims_.end(), station)) continue;
      if (!inside(station, self)) {
        rings.push_back(station);
      } else if ((self - graph_.position(station)).norm() >
                 options_.fleet_station_clear_m - kRingSlipM) {
        ratchets.push_back(station);
      }
    }
    // A station this robot claims or heads for while another robot
    // (claiming it or not) is inside its ring: wait outside until it has left.
    for (int station : own) {
      const bool in = inside(station, m.pose->translation()) ||
                      (m.also_at && inside(station, m.also_at->translation()));
      if (in && !inside(station, self)) {
        rings.push_back(station);
      }
    }
  }
  const auto append_ring = [&](const Eigen::Vector2d& at, double radius_m) {
    const std::size_t first = points->size();
    AppendContour(at, radius_m, options_.ghost_barrier.fill_m, points);
    for (std::size_t k = first; k < points->size(); ++k) {
      (*points)[k] = frame_from_world * (*points)[k];
    }
  };
  std::sort(rings.begin(), rings.end());
  rings.erase(std::unique(rings.begin(), rings.end()), rings.end());
  for (int station : rings) {
    const Eigen::Vector2d& at = graph_.position(station);
    if ((self - at).norm() > reach_m + ring_m) continue;
    append_ring(at, ring_m);
  }
  std::sort(ratchets.begin(), ratchets.end());
  ratchets.erase(std::unique(ratchets.begin(), ratchets.end()), ratchets.end());
  for (int station : ratchets) {
    if (std::binary_search(rings.begin(), rings.end(), station)) continue;
    const Eigen::Vector2d& at = graph_.position(station);
    double hull_m = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < footprint_.size(); ++i) {
      hull_m = std::min(
          hull_m, core::PointSegmentDistance(at, belief * footprint_[i],
                                             belief * footprint_[(i + 1) % footprint_.size()]));
    }
    if (hull_m - kRatchetGapM > 0.0) append_ring(at, hull_m - kRatchetGapM);
  }
}

}  // namespace pavilion::nav
