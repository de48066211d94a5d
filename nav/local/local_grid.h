#pragma once

// The local grid of the path-planning sublayer (thesis §6.3.4): a square grid
// centred on the robot, axis-aligned with the world (belief) frame, built from
// the current scans and the map's ghost points only ("relies on sensory data
// without memory"). For path planning the robot is a circle (§6.3.4): a cell is
// free when the circle centred on it holds no obstacle point.

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

namespace pavilion::nav {

struct LocalGridOptions {
  double size_m = 8.0;          // side of the square, m, [8, 40] (issue 14: >= 8 m across)
  double cell_m = 0.05;         // cell side, m, [0.01, 0.2] (issue 14: <= 5 cm by default)
  double robot_radius_m = 0.4;  // the circle planned for, m, (0, 2]

  void Validate() const;  // throws std::invalid_argument naming the field
};

// A cell index (x, y); (0, 0) is the cell at the grid's lower-left corner.
using GridCell = Eigen::Vector2i;

class LocalGrid {
 public:
  explicit LocalGrid(const LocalGridOptions& options);

  // Rebuilds the grid centred on `center_in_world` from obstacle points in the
  // world frame; points off the grid are ignored.
  void Build(const Eigen::Vector2d& center_in_world,
             std::span<const Eigen::Vector2d> obstacles_in_world);

  const LocalGridOptions& options() const { return options_; }
  int cells_per_side() const { return n_; }
  double cell_m() const { return options_.cell_m; }
  // World position of the grid's lower-left corner.
  const Eigen::Vector2d& origin() const { return origin_; }
  const Eigen::Vector2d& center() const { return center_; }

  bool Inside(const GridCell& cell) const {
    return cell.x() >= 0 && cell.y() >= 0 && cell.x() < n_ && cell.y() < n_;
  }
  bool Inside(const Eigen::Vector2d& p_in_world) const { return Inside(CellOf(p_in_world)); }
  GridCell CellOf(const Eigen::Vector2d& p_in_world) const;
  Eigen::Vector2d CenterOf(const GridCell& cell) const {
    return origin_ + options_.cell_m * Eigen::Vector2d(cell.x() + 0.5, cell.y() + 0.5);
  }
  std::int32_t Index(const GridCell& cell) const { return cell.y() * n_ + cell.x(); }
  GridCell CellAt(std::int32_t index) const { return {index % n_, index / n_}; }

  // A cell holding at least one obstacle point.
  bool Occupied(const GridCell& cell) const { return occupied_[Index(cell)] != 0; }
  // The robot's circle centred on the cell's centre clears every obstacle cell
  // (to within half a cell). Cells off the grid are not free.
  bool Free(const GridCell& cell) const { return Inside(cell) && free_[Index(cell)] != 0; }
  bool FreeAt(const Eigen::Vector2d& p_in_world) const { return Free(CellOf(p_in_world)); }

  // The obstacle points the grid was built from that fell on it (world frame).
  const std::vector<Eigen::Vector2d>& obstacles() const { return obstacles_; }

 private:
  LocalGridOptions options_;
  int n_ = 0;
  Eigen::Vector2d center_ = Eigen::Vector2d::Zero();
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  std::vector<std::uint8_t> occupied_;
  std::vector<std::uint8_t> free_;
  std::vector<Eigen::Vector2d> obstacles_;
  // The cell offsets within the robot radius, row by row: dy and the run
  // [dx_min, dx_max] (a disk's rows are runs), so that a blocked row is one fill.
  struct DiskRow {
    int dy = 0;
    int dx_min = 0;
    int dx_max = 0;
  };
  std::vector<DiskRow> disk_;
};

}  // namespace pavilion::nav
