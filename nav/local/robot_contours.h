#pragma once

// Robots seeing robots (thesis §6.3.5.1): robots of the same design measure at
// the same height, so a laser underestimates another robot's size. Each robot
// carries two retro-reflecting markers on the vertical profiles of its blind
// zones, 0.34 m from its centre; a robot that sees a marker blows it up into a
// virtual robot contour of ghost points for the dynamic window, the anytime
// fall-back when the fleet coordinator's positions are missing.
//
// The model is an oversimplification (§6.5): two robots whose markers appear
// suddenly (a visitor stepped away) can each draw a contour into the other's
// hull and stop each other for good. ClipRadius and ContourOverlapsHull are the
// model correction the deadlock rule (nav/fleet/deadlock_monitor.h) applies:
// another robot cannot overlap our own hull, so such a contour is shrunk.

#include <Eigen/Core>
#include <span>
#include <vector>

#include "core/features/beacon_extraction.h"
#include "core/types/sensor_data.h"

namespace pavilion::nav {

struct RobotContourOptions {
  // Distance from a robot's centre to its markers, m, [0, 2]. Robox: the
  // markers sit on the left and right flats of its octagon, 0.68 m across.
  double marker_offset_m = 0.34;
  // Radius of the virtual contour around the implied centre, m, (0, 2].
  // Chosen: Robox's circumradius 0.34 / cos 22.5° = 0.368 m plus 5 cm, the
  // contour "blown up" (§6.3.5.1) because the other robot's heading is unknown;
  // it also covers the centre falling short by the marker's own 2.5 cm radius
  // (the laser reads the marker's near side, robots/robox/robot.yaml).
  double contour_radius_m = 0.42;
  // Ghost points on the contour at most this far apart, m, [0.005, 1]. Chosen:
  // as GhostBarrier::fill_m, so a corner reaches at most 1.5 cm between two.
  double point_spacing_m = 0.03;
  // Markers farther than this from the laser are ignored, m, (0, 100]. Chosen:
  // a contour that far cannot stop the dynamic window before the next scan.
  double max_range_m = 6.0;
  // Two markers of one scan this close to 2 * marker_offset_m apart, each the
  // other's only such partner, are one robot's pair: its centre is their
  // midpoint, not behind either (ours; the line-of-sight centre holds for a
  // robot showing one flank). Seen head-on, a Robox shows both markers, and
  // the centres behind them lay 0.35–0.5 m beside the robot's body, whose
  // recessed profile alone let another drive into it (expo_rush seed 1,
  // 371.9 s). m, [0, 0.5]; 0: no pairing. Chosen: the markers' 2.5 cm radius
  // on either side and the lit arc's few centimetres (core::LitArc).
  double pair_tolerance_m = 0.1;
  // How markers are cut out of the scan by their reflector flag (§3.3).
  core::BeaconExtractionOptions beacons;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// A marker of another robot and where that robot's centre is taken to be,
// both in the observer's robot frame.
struct SeenRobot {
  Eigen::Vector2d marker_in_robot = Eigen::Vector2d::Zero();
  // The marker pushed marker_offset_m farther along the line of sight from
  // the observing laser: the other robot lies behind the marker it shows;
  // or, for a marker of a pair (pair_tolerance_m), the pair's midpoint.
  Eigen::Vector2d centre_in_robot = Eigen::Vector2d::Zero();
};

// The robots whose markers `scan` shows within options.max_range_m, in the
// order of the scan's readings; the frame is the observer's robot frame
// (through scan.robot_from_sensor).
std::vector<SeenRobot> SeeRobots(const core::LaserScan& scan, const RobotContourOptions& options);

// Appends a circle of ghost points around `centre` (any frame), at most
// `spacing_m` apart, counter-clockwise from the +x direction; a single point
// for a radius of 0. Throws std::invalid_argument for a negative or non-finite
// radius, a spacing not > 0, or more than 1e5 points.
void AppendContour(const Eigen::Vector2d& centre, double radius_m, double spacing_m,
                   std::vector<Eigen::Vector2d>* points);

// The robots of `seen` whose implied centre is farther than `tolerance_m`
// from every centre in `known_centres_in_robot` (robots whose pose the fleet
// coordinator knows; those are drawn from the known pose instead), in order.
std::vector<SeenRobot> Unexplained(std::span<const SeenRobot> seen,
                                   std::span<const Eigen::Vector2d> known_centres_in_robot,
                                   double tolerance_m);

// The largest radius <= `radius_m` whose circle around `centre` stays
// `margin_m` outside `own_footprint` (the observer's convex CCW polygon, robot
// frame); never below 0 (0 when the centre is inside the hull).
double ClipRadius(const Eigen::Vector2d& centre, double radius_m,
                  std::span<const Eigen::Vector2d> own_footprint, double margin_m);

// True when the circle (centre, radius_m) reaches within `margin_m` of
// `own_footprint` (the centre's hull distance < radius_m + margin_m); for a
// radius > 0, exactly when ClipRadius would shrink it.
bool ContourOverlapsHull(const Eigen::Vector2d& centre, double radius_m,
                         std::span<const Eigen::Vector2d> own_footprint, double margin_m);

}  // namespace pavilion::nav
