#pragma once

// The NF1 navigation function (Latombe 1991; Lamon, Nourbakhsh et al. 2001)
// that initializes the elastic band of the path-planning sublayer (thesis
// §6.3.4: "uses an NF1 navigation function for initialization"). A wavefront
// from the goal cell over the local grid's free cells, 4-connected with unit
// steps; the path descends the values from the start cell. NF1 "always yields
// topologically correct solutions" but grazes obstacles; the band smooths it.

#include <Eigen/Core>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "nav/local/initial_path_planner.h"
#include "nav/local/local_grid.h"

namespace pavilion::nav {

class Nf1Planner : public InitialPathPlanner {
 public:
  // The value of a cell the wavefront does not reach (blocked, off the grid or
  // in another component).
  static constexpr std::int32_t kUnreachable = std::numeric_limits<std::int32_t>::max();

  // The wavefront from `goal` (a free cell of `grid`; otherwise every value is
  // kUnreachable): value = number of 4-connected unit steps to the goal.
  // Reuses its arrays: no allocation after the first call on a grid size.
  void Compute(const LocalGrid& grid, const GridCell& goal);
  // The last Compute's value of `cell`; kUnreachable when not reached.
  std::int32_t value(const GridCell& cell) const;

  // The goal the planner plans to (issue 14): `goal` itself when its cell is
  // free and reachable from the start's cell; otherwise the centre of the free
  // cell reachable from the start nearest (Euclidean) to `goal`; none when no
  // free start cell exists (see StartCell). Allocates its own arrays; Plan()
  // runs the same selection on the planner's reused ones.
  static std::optional<Eigen::Vector2d> LocalGoal(const LocalGrid& grid,
                                                  const Eigen::Vector2d& start,
                                                  const Eigen::Vector2d& goal);
  // The start's cell when free; otherwise the free cell whose centre lies
  // nearest to `start` within one robot radius (the robot already grazes an
  // obstacle); none when there is none.
  static std::optional<GridCell> StartCell(const LocalGrid& grid, const Eigen::Vector2d& start);

  // NF1 path from `start` to LocalGoal(grid, start, goal): cell centres where
  // the descent turns, with the exact start and (local) goal at the ends.
  // The descent moves to the lowest-valued of the 8 neighbours, diagonally
  // only when both cells it passes between are reachable (no corner cut);
  // ties keep the previous direction, then the fixed order E, N, W, S, NE,
  // NW, SW, SE. `seed` is ignored.
  std::optional<std::vector<Eigen::Vector2d>> Plan(const LocalGrid& grid,
                                                   const Eigen::Vector2d& start,
                                                   const Eigen::Vector2d& goal,
                                                   std::uint64_t seed) override;
  std::string name() const override { return "nf1"; }

  // The cells of the last successful Plan's descent, start cell to goal cell.
  const std::vector<GridCell>& cell_path() const { return cell_path_; }

 private:
  // Selects the local goal for a free `start_cell` and leaves the wavefront
  // computed from the local goal's cell.
  std::optional<Eigen::Vector2d> SelectLocalGoal(const LocalGrid& grid, const GridCell& start_cell,
                                                 const Eigen::Vector2d& goal);
  // Descends from `start_cell` into cell_path_; false when it is unreachable.
  bool Descend(const GridCell& start_cell);
  std::int32_t PaddedIndex(const GridCell& cell) const {
    return (cell.y() + 1) * stride_ + cell.x() + 1;
  }

  int n_ = 0;       // cells per side of the last grid
  int stride_ = 0;  // n_ + 2: the values carry a blocked one-cell border
  std::vector<std::int32_t> values_;
  std::vector<std::int32_t> queue_;  // ring buffer of padded indices
  std::vector<GridCell> cell_path_;
};

}  // namespace pavilion::nav
