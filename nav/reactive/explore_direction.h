#pragma once
// Where a robot drives while it does not know where it is (thesis Fig. 5.17:
// lost, or several hypotheses): new views let the interpretation tree find
// its location (§5.7.1), so it moves, but only by what it senses. The
// direction is chosen in the robot frame from the dynamic window's obstacle
// points (laser readings, the blind zones' memory, other robots' contours),
// never from the map or the belief: the freest of a fan of bearings, kept
// while it stays free so that the robot does not dither between two gaps.
// The dynamic window then drives towards it with the robot's true outline,
// as it does on a mission.
//
// Why not the hall benchmark's wander, which lost Robox used before: it
// looks at the front third of one laser and stops 0.3 m from a reading, while
// a Robox' two lasers leave its flanks blind. In the hour-long expo_tours runs
// half of the robot-robot contacts were a wandering Robox turning its flank
// into another (docs/benchmarks.md, "Lost robots drive by the dynamic window").
#include <Eigen/Core>
#include <optional>
#include <span>

namespace pavilion::nav {

struct ExploreOptions {
  // Bearings of the fan, evenly spaced around the robot, [4, 360].
  int bearings = 16;
  // A bearing whose free travel is shorter than this is not taken, m, (0, 10].
  // Chosen: a Robox length, so that the robot does not head into a pocket.
  double min_free_m = 0.6;
  // The current bearing is kept while its free travel is at least this, m,
  // [min_free_m, reach_m]. Chosen: the dynamic window's 1.2 m lookahead less
  // a braking distance.
  double keep_free_m = 1.0;
  // Free travel is looked for this far, m, (0, 20].
  double reach_m = 3.0;
  // Translation limit while exploring, m/s, (0, 2]. Chosen: half the Expo.02
  // mission speed — the robot is not sure of anything but its sensors.
  double speed_mps = 0.3;
  // The robot stands this long after the loss before it moves, s, [0, 600]:
  // most losses in a crowd are a few cycles without a match, and a robot
  // standing still relocalizes within a second (docs/benchmarks.md).
  double settle_s = 3.0;
  // Where the bumpers touched stays in the bearing's choice this long (held
  // in the odometry frame), s, [0, 600]. The lasers do not see what the
  // bumpers met (a bench, a glass panel, a plinth below the beam plane), so
  // the freest bearing led straight back into it: in expo_rush (seed 1, from
  // 1,626 s) a lost Robox explored into bench_1 451 times in 13 minutes. The
  // dynamic window does not get these points: a bumper memory there held
  // robots in place in the rush (docs/benchmarks.md, "Session 19").
  double contact_memory_s = 30.0;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// How far (m) the robot's origin can travel along `bearing_rad` (robot frame)
// before a corridor of half-width `half_width_m` reaches one of
// `points_in_robot`, measured from the point's nearest approach less
// `half_width_m`; capped at `reach_m`. Points behind the origin (along the
// bearing) or outside the corridor do not count.
double FreeTravel(std::span<const Eigen::Vector2d> points_in_robot, double bearing_rad,
                  double half_width_m, double reach_m);

// How far (m) the robot can drive straight ahead (or straight back with
// `reverse`) before its outline `footprint` grown by `margin_m` — taken as
// the box of its extents, so conservative — reaches one of
// `points_in_robot`; capped at `reach_m`. A robot wedged where it cannot
// turn can still back out the way it came.
double StraightFreeTravel(std::span<const Eigen::Vector2d> points_in_robot,
                          std::span<const Eigen::Vector2d> footprint, bool reverse, double margin_m,
                          double reach_m);

// How far (m) the robot can drive straight ahead (or straight back with
// `reverse`) before its convex outline `footprint` (counter-clockwise) grown
// by `margin_m` reaches one of `points_in_robot`, exactly; 0 when a point is
// inside the grown outline now; capped at `reach_m`. Unlike the box of
// StraightFreeTravel, a point beside the outline's narrower parts does not
// count: a square robot with wheel hubs bulging 4 cm from its sides, a door
// post beside the hub, can still drive straight on or back. A point inside
// the grown outline now does not count when the travel takes it out again
// no more than `contact_slack_m` deeper than it is (DwaGoal::contact_slack_m:
// the hub's round side pressed on a post's corner).
double StraightPolygonTravel(std::span<const Eigen::Vector2d> points_in_robot,
                             std::span<const Eigen::Vector2d> footprint, bool reverse,
                             double margin_m, double reach_m, double contact_slack_m = 0.0);

// The bearing to drive along (robot frame, rad in (-pi, pi]): `current` while
// its free travel is at least keep_free_m, else the freest bearing of the fan
// (ties to the one nearest ahead), provided it is free for min_free_m; none
// when no bearing is. `half_width_m`: the robot's circumradius (it turns
// into the bearing on the spot) plus a margin.
std::optional<double> ExploreBearing(std::span<const Eigen::Vector2d> points_in_robot,
                                     std::optional<double> current, double half_width_m,
                                     const ExploreOptions& options);

}  // namespace pavilion::nav
