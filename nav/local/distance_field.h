#pragma once

// Distance from any point to the nearest obstacle point of a local grid
// (thesis §6.3.4: the elastic band's bubbles are sized by it and pushed along
// its gradient, Quinlan & Khatib 1993). Exact to the points, not quantized to
// cells: the points are bucketed in a coarse index and a query searches rings
// of buckets outward from the first non-empty ring until no nearer point can
// remain. Distances are capped; off the grid every distance is the cap.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "nav/local/local_grid.h"

namespace pavilion::nav {

struct DistanceFieldOptions {
  double cap_m = 2.0;     // distances beyond are reported as the cap, m, (0, 20]
  double bucket_m = 0.2;  // side of the point index's square buckets, m, [0.02, 2]

  void Validate() const;  // throws std::invalid_argument naming the field
};

class DistanceField {
 public:
  // Distance to the nearest obstacle point and its gradient: the unit vector
  // from that point to the query (zero at the cap or on a point).
  struct Query {
    double distance_m = 0.0;
    Eigen::Vector2d gradient = Eigen::Vector2d::Zero();
  };

  explicit DistanceField(const DistanceFieldOptions& options = {});

  // Indexes grid.obstacles() over the grid's square; reuses its arrays.
  void Build(const LocalGrid& grid);

  Query Nearest(const Eigen::Vector2d& p_in_world) const;
  double Distance(const Eigen::Vector2d& p_in_world) const {
    return Nearest(p_in_world).distance_m;
  }

  const DistanceFieldOptions& options() const { return options_; }
  double cap_m() const { return options_.cap_m; }

 private:
  // Nearest point among those in bucket row `by`, columns [x0, x1] (clipped).
  void ScanRow(int by, int x0, int x1, const Eigen::Vector2d& p, double* best_d2,
               std::int32_t* best) const;

  DistanceFieldOptions options_;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();  // the grid's lower-left corner
  double side_m_ = 0.0;                               // the grid's side
  int buckets_ = 0;                                   // buckets per side
  std::vector<std::int32_t> bucket_start_;  // CSR: bucket b's points are [start[b], start[b+1])
  std::vector<std::int32_t> empty_rings_;   // Chebyshev distance (buckets) to a non-empty bucket
  std::vector<double> xs_;                  // the points, ordered by bucket
  std::vector<double> ys_;
  std::vector<std::int32_t> bucket_of_;  // scratch: each obstacle's bucket
};

}  // namespace pavilion::nav
