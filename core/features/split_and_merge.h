#pragma once

#include <vector>

#include "core/features/uncertain_geometry.h"
#include "core/types/sensor_data.h"

namespace pavilion::core {

// Options of the split-and-merge (iterative end-point fit) baseline. Defaults
// suit the SICK LMS 200 (0.5 deg, sigma_rho = 1 cm), as LineExtractionOptions'.
struct SplitAndMergeOptions {
  // A run of points is split at the point farthest from the chord joining its
  // first and last points when that distance exceeds this, m; > 0. 5 sigma: the
  // largest of ~100 Gaussian deviations plus the chord's own endpoint noise
  // stays below it, a corner of a few degrees between walls does not.
  double split_threshold_m = 0.05;
  // Split between consecutive valid readings whose distance exceeds the
  // adaptive breakpoint threshold (Borges and Aldon 2004)
  //   D = r_prev sin(dphi) / sin(lambda - dphi) + gap_min_m,
  // dphi the bearing step between them (dropouts included): a surface seen at
  // an incidence beyond 90 deg - lambda is treated as a gap.
  bool split_at_gaps = true;
  double gap_min_m = 0.03;                                  // >= 0; 3 sigma_rho
  double gap_lambda_rad = 10.0 * 3.14159265358979 / 180.0;  // in (0, pi/2]
  // Merge adjacent segments (in scan order, after dropping those with fewer
  // than min_points) while every point of the pair lies within
  // merge_threshold_m of the line fitted to their union (eqs. 3.4-3.5).
  bool merge = true;
  double merge_threshold_m = 0.05;  // > 0
  // sigma_rho of every valid reading, m; > 0 (weights of the final fit, eq. 3.11).
  double range_sigma_m = 0.01;
  // Segments supported by fewer readings are rejected; >= 2.
  int min_points = 7;
  // Segments shorter than this (eq. 5.15), or whose longest run of consecutive
  // valid readings is, are rejected, m; >= 0 (as ExtractLines).
  double min_length_m = 0.3;
  // Additive covariance floor of the fitted (alpha, r), as in
  // LineExtractionOptions (§2.2.1.3); >= 0.
  double alpha_sigma_floor_rad = 0.0;
  double r_sigma_floor_m = 0.0;
  // sigma_theta_e of the endpoint bearings (eq. 5.2), rad; >= 0, 0 means the
  // scan's angular resolution.
  double endpoint_bearing_sigma_rad = 0.0;

  // Throws std::invalid_argument naming the first invalid field.
  void Validate() const;

  static SplitAndMergeOptions SickLms200();
};

// Split-and-merge line extraction, the classic baseline for ExtractLines with
// the same output: valid readings become points; runs between gaps are split
// recursively at the point farthest from their chord; adjacent collinear
// segments are merged; each segment's line is the weighted polar fit of its
// readings (FitLine, eqs. 3.4-3.10) and its endpoints and length come from
// MakeSegment (eqs. 5.3-5.9, 5.15-5.16). Segments are in the sensor frame, in
// scan order, r >= 0. Invalid readings are skipped. Cost O(n log n) typical,
// O(n^2) worst case for the split, O(n_s n) for the merge.
std::vector<Segment> SplitAndMerge(const LaserScan& scan, const SplitAndMergeOptions& options);

}  // namespace pavilion::core
