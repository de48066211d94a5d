#pragma once

// Floor fields for simulated pedestrians: which cells of a floor a person's
// centre may occupy (WalkableGrid), and the walking distance from every free
// cell to a goal, whose steepest descent is a person's desired direction
// (DistanceField). This is the static floor field of Burstedde et al. 2001
// ("Simulation of pedestrian dynamics using a two-dimensional cellular
// automaton", Physica A 295:507-525) taken as the distance to the goal, as in
// Kirchner & Schadschneider 2002 (Physica A 312:260-276), and the potential of
// Hughes 2002 ("A continuum theory for the flow of pedestrians", Transp. Res. B
// 36:507-535) at unit walking cost: the solution T of the eikonal equation
// |grad T| = 1 in the free space with T = 0 on the goal. Walking down it leads
// around exhibits and through doors instead of straight into them.
//
// All coordinates are in the world frame, in metres.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "core/geometry/polygon.h"

namespace pavilion::sim::crowd {

// A thin wall from a_m to b_m (both finite; a_m = b_m is a point).
struct ObstacleSegment {
  Eigen::Vector2d a_m{0, 0};
  Eigen::Vector2d b_m{0, 0};
};

// A round obstacle (pillar, bollard): centre finite, radius_m in [0, inf) m.
struct ObstacleCircle {
  Eigen::Vector2d center_m{0, 0};
  double radius_m = 0.0;
};

struct WalkableGridOptions {
  double cell_m = 0.2;        // side of the square cells, m, (0, 2]
  double clearance_m = 0.25;  // a person's radius: cells whose centre is closer to an obstacle
                              // are blocked, m, [0, 2]

  void Validate() const;  // throws std::invalid_argument naming the field
};

// A cell index (col, row); (0, 0) is the cell at the floor's min corner.
using FloorCell = Eigen::Vector2i;

// What a cell of the walkable grid is, in increasing order of blockage.
enum class CellKind : std::uint8_t {
  kFree,       // a person's centre may stand here
  kClearance,  // the centre lies within clearance_m of an obstacle, which does not touch the cell
  kObstacle,   // an obstacle touches the cell, or the cell's centre is off the floor
};

// The obstacles that touch each cell of a walkable grid (cells row-major). A
// person whose centre is in such a cell may be on either side of a wall, so
// DistanceField::Direction checks its moves out of blocked cells against them.
struct CellObstacles {
  std::vector<ObstacleSegment> segments;
  std::vector<ObstacleCircle> circles;
  // Cell c is touched by ids[start[c]] .. ids[start[c + 1] - 1]: an id i >= 0
  // is segments[i], i < 0 is circles[-1 - i]. start has one entry per cell + 1.
  std::vector<std::int32_t> start;
  std::vector<std::int32_t> ids;

  // True when the straight move a_m -> b_m crosses a segment touching cell c,
  // or enters a circle touching it from outside.
  bool Blocks(std::size_t c, const Eigen::Vector2d& a_m, const Eigen::Vector2d& b_m) const;
};

// Which cells of a rectangular floor a person's centre may occupy. Cells of
// side cell_m tile the rectangle from min_m; the last column and row may stick
// out past max_m. A cell is blocked when its centre lies closer than
// clearance_m to an obstacle, or when an obstacle touches the (closed) cell
// square: the touched cells of a wall form an edge-connected chain, so a wall
// thinner than a cell never lets a field through, whatever the clearance. The
// rectangle's edges are not walls: pass the floor's walls as segments.
// Segments are thin: a closed outline (a box's four sides) leaves the cells
// inside it free when they are far enough from its sides, but no field from
// outside reaches them.
class WalkableGrid {
 public:
  // Throws std::invalid_argument naming the bad argument: options out of
  // range, min_m / max_m not finite or max_m not above min_m in x and y, more
  // than 2^24 cells, or an obstacle with a non-finite coordinate or a negative
  // radius.
  WalkableGrid(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m,
               const std::vector<ObstacleSegment>& segments,
               const std::vector<ObstacleCircle>& circles, const WalkableGridOptions& options = {});

  // True when p_m lies in the closed rectangle [min_m, max_m].
  bool Contains(const Eigen::Vector2d& p_m) const;
  // The cell holding p_m; none outside the rectangle (points on max_m belong to
  // the last column / row).
  std::optional<FloorCell> CellAt(const Eigen::Vector2d& p_m) const;
  // True when p_m lies in the rectangle and in a kFree cell.
  bool IsFree(const Eigen::Vector2d& p_m) const;

  // `cell` must lie on the grid: 0 <= col < cols(), 0 <= row < rows().
  CellKind kind(const FloorCell& cell) const { return kinds_[Index(cell)]; }
  Eigen::Vector2d CellCenter(const FloorCell& cell) const {
    return min_m_ + options_.cell_m * Eigen::Vector2d(cell.x() + 0.5, cell.y() + 0.5);
  }

  int cols() const { return cols_; }
  int rows() const { return rows_; }
  double cell_m() const { return options_.cell_m; }
  double clearance_m() const { return options_.clearance_m; }
  const Eigen::Vector2d& min_m() const { return min_m_; }
  const Eigen::Vector2d& max_m() const { return max_m_; }
  // The obstacles touching each cell; shared (immutable) with the fields
  // built on this grid.
  const std::shared_ptr<const CellObstacles>& obstacles() const { return obstacles_; }

 private:
  // Marks the cells obstacle `id` touches (and records it for them, in
  // `touches` as (cell, id)) and those it leaves within the clearance.
  void MarkSegment(const ObstacleSegment& segment, std::int32_t id,
                   std::vector<std::pair<std::int32_t, std::int32_t>>* touches);
  void MarkCircle(const ObstacleCircle& circle, std::int32_t id,
                  std::vector<std::pair<std::int32_t, std::int32_t>>* touches);
  // Raises the cell's kind to `kind` (blockage never decreases).
  void Mark(const FloorCell& cell, CellKind kind);
  std::size_t Index(const FloorCell& cell) const {
    return static_cast<std::size_t>(cell.y()) * static_cast<std::size_t>(cols_) +
           static_cast<std::size_t>(cell.x());
  }

  WalkableGridOptions options_;
  Eigen::Vector2d min_m_;
  Eigen::Vector2d max_m_;
  int cols_ = 0;
  int rows_ = 0;
  std::vector<CellKind> kinds_;  // row-major, cols_ * rows_
  std::shared_ptr<const CellObstacles> obstacles_;
};

// The walking distance to a goal from every free cell of a WalkableGrid, and
// the direction down it.
//
// Method: the fast marching method (Sethian 1996, "A fast marching level set
// method for monotonically advancing fronts", PNAS 93:1591-1595) from the goal
// cells, each set to minus its centre's depth in the goal so that the front
// starts at the goal's boundary. A trial cell takes the smaller of two
// solutions: on the edge-neighbour stencil, second order wherever two known
// cells lie upwind (Sethian 1999, "Fast marching methods", SIAM Review
// 41:199-235), and on the diagonal stencil, first order (the multi-stencil
// method of Hassouna & Farag 2007, IEEE PAMI 29:1563-1574), which carries the
// front along staircase boundaries and through doors.
// Why not Dijkstra on the 8-connected grid: its octile metric is up to 8 %
// longer than Euclidean (at 22.5 deg), and its descent is off by up to 22.5 deg
// at any range. Here, in an empty room, the distance to a disc is Euclidean to
// within half a cell plus 1 %, from every direction, and the descent at range R
// is off by less than 2 h / R rad (0.2 m cells: 4.5 deg at 3 m, 1.6 deg at
// 12 m measured); floor_field_test bounds both.
// Walls cannot leak: a step between free cells (edge or diagonal) runs inside
// the two cells' squares, and a wall crossing it would touch one of them and
// make it an obstacle cell.
//
// Beyond the free cells, the march continues into the clearance cells at three
// times the walking cost (kEscapeSlowness in floor_field.cc): an escape
// potential, never fed back into the free cells, down which a person pressed
// into a wall's clearance walks back out, forwards. Values are stored as float.
//
// Construction is O(N log N) in the grid's N cells (about 1.5 ms for 175 x 75
// cells, floor_field_bench); queries are O(1), need no allocation and are
// deterministic (no threads, no hashing). A field copies what it needs of the
// grid, shares its immutable CellObstacles, and may outlive it.
class DistanceField {
 public:
  // Goal: the free cells whose centre lies within radius_m of center_m; if
  // none is free, the free cell whose centre lies nearest to center_m (ties:
  // the lowest row, then column). center_m finite (may lie off the floor),
  // radius_m finite, >= 0 m; throws std::invalid_argument naming the argument.
  static DistanceField ToDisc(const WalkableGrid& grid, const Eigen::Vector2d& center_m,
                              double radius_m);
  // Goal: the free cells whose centre lies inside `area` or on its boundary; if
  // none is free, the free cell whose centre lies nearest to it. `area` is a
  // simple polygon of >= 3 finite vertices (either orientation); throws
  // std::invalid_argument otherwise.
  static DistanceField ToArea(const WalkableGrid& grid, const core::Polygon2& area);

  // Walking distance from p_m to the goal (m), interpolated as for Direction;
  // 0 in a goal cell; +inf off the floor, in a blocked cell or in free space
  // from which the goal cannot be reached.
  double Distance(const Eigen::Vector2d& p_m) const;

  // The unit vector a person at p_m should walk along, or zero:
  //  - in a reachable free cell: steepest descent of the field interpolated
  //    over the four cell centres around p_m that are free and reachable:
  //    bilinearly when all four are, a missing one on the plane of the other
  //    three; with two or fewer (along a wall, in a gap one cell wide) from
  //    differences over the own cell's usable edge neighbours. Where that has
  //    no slope, towards the centre of the lowest neighbouring free cell;
  //  - in a goal cell, off the floor, or where the goal is unreachable: zero;
  //  - in a blocked cell: towards the centre of the neighbouring cell (of 8)
  //    lowest in the escape potential that p_m reaches in a straight line
  //    without crossing an obstacle: out of the clearance, on towards the
  //    goal, and on p_m's side of a wall through its cell; zero when there is
  //    no such neighbour.
  // Deterministic, O(1), no allocation.
  Eigen::Vector2d Direction(const Eigen::Vector2d& p_m) const;

  // True when p_m lies in a free cell from which the goal can be reached.
  bool Reachable(const Eigen::Vector2d& p_m) const;
  // True when p_m lies in a goal cell (where Direction is zero).
  bool InGoal(const Eigen::Vector2d& p_m) const;

 private:
  struct GoalShape;  // the goal's bounding box and signed distance (floor_field.cc)
  struct Patch;      // the field's value and gradient at a point (floor_field.cc)

  explicit DistanceField(const WalkableGrid& grid);

  // Fills potential_ and the goal flags: seeds the goal, marches the free
  // cells, then the clearance cells (see the class comment).
  void Compute(const GoalShape& goal);
  // Flags the goal cells and sets them to minus their centre's depth in the
  // goal (a stand-in cell to 0); returns them (padded indices), none when the
  // grid has no free cell.
  std::vector<std::int32_t> SeedGoal(const GoalShape& goal);

  // Padded index of the cell holding p_m; -1 off the floor.
  std::int32_t IndexAt(const Eigen::Vector2d& p_m) const;
  std::int32_t PaddedIndex(int col, int row) const;
  Eigen::Vector2d CenterOf(std::int32_t k) const;
  // True when cell k is free and reached: its value is a walking distance.
  bool Usable(std::int32_t k) const;
  // The field around p_m, which lies in the usable cell k.
  Patch Interpolate(const Eigen::Vector2d& p_m, std::int32_t k) const;
  // Towards the centre of the 8-neighbour of cell k with `allowed` flags that
  // is lowest in potential_ and lower than cell k, and that p_m can walk to in
  // a straight line without crossing an obstacle; zero when there is none.
  Eigen::Vector2d TowardsBestNeighbour(const Eigen::Vector2d& p_m, std::int32_t k,
                                       std::uint8_t allowed) const;
  // True when an obstacle touching padded cell k (none off the grid) blocks
  // the move a_m -> b_m.
  bool Blocks(std::int32_t k, const Eigen::Vector2d& a_m, const Eigen::Vector2d& b_m) const;

  Eigen::Vector2d min_m_;
  Eigen::Vector2d max_m_;
  double cell_m_ = 1.0;
  int cols_ = 0;
  int rows_ = 0;
  int stride_ = 0;  // cols_ plus the padding on both sides
  // Per padded cell: walking distance (m) in free cells (in goal cells minus
  // the centre's depth in the goal), escape potential in clearance cells, +inf
  // where not reached, in obstacle cells and in the padding.
  std::vector<float> potential_;
  std::vector<std::uint8_t> flags_;  // per padded cell: kFreeFlag, kClearanceFlag, kGoalFlag
  std::shared_ptr<const CellObstacles> obstacles_;  // the grid's
};

}  // namespace pavilion::sim::crowd
