#pragma once

// The seam for the band's initial path (thesis §6.3.4: "uses an NF1 navigation
// function for initialization"): NF1 by default, OMPL's planners as selectable
// alternatives. Every implementation meets the same conformance suite
// (tests/nav/local/initial_path_conformance_test.cc).

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "nav/local/local_grid.h"

namespace pavilion::nav {

class InitialPathPlanner {
 public:
  virtual ~InitialPathPlanner() = default;
  // A collision-free polyline (world frame) over the grid's free cells from
  // `start` to `goal`, both included, or none when the planner finds no path.
  // `seed` makes a sampling planner's draw reproducible (scenario seed, robot,
  // plan number); deterministic planners ignore it.
  virtual std::optional<std::vector<Eigen::Vector2d>> Plan(const LocalGrid& grid,
                                                           const Eigen::Vector2d& start,
                                                           const Eigen::Vector2d& goal,
                                                           std::uint64_t seed) = 0;
  virtual std::string name() const = 0;
};

}  // namespace pavilion::nav
