#pragma once

// How close the fleet's robots come to each other (issue 15, metrics.md
// "Navigation and fleet"): the distance between their true hulls after each
// physics step — ground truth, for the metrics only, never given to a robot.
// A near miss is an episode of two hulls closer than `near_m` (0.2 m; a
// contact counts as one too), ended once they are `near_m + kNearHysteresisM`
// apart again.

#include <Eigen/Core>
#include <limits>
#include <span>
#include <vector>

#include "core/geometry/polygon.h"
#include "core/types/pose2.h"

namespace pavilion::scenarios {

struct ProximityFigures {
  double min_distance_m = std::numeric_limits<double>::infinity();  // hull to hull
  int near_misses = 0;
  double time_near_s = 0.0;  // inside near-miss episodes (a pair counts its time once)
  // Episodes of two or more robot centres within the station radius of the
  // same station node (goal coordination's bound; fleet figures only).
  int station_conflicts = 0;
};

// The distance between two convex polygons (0 when they touch or overlap).
double ConvexPolygonDistance(const core::Polygon2& a, const core::Polygon2& b);

class RobotProximity {
 public:
  static constexpr double kNearHysteresisM = 0.05;
  // `footprints`: each robot's convex outline in its own frame.
  explicit RobotProximity(std::vector<core::Polygon2> footprints, double near_m = 0.2);

  struct NearMiss {
    int a = 0;  // robot indices, a < b
    int b = 0;
    double distance_m = 0.0;
  };
  struct StationConflict {
    int station = 0;          // index into the watched stations
    std::vector<int> robots;  // the robots within the radius, ascending
  };
  // The robots' true poses after a step of dt_s; the pairs that began a near
  // miss are appended to `began`, the station conflicts that began to
  // `conflicts` (when given).
  void Update(double dt_s, std::span<const core::Pose2> poses, std::vector<NearMiss>* began,
              std::vector<StationConflict>* conflicts = nullptr);

  // The station nodes (world frame) watched for two robots at once within
  // `radius_m` of their centres.
  void WatchStations(std::vector<Eigen::Vector2d> stations, double radius_m = 1.0);

  const ProximityFigures& robot(int k) const { return robots_.at(static_cast<std::size_t>(k)); }
  const ProximityFigures& fleet() const { return fleet_; }

 private:
  std::vector<core::Polygon2> footprints_;
  std::vector<double> radii_m_;  // circumradii, for the quick rejection
  double near_m_;
  std::vector<char> near_;  // per pair (a, b), a < b: inside an episode
  std::vector<ProximityFigures> robots_;
  ProximityFigures fleet_;
  std::vector<Eigen::Vector2d> stations_;
  std::vector<char> station_shared_;  // per station: inside a conflict episode
  double station_radius_m_ = 1.0;
  core::Polygon2 scratch_a_;
  core::Polygon2 scratch_b_;
};

}  // namespace pavilion::scenarios
