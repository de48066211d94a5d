#pragma once

// The clearance look-up table of the dynamic window (thesis §6.3.4: "we use a
// look-up table for the clearance measure"). The distance to collision along
// a constant-twist path depends only on the path's shape and on the point's
// position in the robot frame, not on the speed, so it is precomputed per
// path shape and robot-frame cell.
//
// Path shape: a twist (v, ω) has the direction γ = atan2(ρω, v) and the
// generalized speed σ = hypot(v, ρω), ρ the robot polygon's circumradius. γ
// is a bounded image of the curvature (κ = tan γ / ρ): 0 straight ahead, π
// straight back, ±π/2 turning on the spot, whose bins hold ρ times the
// rotation angle to collision. Along it the generalized arc u = σ·t is the
// arc length when straight and ρ·angle on the spot; time to collision is u/σ.
//
// Conservative: an entry is the exact u at which the cell's centre touches
// the robot polygon grown by safety_margin_m plus the cell's half diagonal
// (mitred), evaluated at the bin's centre direction, rounded down. Any point
// of the cell touches the polygon grown by the margin no earlier, so for the
// bin's direction the table never reports a later collision than the exact
// geometry; it is earlier by at most a grown cell (collision_table_test).

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "core/geometry/polygon.h"
#include "nav/reactive/swept_polygon.h"

namespace pavilion::nav {

struct CollisionTableOptions {
  double lookahead_m = 1.2;       // generalized arc tabulated, m, (0, 10]; beyond it: "later"
  double cell_m = 0.025;          // robot-frame cell side, m, [0.005, 0.2]
  int direction_bins = 64;        // twist directions over 2π, multiple of 4, [8, 1024]
  double safety_margin_m = 0.02;  // the robot polygon grown by this, m, [0, 0.5]

  void Validate() const;  // throws std::invalid_argument naming the field
};

class CollisionTable {
 public:
  // `robot_polygon` in the robot frame, counter-clockwise and convex.
  CollisionTable(const CollisionTableOptions& options, const core::Polygon2& robot_polygon);

  const CollisionTableOptions& options() const { return options_; }
  int bins() const { return options_.direction_bins; }
  int cells() const { return cells_per_side_ * cells_per_side_; }
  // ρ: the robot polygon's circumradius (m).
  double reference_radius_m() const { return reference_radius_m_; }
  // Points farther than this from the robot origin are not touched within
  // lookahead_m (the centre moves at most u, the grown polygon lies within its
  // circumradius); the table covers the square of this half side.
  double reach_m() const { return reach_m_; }
  // The robot polygon grown by the margin and the cell's half diagonal.
  const core::Polygon2& table_polygon() const { return table_polygon_; }

  double GeneralizedSpeed(const BodyTwist& twist) const;
  // The nearest bin to the twist's direction (a zero twist gives bin 0).
  int BinOf(const BodyTwist& twist) const;
  // The unit generalized speed twist at the bin's centre direction.
  BodyTwist BinDirection(int bin) const;

  // The cell holding the point, -1 when off the table.
  int CellOf(const Eigen::Vector2d& point_in_robot) const;
  // Generalized arc (m) to collision for the bin and cell, lookahead_m when
  // there is none within it.
  double ArcToCollision(int bin, int cell) const;
  // The earliest ArcToCollision over the cells (lookahead_m for none).
  double MinArcToCollision(int bin, std::span<const int> cells) const;

 private:
  void Fill(int bin);

  CollisionTableOptions options_;
  double reference_radius_m_ = 0.0;
  double reach_m_ = 0.0;
  int cells_per_side_ = 0;
  double bin_rad_ = 0.0;
  core::Polygon2 table_polygon_;
  std::vector<std::uint16_t> arc_;  // [bin][cell], arc / lookahead_m in 1/65535
};

// The table for (options, robot_polygon), shared by every caller that asks
// for the same inputs while one of them still holds it. A table is a pure
// function of its inputs and immutable once built, so a fleet of identical
// robots needs only one: ten Robox built ten identical 2.5 MB tables, ~0.1 s
// each, a fifth of the start-up of a demo run. Keyed by the exact bits of the
// options and vertices (no tolerance: a different polygon gets its own
// table). Thread-safe; a table is built under the cache's lock.
std::shared_ptr<const CollisionTable> SharedCollisionTable(const CollisionTableOptions& options,
                                                           const core::Polygon2& robot_polygon);

}  // namespace pavilion::nav
