#include "nav/local/local_grid.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace pavilion::nav {

void LocalGridOptions::Validate() const {
  auto fail = [](const std::string& message) { throw std::invalid_argument(message); };
  if (!(size_m >= 8.0 && size_m <= 40.0)) fail("size_m must be in [8, 40] m");
  if (!(cell_m >= 0.01 && cell_m <= 0.2)) fail("cell_m must be in [0.01, 0.2] m");
  if (!(robot_radius_m > 0.0 && robot_radius_m <= 2.0)) {
    fail("robot_radius_m must be in (0, 2] m");
  }
}

LocalGrid::LocalGrid(const LocalGridOptions& options) : options_(options) {
  options_.Validate();
  n_ = static_cast<int>(std::ceil(options_.size_m / options_.cell_m - 1e-9));
  occupied_.assign(static_cast<std::size_t>(n_) * n_, 0);
  free_.assign(occupied_.size(), 0);
  // Offsets whose centres lie within the radius (plus half a cell, so a point
  // anywhere in an occupied cell within the radius blocks the centre).
  const double reach = options_.robot_radius_m / options_.cell_m + 0.5;
  const int r = static_cast<int>(std::ceil(reach));
  for (int dy = -r; dy <= r; ++dy) {
    DiskRow row{dy, r + 1, -r - 1};
    for (int dx = -r; dx <= r; ++dx) {
      if (dx * dx + dy * dy <= reach * reach) {
        row.dx_min = std::min(row.dx_min, dx);
        row.dx_max = std::max(row.dx_max, dx);
      }
    }
    if (row.dx_min <= row.dx_max) disk_.push_back(row);
  }
}

GridCell LocalGrid::CellOf(const Eigen::Vector2d& p_in_world) const {
  const Eigen::Vector2d q = (p_in_world - origin_) / options_.cell_m;
  return {static_cast<int>(std::floor(q.x())), static_cast<int>(std::floor(q.y()))};
}

void LocalGrid::Build(const Eigen::Vector2d& center_in_world,
                      std::span<const Eigen::Vector2d> obstacles_in_world) {
  center_ = center_in_world;
  origin_ = center_ - Eigen::Vector2d::Constant(0.5 * n_ * options_.cell_m);
  std::fill(occupied_.begin(), occupied_.end(), 0);
  std::fill(free_.begin(), free_.end(), 1);
  obstacles_.clear();
  for (const Eigen::Vector2d& p : obstacles_in_world) {
    const GridCell c = CellOf(p);
    if (!Inside(c)) continue;
    obstacles_.push_back(p);
    std::uint8_t& occupied = occupied_[Index(c)];
    if (occupied) continue;
    occupied = 1;
    for (const DiskRow& d : disk_) {
      const int y = c.y() + d.dy;
      if (y < 0 || y >= n_) continue;
      const int x0 = std::max(0, c.x() + d.dx_min);
      const int x1 = std::min(n_ - 1, c.x() + d.dx_max);
      if (x0 <= x1) std::fill_n(free_.begin() + Index({x0, y}), x1 - x0 + 1, std::uint8_t{0});
    }
  }
}

}  // namespace pavilion::nav
