#pragma once

// Where a particle may be drawn (Probabilistic Robotics §8.3: random particles
// of global localization and of the augmented MCL's recovery): the free space
// of the a-priori map, never of the world.

#include <Eigen/Core>
#include <vector>

#include "core/localization/mcl/likelihood_field.h"
#include "core/map/robot_map.h"
#include "core/random/random_stream.h"

namespace pavilion::core {

struct MapFreeSpaceOptions {
  double resolution_m = 0.05;  // cell size, m; (0, 1]; chosen: as the likelihood field
  // Smallest distance of a free cell's centre to mapped geometry, m; >= 2
  // resolution_m (so that a 4-connected step cannot cross a mapped line) and
  // <= 10. Chosen: about Robox's radius (0.3 m); no robot centre lies closer.
  double robot_radius_m = 0.3;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// The cells a robot's centre can occupy according to the map: a flood fill
// (4-connected) from the cell of every topology node (map.nodes lie in free
// space; a node whose cell lacks the clearance seeds nothing) through cells
// whose centre lies inside the geometry's bounding box and at least
// robot_radius_m from the mapped geometry (LikelihoodField distances, so
// within resolution/sqrt(2) of the true clearance). Cells are never crossed
// by mapped geometry: a step joins two cells each >= 2 resolution from it.
// A map without nodes: every in-bounds cell with the clearance is free (rooms
// that no node reaches are then free too, e.g. the inside of a closed box).
class MapFreeSpace {
 public:
  explicit MapFreeSpace(const RobotMap& map, const MapFreeSpaceOptions& options = {});

  // A point uniform over the free cells (a cell uniformly, then uniformly
  // within it): three draws from `random`. Throws std::logic_error
  // when there is no free cell.
  Eigen::Vector2d Sample(RandomStream& random) const;
  // True when the cell holding `point_in_map` is free.
  bool IsFree(const Eigen::Vector2d& point_in_map) const;
  int free_cells() const { return static_cast<int>(free_.size()); }
  double resolution_m() const { return field_.resolution_m(); }

 private:
  void Flood(const RobotMap& map, const std::vector<char>& passable);

  MapFreeSpaceOptions options_;
  LikelihoodField field_;      // clearance, capped just above robot_radius_m
  std::vector<long> free_;     // free cell indices, ascending
  std::vector<char> is_free_;  // per cell of field_
};

}  // namespace pavilion::core
