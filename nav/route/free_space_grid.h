#pragma once

// A grid over the floor holding each cell centre's clearance to the obstacles
// (capped) and which cells a robot of a given radius can reach from seeds.

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "core/geometry/obstacle_set.h"

namespace pavilion::nav {

class FreeSpaceGrid {
 public:
  // Cells of `cell_m` (> 0) covering the box lo-hi; clearances above `cap_m`
  // are not told apart. No cell is reachable until Flood().
  FreeSpaceGrid(const Eigen::Vector2d& lo, const Eigen::Vector2d& hi,
                const core::ObstacleSet& obstacles, double cap_m, double cell_m);

  int nx() const { return nx_; }
  int ny() const { return ny_; }
  double cell_m() const { return cell_m_; }
  std::size_t Index(int x, int y) const { return static_cast<std::size_t>(y) * nx_ + x; }
  Eigen::Vector2d Center(int x, int y) const {
    return lo_ + cell_m_ * Eigen::Vector2d(x + 0.5, y + 0.5);
  }
  Eigen::Vector2d Center(std::size_t i) const {
    return Center(static_cast<int>(i % nx_), static_cast<int>(i / nx_));
  }
  // The cell holding p; false when p is off the grid.
  bool CellOf(const Eigen::Vector2d& p, std::size_t* index) const;
  double clearance(std::size_t i) const { return clearance_[i]; }
  bool reachable(std::size_t i) const { return reachable_[i] != 0; }
  bool ReachableAt(const Eigen::Vector2d& p) const {
    std::size_t i;
    return CellOf(p, &i) && reachable(i);
  }

  // Floods the cells with clearance >= radius from the seeds (4-connected).
  void Flood(const std::vector<std::size_t>& seeds, double radius_m);

 private:
  struct CellBox {
    int x0, y0, x1, y1;
  };
  // The cells within `margin` of the box, clipped to the grid.
  CellBox CellRange(const Eigen::Vector2d& box_lo, const Eigen::Vector2d& box_hi,
                    double margin) const;
  // Lowers the cells near the box to `distance` of their centres.
  template <typename Distance>
  void Lower(const Eigen::Vector2d& box_lo, const Eigen::Vector2d& box_hi, double cap_m,
             Distance distance);

  Eigen::Vector2d lo_;
  double cell_m_ = 0.0;
  int nx_ = 0;
  int ny_ = 0;
  std::vector<float> clearance_;
  std::vector<char> reachable_;
};

}  // namespace pavilion::nav
