#pragma once

// The free-space constraint of a location hypothesis: negative evidence, an
// addition to the thesis' constraints (§5.3), which all ask whether what is
// observed fits the map. This one asks whether the map fits what is observed:
// a laser beam that ends well beyond a mapped wall went through where the
// hypothesis says a wall stands. A visitor or an unmapped cupboard can shorten
// a beam, never lengthen it, so the test is one-sided and does not need the
// map to be complete — only its walls to be where it says.
//
// Why it is needed: where places repeat (the office floor's rooms, Fig. 4.8),
// the look-alikes pair the same observations with their own walls, and
// counting pairings (§5.5.2) separates them only by chance. What does separate
// them is seen through their openings: a beam through the true room's door
// into the corridor and across it into an open office ends where, in the
// look-alike, the corridor's far wall stands.
//
// Each beam is cast from the sensor pose of the hypothesis against the map's
// finite geometry (segments, multi-segment line members, columns; infinite
// lines have no extent and are left out). A beam contradicts the hypothesis
// when it crosses a wall and reads more than a margin beyond it. The margin
// and the distance a crossing must keep from a wall's end (door frames) grow
// with the hypothesis' own uncertainty, three sigma of where the beam lies.
//
// Two users: global localization (chapter 5) tests its hypotheses with it,
// and the chapter-4 tracker (Localizer) asks it, in a cycle where nothing
// paired, whether the scan showed the map at all (the beams short of it).

#include <utility>
#include <vector>

#include "core/map/map_geometry.h"
#include "core/odometry/diff_drive.h"
#include "core/types/sensor_data.h"

namespace pavilion::core {

struct FreeSpaceOptions {
  // Distance a beam must read beyond a mapped wall to contradict, before the
  // hypothesis' uncertainty is added, m; >= 0. Chosen: the LMS 200's range
  // sigma is 5-10 mm (§2.2.1) and walls are mapped to a few mm; 0.2 m leaves
  // room for a door leaf that stands a little open.
  double margin_m = 0.2;
  // Crossings closer than this to a wall's end are not counted (a beam past a
  // door frame, a map corner measured a few cm off), before the hypothesis'
  // uncertainty is added, m; >= 0.
  double end_clearance_m = 0.1;
  // Crossings at more than this angle from the wall's normal are not counted:
  // a grazing beam crosses far along the wall for a small pose error, rad;
  // in (0, pi/2).
  double max_incidence_rad = 1.3;  // ~75 deg
  // Sigmas of the hypothesis' position and heading the margins grow by; >= 0.
  double sigma_factor = 3.0;
  // Every `beam_stride`-th reading is cast (bounded cost); >= 1. An LMS 200 at
  // 0.5 deg gives 361 readings.
  int beam_stride = 1;
  // The constraint fails when more than this many cast beams, and more than
  // `max_see_through_ratio` of them, contradict (a specular surface or a map
  // error lets a beam through now and then); >= 0 and in [0, 1].
  int max_see_through = 1;
  double max_see_through_ratio = 0.01;
  // With Check's `count_short`: a run of consecutive cast beams that all end
  // at the same mapped wall counts for wall_run_m only when it has at least
  // this many beams; >= 2. Default: the fewest readings the line extraction
  // fits a line to (LineExtractionOptions::sparse_min_points of the SICK LMS
  // 200 preset).
  int min_wall_run_beams = 4;

  void Validate() const;  // throws std::invalid_argument naming the field
};

struct FreeSpaceCheck {
  int beams = 0;        // valid readings cast
  int see_through = 0;  // of them, beams that contradict the hypothesis
  // With Check's `count_short`: beams with a mapped wall or column within the
  // scan's range, and of them those that end more than the margin before it —
  // something unmapped stands in front of the map: a visitor, a cupboard.
  int mapped = 0;
  int short_of_map = 0;
  // With `count_short`: the longest stretch of a mapped wall, m, that a run
  // of at least min_wall_run_beams consecutive cast beams all ending at it
  // (neither short nor beyond) reached; 0 for none. The extraction keeps a
  // line only when one unbroken run of its readings is long enough
  // (LongestRunLength, segment_builder.cc): beams that reach a wall only
  // between visitors, in short runs, give it nothing, however many they are.
  double wall_run_m = 0.0;
};

// Holds the map's geometry; independent of the map object once built.
class FreeSpaceConstraint {
 public:
  explicit FreeSpaceConstraint(const RobotMap& map, const FreeSpaceOptions& options = {});

  // Casts the readings of `scan` (registered: every reading in the frame of
  // the scan's stamp, its mounting pose robot_from_sensor) from the robot
  // location `world_from_robot`.
  // With `count_short`, also counts the beams short of the map (one more
  // cast per beam).
  FreeSpaceCheck Check(const LaserScan& scan, const PoseWithCovariance& world_from_robot,
                       bool count_short = false) const;
  // Whether a check leaves the hypothesis standing.
  bool Satisfied(const FreeSpaceCheck& check) const;

  const FreeSpaceOptions& options() const { return options_; }

 private:
  // The walls (indices) a beam from `origin` can reach within max_range_m,
  // and the columns' cores (centre, radius less `clearance_m`) in reach.
  void InReach(const Eigen::Vector2d& origin, double max_range_m, double clearance_m,
               std::vector<std::size_t>* near,
               std::vector<std::pair<Eigen::Vector2d, double>>* cores) const;
  // Where a beam first meets the map: its range and the element it meets
  // (a segment's index, or the number of segments plus a column's index).
  struct MapCrossing {
    double range_m = 0.0;  // infinity for none within the scan's range
    std::size_t element = 0;
  };
  // Along the unit direction `u` from `origin`: the first mapped wall (of
  // `near`) or column within max_range_m.
  MapCrossing FirstMapCrossing(const Eigen::Vector2d& origin, const Eigen::Vector2d& u,
                               double max_range_m, const std::vector<std::size_t>& near) const;

  FreeSpaceOptions options_;
  MapGeometry geometry_;
};

}  // namespace pavilion::core
