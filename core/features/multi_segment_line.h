#pragma once

#include <Eigen/Core>
#include <vector>

#include "core/features/uncertain_geometry.h"

namespace pavilion::core {

// A multi-segment line (MS-line, thesis §5.2, eq. 5.17): m = (l, {s_i}_{i=1..n_s}),
// a supporting line l together with the n_s collinear segments it supports (e.g.
// a wall interrupted by doors). For estimation the line l carries the
// probabilistic information; for data association the segments come into play.
struct MultiSegmentLine {
  // l: the (alpha, r) of the member segments' lines fused by the information
  // filter (eqs. 3.13-3.14), in the sensor frame with r >= 0.
  Line line;
  // {s_i}: the member segments, in scan order (by first reading).
  std::vector<Segment> segments;
  // Index of each member in the input vector, same order as `segments`.
  std::vector<int> segment_indices;
};

struct MultiSegmentLineOptions {
  // alpha, significance level of the chi^2(2) collinearity test (eq. 3.16); in (0, 1).
  double significance = 0.99;
  // MS-lines with fewer member segments are dropped; >= 1 (1 keeps every segment).
  int min_segments = 1;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// The squared Mahalanobis distance of eq. 3.16 between two lines' (alpha, r),
// d^2 = (x_i - x_j)^T (C_i + C_j)^{-1} (x_i - x_j), with the angle difference
// wrapped to (-pi, pi]. Lines through (almost) the origin have two equivalent
// parameterizations, (alpha, r) and (alpha + pi, -r); the smaller distance is
// taken. Infinite if C_i + C_j is singular.
double LineMahalanobis2(const Line& a, const Line& b);

// Information filter (eqs. 3.13-3.14): C_w = (sum C_i^{-1})^{-1},
// x_w = C_w sum C_i^{-1} x_i over the lines' (alpha, r); angles are expressed
// relative to the first line before averaging (no wrap-around bias). Lines
// are first brought to r >= 0 where that flips nothing significant (see
// LineMahalanobis2). Requires every covariance to be invertible; throws
// std::invalid_argument for an empty input or a singular covariance.
Line FuseLines(const std::vector<Line>& lines);

// Groups a scan's segments into MS-lines (eq. 5.17) by the nearest-neighbour
// agglomerative clustering of §3.2.3: repeatedly the pair of clusters whose
// fused lines have the smallest chi^2 distance (eq. 3.16) is merged while that
// distance is below the chi^2(2) quantile at `significance`, and the merged
// cluster's line is the information-filter fusion (3.13-3.14) of all its
// members' lines. Unlike the extractor's fusion, segments need not be adjacent:
// collinear segments separated by gaps (doors) or by other segments form one
// MS-line. Result ordered by the first reading of each MS-line's first
// segment. Cost O(n_s^3) for n_s segments (n_s is small).
std::vector<MultiSegmentLine> GroupMultiSegmentLines(const std::vector<Segment>& segments,
                                                     const MultiSegmentLineOptions& options = {});

}  // namespace pavilion::core
