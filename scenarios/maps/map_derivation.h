#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/geometry/obstacle_set.h"
#include "core/map/robot_map.h"
#include "sim/world/world.h"

namespace pavilion::scenarios {

// How `pavilion map derive` turns a world into the a-priori map a robot is given
// (thesis §4.3, §6.3.1). docs/map_format.md explains each step and default.
struct MapDerivationOptions {
  // Height of the scan plane the features describe, (0, 10] m. 0.5 m: both
  // shipped robots mount their SICK LMS 200 at 0.50 m (robots/*/robot.urdf).
  double beam_height_m = 0.5;
  // Height of the second cut that finds solids below the beam (benches, docks),
  // (0, beam_height_m) m.
  double low_height_m = 0.2;
  // Tape-measure error, one standard deviation, applied to every measured corner
  // and centre, [0, 0.1] m. The recorded covariances use max(noise, 1 mm).
  double noise_sigma_m = 0.005;
  // Survey error of whole walls (issue 20, `realism: realistic`): each end of
  // a line feature is measured off along its normal by its own draw of this
  // sigma (the wall shifted and turned), beside the tape-measure noise of its
  // corners. The recorded (alpha, r) covariance includes it (the surveyor
  // states the method's accuracy). [0, 0.1] m.
  double wall_offset_sigma_m = 0.0;
  // Seed of the tape-measure noise (and of the wall offsets, a stream of their own).
  std::uint64_t seed = 1;
  // Clearance every edge (and node) keeps from every obstacle, [0.05, 2] m.
  double robot_radius_m = 0.35;
  // Pitch of the grid that places via nodes, [0.5, 20] m.
  double via_spacing_m = 3.0;
  // Largest gap between neighbouring ghost points, (0, 2 * robot_radius_m) m.
  double ghost_spacing_m = 0.25;
  // Also map the vertical edges a camera sees (§4.2, Fig. 4.2; issue 19) as
  // points of radius 0 named edge_NNN, measured with the tape-measure noise
  // from a stream of their own (the other features' draws stay as they were).
  bool vertical_edges = false;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// Derives a map from the world's section at the beam height: laser-visible faces
// grouped into segments and multi-segment lines, columns as points,
// retro-reflective elements as beacons, station and via nodes with collision-free
// edges, and ghost points on what the laser cannot see. Deterministic for given
// options. Problems that do not stop the derivation (a node without edges, a
// place in an obstacle) are appended to `warnings` when it is given. Throws
// std::invalid_argument for bad options and std::runtime_error when the result
// is not a valid map (e.g. a visible face on a line through the world origin,
// which eq. B.4 cannot represent).
core::RobotMap DeriveRobotMap(const sim::World& world, const MapDerivationOptions& options,
                              std::vector<std::string>* warnings = nullptr);

// Keeps only the map lines whose direction lies within `tolerance_rad` of
// `direction_rad` (modulo pi; a line (alpha, r) runs along alpha + pi/2): lines,
// segments and multi-segment lines; drops columns and beacons but keeps
// vertical edges (points of radius 0, the camera's features); keeps the
// topology and ghost points. For experiments in which the map constrains the
// robot in one direction only (thesis Table 4.1, Fig. 4.4: a corridor whose map
// has only the walls parallel to it). The description records the filter.
// Throws std::invalid_argument for a non-finite direction or a tolerance
// outside (0, pi/2].
core::RobotMap KeepLinesAlongDirection(const core::RobotMap& map, double direction_rad,
                                       double tolerance_rad);

// The obstacles a robot must keep clear of at the given heights: every static
// section primitive (laser-visible or not) at the beam and the low height, as
// segments and circles. Used for edge checks and by tests.
using MapObstacles = core::ObstacleSet;
MapObstacles NavigationObstacles(const sim::World& world, double beam_height_m,
                                 double low_height_m);

}  // namespace pavilion::scenarios
