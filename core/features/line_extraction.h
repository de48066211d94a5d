#pragma once

#include <vector>

#include "core/features/uncertain_geometry.h"
#include "core/types/sensor_data.h"

namespace pavilion::core {

// Options of the probabilistic line extraction (thesis §3.2, appendix C).
struct LineExtractionOptions {
  // n_f, points per sliding window (§3.2.2); odd, >= 3. Default: SICK LMS 200
  // (0.5 deg, sigma 1 cm). The thesis chose n_f by angular resolution against
  // radial accuracy (n_f * resolution = 3.5 deg for the PLS, 3.75 deg for the
  // RS3). For the LMS 200 a sweep over n_f = 5..15 on simulated rooms
  // (line_extraction_test, WindowSizeSweepForLms200) gave: n_f <= 9 leaves short
  // fragments whose edge readings bias their fit, so they fail the chi^2 fusion
  // test (2-6% of walls split, 0.04-0.09 inconsistent lines per scan, 90-93% of
  // (alpha, r) errors in the 95% gate); n_f = 11 gives 1.3% split walls, no
  // spurious line, 94% in the gate; 13 and 15 gain little but need longer
  // walls. n_f = 11 (5.5 deg) keeps the minimal segment at 13 readings, a 1 m
  // wall at 6 m seen within ~45 deg of head-on.
  int window_size = 11;
  // d_m, threshold on the model fidelity distance (eq. 3.15); > 0.
  double fidelity_threshold = 3.0;
  // alpha, significance level of the chi^2(2) collinearity test (eq. 3.16); in (0, 1).
  double significance = 0.99;
  // sigma_rho of every valid reading, m; > 0 (weights, eq. 3.11).
  double range_sigma_m = 0.01;
  // Segments supported by fewer readings are rejected; >= 2.
  int min_points = 2;
  // Segments shorter than this (eq. 5.15) are rejected, m; >= 0. Rejects people's
  // legs (10-15 cm wide, §6.5) with a margin for endpoint noise.
  double min_length_m = 0.3;
  // Additive covariance floor for correlated error (§2.2.1.3): standard
  // deviations added in quadrature to every fitted line's (alpha, r); >= 0.
  // Zero for white simulated noise, set for real logs and biased sensors.
  double alpha_sigma_floor_rad = 0.0;
  double r_sigma_floor_m = 0.0;
  // sigma_theta_e of the endpoint bearings (eq. 5.2), rad; >= 0, 0 means the
  // scan's angular resolution (the thesis' n = 4 at alpha = 0.95).
  double endpoint_bearing_sigma_rad = 0.0;

  // Throws std::invalid_argument naming the first invalid field.
  void Validate() const;

  // Per-sensor presets. The thesis used n_f = 7 for the SICK PLS 100 and the
  // Acuity AccuRange 3000, and n_f = 15 for the Leuze RS3 (§3.2.4).
  static LineExtractionOptions SickPls100();
  static LineExtractionOptions AccuRange3000();
  static LineExtractionOptions LeuzeRs3();
  static LineExtractionOptions SickLms200();
};

// The chi^2 quantile with two degrees of freedom at probability p, -2 ln(1 - p).
double ChiSquare2Quantile(double p);

// Extracts line segments from a scan (thesis §3.2, appendix C): a line is fitted
// to every window of n_f consecutive valid readings (eqs. 3.4-3.10), windows
// whose model fidelity distance (eqs. 3.12-3.14) is at most d_m (eq. 3.15) form
// segment candidates, and collinear candidates (chi^2 test, eq. 3.16) are fused
// by re-fitting their joined readings under the overlap-adjacency-collinearity
// policy. Invalid readings are skipped. Segments are in the sensor frame, in
// order of their first reading; their lines have r >= 0. Segments shorter than
// min_length_m, or whose longest run of consecutive readings is (legs fused
// across a gap), are rejected. Cost: O(n n_f) for the segmentation, O(n_s^2)
// chi^2 distances per fusion of the n_s candidates.
std::vector<Segment> ExtractLines(const LaserScan& scan, const LineExtractionOptions& options);

}  // namespace pavilion::core
