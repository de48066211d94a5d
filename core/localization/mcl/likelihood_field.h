#pragma once

// The likelihood field of a map's lines (Thrun, Burgard & Fox, Probabilistic
// Robotics §6.4): for every point of the plane, the distance to the nearest
// mapped geometry, capped. The Monte Carlo localization baseline scores each
// beam end by it. Built from the a-priori RobotMap only, never from the world.

#include <Eigen/Core>
#include <algorithm>
#include <utility>
#include <vector>

#include "core/geometry/segment2.h"
#include "core/map/map_geometry.h"
#include "core/map/robot_map.h"

namespace pavilion::core {

struct LikelihoodFieldOptions {
  // Cell size, m; (0, 1]. nav2 maps are commonly 0.05 m (chosen: the raster
  // error, at most resolution/sqrt(2), stays far below sigma_hit 0.2 m).
  double resolution_m = 0.05;
  // Grown around the geometry's bounding box, m; [0, 100]. Chosen: beam ends up
  // to 1 m beyond the outermost wall still get their true distance.
  double margin_m = 1.0;
  // Distances are capped here, m; (0, 100]. nav2 laser_likelihood_max_dist 2.0.
  double max_distance_m = 2.0;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// A grid over the map's geometry (bounding box plus margin) holding, for each
// cell, the distance of its centre to the nearest cell the geometry passes
// through: the geometry is rasterized (segments sampled every resolution/4,
// discs filled), then an exact Euclidean distance transform of the raster
// (Felzenszwalb & Huttenlocher 2012, separable lower envelope of parabolas)
// runs over it. The value differs from the true distance to the geometry by at
// most resolution/sqrt(2) (half a cell diagonal). A map without finite
// geometry gives an empty grid: every query returns max_distance_m.
class LikelihoodField {
 public:
  explicit LikelihoodField(const RobotMap& map, const LikelihoodFieldOptions& options = {});

  // Distance (m) from `point_in_map` to the nearest mapped geometry, read at the
  // cell holding the point; max_distance_m off the grid.
  double DistanceM(const Eigen::Vector2d& point_in_map) const;

  // Index of the cell holding the point, -1 off the grid.
  long CellIndex(const Eigen::Vector2d& point_in_map) const;
  // Stored as float; the min keeps the cap exact.
  double CellDistanceM(long index) const {
    return std::min<double>(distance_m_[static_cast<std::size_t>(index)], options_.max_distance_m);
  }
  Eigen::Vector2d CellCenter(long index) const;
  long cell_count() const { return static_cast<long>(width_) * height_; }
  int width() const { return width_; }
  int height() const { return height_; }
  double resolution_m() const { return options_.resolution_m; }
  double max_distance_m() const { return options_.max_distance_m; }
  // The bounding box of the finite geometry (without margin); empty when none.
  const Box2& geometry_bounds() const { return bounds_; }

 private:
  void Rasterize(const MapGeometry& geometry, std::vector<char>* occupied) const;
  void Transform(const std::vector<char>& occupied);

  LikelihoodFieldOptions options_;
  Box2 bounds_;
  Eigen::Vector2d origin_m_ = Eigen::Vector2d::Zero();  // lower-left corner of cell 0
  int width_ = 0;
  int height_ = 0;
  std::vector<float> distance_m_;  // row-major, y rows of width_ cells
};

}  // namespace pavilion::core
