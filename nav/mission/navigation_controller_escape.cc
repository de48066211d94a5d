// The navigation controller's escape from a pocket (EscapeOptions): when it
// starts and ends, the way out (a bearing, straight back or on, or the creep
// with the margin cut), and the pockets remembered for the band; and its
// exploring while not localized (explore_when_lost).

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "nav/mission/navigation_controller.h"
#include "nav/reactive/explore_direction.h"
#include "nav/reactive/swept_polygon.h"

namespace pavilion::nav {
namespace {

// The escape's creep (EscapeWay::kCreep): where the window, held to its
// safety margin, keeps the robot standing this many cycles of an escape, it
// drives straight back (else straight on) at kCreepSpeedMps with the margin
// cut to kCreepMarginM, the exact outline judging, while that way is free for
// kCreepMinFreeM, until no point is within the full margin plus kCreepClearM.
// Pygmalion askew in a 0.9 m door stood for good with the door post's map
// outline 1.8-2.0 cm beside its wheel hub, inside the 2 cm margin: the hub,
// on the wheel axis, moves only along the robot's axis, so every motion
// brought a point on one side of it nearer and the window admitted none
// (computer2000, seed 1, office_08's door from 3,208 s).
constexpr int kCreepAfterCycles = 10;
constexpr double kCreepMarginM = 0.005;
constexpr double kCreepSpeedMps = 0.05;
constexpr double kCreepMinFreeM = 0.05;
constexpr double kCreepClearM = 0.01;
// A creep that begins in contact — a point inside the outline — judges with
// no margin and lets the points inside get this much deeper while it passes
// them (DwaGoal::contact_slack_m): a wheel hub's round side sliding off a
// door post's corner whose points lie on both sides of the wheel axis, where
// every motion the drive allows first takes one of them deeper (3.2 mm for a
// point 1.6 cm beside the axis, on the outline's 16-gon hub). Pygmalion
// stood so for 18 hours, the post 1.7 cm into its hub (computer2000, seed 1,
// office_09's door, 34,015 s).
constexpr double kCreepContactSlackM = 0.004;
// The turn towards an escape bearing creeps too (the margin cut to
// kCreepMarginM) once it has been held this many cycles more than
// kTurnedRad from the bearing with some point within the circle its corners
// sweep, grown by the full margin plus kCreepClearM: the window then admits
// only a crawl, its corners sweeping 2.8 cm past an octagon's sides. A Robox
// between a pedestal and a glass panel's ghost barrier, points 1.4-2.4 cm
// outside that circle, turned 1 deg/s for 6 s per escape and stood 92 s
// (expo_tours seed 5, robox_07 at 828 s).
constexpr int kCreepTurnAfterCycles = 10;
constexpr double kTurnedRad = 0.35;

// The clearance of the circle the robot sweeps turning on the spot, m.
double TurnClearance(std::span<const Eigen::Vector2d> points, double circumradius_m) {
  double nearest_m = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector2d& p : points) nearest_m = std::min(nearest_m, p.norm());
  return nearest_m - circumradius_m;
}

}  // namespace

void NavigationController::ResetProgress(const ControlTick& tick) {
  progress_anchor_ = tick.odometry.translation();
  progress_since_s_ = tick.now_s;
  escape_until_s_.reset();
}

Eigen::Vector2d NavigationController::AheadAlong(double bearing_rad) const {
  return options_.band_lookahead_m * Eigen::Vector2d(std::cos(bearing_rad), std::sin(bearing_rad));
}

void NavigationController::AppendPockets(double now_s, std::vector<Eigen::Vector2d>* points) {
  std::erase_if(pockets_, [&](const PocketMark& p) { return now_s >= p.until_s; });
  constexpr int kMarkPoints = 12;
  for (const PocketMark& p : pockets_) {
    for (int k = 0; k < kMarkPoints; ++k) {
      const double a = 2.0 * std::numbers::pi * k / kMarkPoints;
      points->push_back(p.at_in_map +
                        options_.escape.mark_radius_m * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
  }
}

std::optional<double> NavigationController::ChooseEscapeWay(const ControlTick& tick) {
  const EscapeOptions& o = options_.escape;
  // The way out: the freest bearing it can turn to (its circumcircle swept),
  // else straight back the way it came, else straight on — each kept while
  // it stays free for min_free_m.
  const double margin_m = options_.dwa.safety_margin_m;
  const auto straight_free = [&](bool reverse) {
    return StraightFreeTravel(points_, footprint_, reverse, margin_m, options_.explore.reach_m);
  };
  ExploreOptions fan = options_.explore;
  fan.min_free_m = std::min(o.min_free_m, fan.reach_m);
  fan.keep_free_m = fan.min_free_m;
  if ((escape_way_ == EscapeWay::kReverse || escape_way_ == EscapeWay::kForward) &&
      straight_free(escape_way_ == EscapeWay::kReverse) < fan.min_free_m) {
    escape_way_ = EscapeWay::kNone;
  }
  const auto creep_free = [&](bool reverse) {
    return creep_from_contact_
               ? StraightPolygonTravel(points_, footprint_, reverse, 0.0, options_.explore.reach_m,
                                       kCreepContactSlackM)
               : StraightPolygonTravel(points_, footprint_, reverse, kCreepMarginM,
                                       options_.explore.reach_m);
  };
  if (escape_way_ == EscapeWay::kCreep &&
      (PolygonClearance(footprint_, points_) > margin_m + kCreepClearM ||
       creep_free(creep_reverse_) < kCreepMinFreeM)) {
    escape_way_ = EscapeWay::kNone;  // out of the margin (or the way closed): choose again
    escape_stalls_ = 0;
  }
  std::optional<double> bearing;
  if (escape_way_ == EscapeWay::kNone || escape_way_ == EscapeWay::kBearing) {
    std::optional<double> current;
    if (escape_way_ == EscapeWay::kBearing) {
      current = core::NormalizeAngle(escape_heading_ - tick.odometry.theta_rad);
    }
    bearing = ExploreBearing(points_, current, circumradius_m_ + margin_m, fan);
    escape_way_ = bearing                                  ? EscapeWay::kBearing
                  : straight_free(true) >= fan.min_free_m  ? EscapeWay::kReverse
                  : straight_free(false) >= fan.min_free_m ? EscapeWay::kForward
                                                           : EscapeWay::kNone;
  }
  if (escape_way_ != EscapeWay::kCreep && escape_stalls_ >= kCreepAfterCycles) {
    creep_from_contact_ = PolygonClearance(footprint_, points_) <= 0.0;
    creep_reverse_ = creep_free(true) >= kCreepMinFreeM;
    if (creep_reverse_ || creep_free(false) >= kCreepMinFreeM) escape_way_ = EscapeWay::kCreep;
  }
  return bearing;
}

bool NavigationController::Escape(const ControlTick& tick) {
  const EscapeOptions& o = options_.escape;
  const Eigen::Vector2d at = tick.odometry.translation();
  if (!escape_until_s_) {
    if ((at - progress_anchor_).norm() > o.still_m) ResetProgress(tick);
    if (o.after_s <= 0.0 || tick.now_s - progress_since_s_ < o.after_s || contour_overlap_) {
      return false;
    }
    escape_until_s_ = tick.now_s + o.drive_s;
    escape_from_ = at;
    escape_way_ = EscapeWay::kNone;
    escape_stalls_ = 0;
    creep_turn_cycles_ = 0;
    ++figures_.escapes;
    if (o.remember_s > 0.0)
      pockets_.push_back({tick.belief.translation(), tick.now_s + o.remember_s});
  } else if (tick.now_s + 1e-9 >= *escape_until_s_ || (at - escape_from_).norm() >= o.leave_m) {
    // Out (or as far as it got): a new plan from here, avoiding the node it
    // could not reach.
    ResetProgress(tick);
    const int avoid =
        graph_.FindIndex(queue_.empty() ? current_.goal : queue_.current().id).value_or(kNoNode);
    if (!PlanGlobal(tick, avoid)) {
      EndMission(tick, false, AbortReason::kUnreachable);
      return true;
    }
    PlanLocal(tick, true, "escape");
    return false;
  }
  GatherDrivePoints(tick);
  AddBumpersAndMeasure(tick);
  const std::optional<double> bearing = ChooseEscapeWay(tick);
  arc_in_world_.clear();
  if (escape_way_ == EscapeWay::kNone) {  // no way out now: stand until the time is up
    ++escape_stalls_;
    UpdateDeadlock(tick, true);
    return true;
  }
  DwaGoal goal;
  if (escape_way_ == EscapeWay::kBearing) {
    escape_heading_ = core::NormalizeAngle(*bearing + tick.odometry.theta_rad);
    goal.target_in_robot = AheadAlong(*bearing);
    const bool cramped =
        std::abs(*bearing) > kTurnedRad &&
        TurnClearance(points_, circumradius_m_) <= options_.dwa.safety_margin_m + kCreepClearM;
    creep_turn_cycles_ = cramped ? creep_turn_cycles_ + 1 : 0;
  } else {
    creep_turn_cycles_ = 0;
    goal.reverse =
        escape_way_ == EscapeWay::kCreep ? creep_reverse_ : escape_way_ == EscapeWay::kReverse;
    goal.target_in_robot =
        Eigen::Vector2d(goal.reverse ? -options_.band_lookahead_m : options_.band_lookahead_m, 0.0);
  }
  goal.speed_limit_mps = std::min(o.speed_mps, UncertainSpeedLimit(tick));
  // A pocket is where the table's cell-sized caution leaves only a crawl.
  goal.exact_clearance = true;
  if (escape_way_ == EscapeWay::kCreep || creep_turn_cycles_ > kCreepTurnAfterCycles) {
    goal.speed_limit_mps = std::min(goal.speed_limit_mps, kCreepSpeedMps);
    goal.margin_m = std::min(kCreepMarginM, options_.dwa.safety_margin_m);
  }
  if (escape_way_ == EscapeWay::kCreep && creep_from_contact_) {
    goal.margin_m = 0.0;
    goal.contact_slack_m = kCreepContactSlackM;
  }
  const DwaResult result = Steer(tick, goal);
  const bool standing = result.command.left_mps == 0.0 && result.command.right_mps == 0.0 &&
                        held_.left_mps == 0.0 && held_.right_mps == 0.0;
  escape_stalls_ = standing ? escape_stalls_ + 1 : 0;
  UpdateDeadlock(tick, !result.admissible_found);
  return true;
}

void NavigationController::ForgetTouchesBefore(double s) {
  std::erase_if(touched_in_odometry_, [&](const auto& touched) { return touched.first < s; });
}

void NavigationController::Explore(const ControlTick& tick) {
  const bool stalled = ExploreStep(tick);
  // A robot relocalizing holds its mission: a deadlock it is in still counts.
  if (state_ == State::kRelocalizing) UpdateDeadlock(tick, stalled);
}

bool NavigationController::ExploreStep(const ControlTick& tick) {
  if (!options_.explore_when_lost || !tick.localization_lost ||
      tick.now_s - lost_since_s_ < options_.explore.settle_s) {
    points_.clear();  // standing: only the overlap the deadlock monitor reads
    AppendContours(tick, clip_contours_, &points_);
    return true;
  }
  // The map's ghost barriers and the others' hulls and stations are placed
  // where it was last localized, carried on by odometry (Placement), and
  // with one hypothesis by that too: where either pose puts an exit or
  // another robot, it keeps out. (expo_rush seed 2: a Robox drove out
  // through the exit its pose carried on placed 1.3 m off, its lone
  // hypothesis 2-4 cm from the truth.)
  ControlTick placed = tick;
  placed.belief = Placement(tick);
  std::vector<ControlTick> placements{placed};
  if (tick.lone_hypothesis && tick.last_localized) placements.push_back(tick);
  obstacles_.InRobot(tick.odometry, placed.belief, options_.dwa_reach_m, &points_,
                     /*map_outline=*/false);
  for (std::size_t k = 1; k < placements.size(); ++k) {
    obstacles_.AppendGhostBarriers(placements[k].belief, options_.dwa_reach_m, &points_);
  }
  const std::size_t sensed = points_.size();
  for (const ControlTick& at : placements) {
    AppendOtherHulls(at, at.belief.Inverse(), options_.dwa_reach_m, options_.lost_hull_margin_m,
                     &points_);
  }
  // The stations the others hold, placed as their hulls are: a
  // robot falsely lost that explored into one came within 1 m of the node as
  // another arrived (expo_tours seed 1, 120.6 s, station_09; its belief was
  // 4 mm off). A kidnapped one keeps out of a phantom ring.
  for (const ControlTick& at : placements) {
    if (!fleet_.coordinator) break;
    AppendStationRings(at.belief, at.belief.Inverse(), options_.dwa_reach_m, &points_);
  }
  points_.erase(
      std::remove_if(points_.begin() + static_cast<std::ptrdiff_t>(sensed), points_.end(),
                     [&](const Eigen::Vector2d& p) { return core::Contains(margin_outline_, p); }),
      points_.end());
  // Contours clipped as the deadlock rule says: a lost robot in a pile of
  // robots sees their markers as well as a localized one does.
  AppendContours(placed, clip_contours_, &points_);
  if (tick.now_s <= bumper_until_s_) {
    points_.insert(points_.end(), bumper_points_.begin(), bumper_points_.end());
  }
  std::optional<double> current;
  if (explore_heading_) {
    current = core::NormalizeAngle(*explore_heading_ - tick.odometry.theta_rad);
  }
  // What the bumpers met lately, for the bearing alone (ExploreOptions::contact_memory_s):
  // appended for the choice, then dropped again before the dynamic window.
  ForgetTouchesBefore(tick.now_s - options_.explore.contact_memory_s);
  const std::size_t seen = points_.size();
  const core::PointTransform robot_from_odometry(tick.odometry.Inverse());
  for (const auto& [at_s, p] : touched_in_odometry_) {
    points_.push_back(robot_from_odometry.Apply(p));
  }
  const std::optional<double> bearing = ExploreBearing(
      points_, current, circumradius_m_ + options_.dwa.safety_margin_m, options_.explore);
  points_.resize(seen);
  arc_in_world_.clear();
  if (!bearing) {  // nowhere open: stand until the others or the crowd move
    explore_heading_.reset();
    return true;
  }
  explore_heading_ = core::NormalizeAngle(*bearing + tick.odometry.theta_rad);
  DwaGoal goal;
  goal.target_in_robot = AheadAlong(*bearing);
  goal.speed_limit_mps = options_.explore.speed_mps;
  return !Steer(tick, goal).admissible_found;
}

}  // namespace pavilion::nav
