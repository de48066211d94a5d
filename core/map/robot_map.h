#pragma once

// The a-priori map a robot is given (thesis §4.3, §6.3.1): geometric features
// with their hand-measurement uncertainty, the topology the navigation layer
// plans on, and ghost points. Everything is in the map (world) frame. Plain
// value types: the YAML file format lives in scenarios/ (docs/map_format.md).

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/features/uncertain_geometry.h"
#include "core/types/pose2.h"

namespace pavilion::core {

// An infinite line (alpha, r) in the map frame. Visibility follows eq. B.4 /
// B.21: the line is seen from the points p with n(alpha) . p < r, i.e. from the
// side the solid's face looks at. `line.covariance` is the measurement
// uncertainty of (alpha, r).
struct MapLine {
  std::string id;
  Line line;
};

// A segment (§5.2): a line plus its two endpoints in the map frame. The
// endpoints lie on the line; their covariances are the hand-measurement
// uncertainty of the corners. `line` keeps the visibility convention of MapLine.
struct MapSegment {
  std::string id;
  Line line;
  Point2Uncertain first_endpoint;
  Point2Uncertain second_endpoint;
};

// A multi-segment line (eq. 5.17): one supporting line and the collinear
// segments (their endpoints) it carries, e.g. a wall interrupted by doors.
struct MapMultiSegmentLine {
  std::string id;
  Line line;
  // Endpoint pairs of the member segments, in the order they lie along the
  // line's direction (-sin alpha, cos alpha).
  std::vector<std::pair<Point2Uncertain, Point2Uncertain>> segments;
};

// A point feature: vertical edge, column centre or corner (Table 5.3, "Point").
struct MapPoint {
  std::string id;
  Point2Uncertain point;
  double radius_m = 0.0;  // 0 for an edge; a column's radius otherwise
};

// A retro-reflective beacon (§3.3): a point the laser flags with its intensity bit.
struct MapBeacon {
  std::string id;
  Point2Uncertain point;
  double radius_m = 0.0;  // 0 for a marker on a face; a foil-wrapped column's radius otherwise
};

// Topology for the navigation layer (§6.3.1): station nodes are goals with a
// name and a pose; via nodes are waypoints; edges are undirected and weighted.
struct MapNode {
  std::string id;
  Pose2 pose;
  bool station = false;  // true: a named goal (exhibit, dock); false: a via node
};

struct MapEdge {
  std::string from;
  std::string to;
  double weight = 1.0;  // > 0; by default the Euclidean length
};

// A ghost point (§6.3.1): a position the planner must never lead through
// (e.g. an object the laser cannot see: a glass panel, a low bench).
struct MapGhostPoint {
  std::string id;
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
};

struct RobotMap {
  std::string name;
  std::string description;     // free text: where the map comes from (provenance)
  double beam_height_m = 0.0;  // height of the section the features describe
  std::vector<MapLine> lines;
  std::vector<MapSegment> segments;
  std::vector<MapMultiSegmentLine> multi_segment_lines;
  std::vector<MapPoint> points;
  std::vector<MapBeacon> beacons;
  std::vector<MapNode> nodes;
  std::vector<MapEdge> edges;
  std::vector<MapGhostPoint> ghost_points;
};

// Largest distance (m) a segment endpoint may lie off its supporting line.
inline constexpr double kMapEndpointToleranceM = 1e-3;

// True when `covariance` is finite, symmetric and positive definite.
bool IsPositiveDefinite(const Eigen::Matrix2d& covariance);

// Checks the invariants of a map and throws std::invalid_argument naming the
// first feature, node or edge (by id) and field that breaks one: finite numbers;
// positive-definite covariances (lines, endpoints, points, beacons); lines with
// r != 0 (eq. B.4: the sign of r carries visibility, undefined for r = 0) and
// alpha in (-pi, pi]; endpoints within kMapEndpointToleranceM of their line,
// every segment running from `first` to `second` along the line's direction
// (-sin alpha, cos alpha) and multi-segment members listed in that order;
// radii >= 0; beam height > 0; feature ids unique among all features, node ids
// among nodes, ghost ids among ghost points; edges between two distinct known
// nodes with a finite weight > 0, at most one per pair.
void ValidateRobotMap(const RobotMap& map);

}  // namespace pavilion::core
