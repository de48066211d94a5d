#pragma once

#include <limits>

#include "core/features/range_noise.h"

namespace pavilion::core {

// Options of the probabilistic line extraction (thesis §3.2, appendix C).
struct LineExtractionOptions {
  // n_f, points per sliding window (§3.2.2); odd, >= 3. Default: SICK LMS 200
  // (0.5 deg, sigma 1 cm). The thesis chose n_f by angular resolution against
  // radial accuracy (n_f * resolution = 3.5 deg for the PLS, 3.75 deg for the
  // RS3). For the LMS 200, a sweep scored against ground truth (metrics.md;
  // office_floor 900 scans / expo_hall 600 scans with 30 visitors, three noise
  // seeds; tests/scenarios/scoring/extraction_scoring_test.cc) with the SickLms200()
  // preset (adaptive sigma, sparse lines, precision limits) gave true-positive
  // rates 0.976/0.951 (n_f 5), 0.995/0.960 (7), 0.994/0.963 (9), 0.994/0.961
  // (11) and false-positive rates 0.011/0.023, 0.014/0.028, 0.015/0.030,
  // 0.016/0.030. Small windows split walls into fragments that the precision
  // limits then drop; larger ones leave more far, short pieces whose r is off
  // by more than 5 cm. n_f = 7 (3.5 deg, as the thesis' PLS). Before the
  // extensions the same sweep gave 0.982/0.929 (7) and 0.974/0.919 (9), FP
  // 0.017/0.027 and 0.018/0.023, and n_f = 9 was the choice.
  int window_size = 7;
  // d_m, threshold on the model fidelity distance (eq. 3.15); > 0.
  double fidelity_threshold = 3.0;
  // alpha, significance level of the chi^2(2) collinearity test (eq. 3.16); in (0, 1).
  double significance = 0.99;
  // sigma_rho of every valid reading, m; > 0 (weights, eq. 3.11).
  double range_sigma_m = 0.01;
  // Segments supported by fewer readings are rejected; >= 2.
  int min_points = 2;
  // Fit consistency: a cluster whose weighted residual sum of squares (the
  // quantity eqs. 3.4-3.5 minimize) exceeds the chi^2(n - 2) quantile at
  // `consistency_significance` is not one line. The sliding windows of §3.2.2 cannot see a
  // gentle bend or a large arc (neighbouring windows differ by one reading), so
  // such a candidate is cut at its best two-line split, recursively, and a
  // fusion whose joined readings fail the test is refused. The thesis met the
  // same problem at Expo.02 (§6.5: walls differing by less than 5 deg, "tuned
  // for a slight tendency to oversegmentation"). Off for sensors whose range
  // error is not white (the test assumes independent readings of range_sigma_m).
  bool fit_consistency = true;
  // In (0, 1). Above alpha: a true line fails the test with probability
  // 1 - this, and a line cut in two by mistake is never fused again.
  double consistency_significance = 0.999;
  // Segments of one fused line interrupted by at least this many readings of
  // something else (an occluding visitor, the room behind a door) are reported
  // as the line's separate visible pieces, each a Segment sharing the fused line
  // and its line_id: the multi-segment line of eq. 5.17. >= 1.
  int min_gap_readings = 2;
  // Segments shorter than this (eq. 5.15) are rejected, m; >= 0. Rejects people's
  // legs (10-15 cm, §6.5) and bodies (~45 cm), and pieces of round objects the
  // fit consistency test cannot tell from a line: a 0.4 m chord of a 0.8 m
  // radius podium bulges 2.5 cm, within 2.6 sigma of 30 readings' residuals.
  double min_length_m = 0.5;
  // Additive covariance floor for correlated error (§2.2.1.3): standard
  // deviations added in quadrature to every fitted line's (alpha, r); >= 0.
  // Zero for white simulated noise, set for real logs and biased sensors.
  double alpha_sigma_floor_rad = 0.0;
  double r_sigma_floor_m = 0.0;
  // sigma_theta_e of the endpoint bearings (eq. 5.2), rad; >= 0, 0 means the
  // scan's angular resolution (the thesis' n = 4 at alpha = 0.95).
  double endpoint_bearing_sigma_rad = 0.0;
  // Range noise estimated from the scan (range_noise.h, an extension): readings
  // of a surface scattering well beyond range_sigma_m (black velvet, §3.2.4
  // fig. 3.6) are weighted with the sigma their scatter shows instead of the
  // nominal one (eq. 3.11 with a local sigma). Their windows are no model
  // points (the noise spans a window), so each such region is one candidate
  // for the top-down split of the fit consistency test. Off: every reading has
  // range_sigma_m, as in the thesis. A no-op where the noise is nominal.
  bool adaptive_range_sigma = true;
  RangeNoiseOptions range_noise;
  // Sparse lines (an extension): runs of at least this many readings that no
  // segment explains, cut at gaps of invalid readings, are split top-down by
  // the fit consistency test; a piece becomes a segment when its range
  // residuals (not only its perpendicular ones) are consistent, after its end
  // readings are shed while they are not (a mixed pixel at a face's end). A
  // face at grazing incidence is seen by readings farther apart than a window
  // can span (5 readings on 1.9 m) yet is a line to within the noise. 0: off
  // (the thesis' minimal segment of n_f readings); else >= 3.
  int sparse_min_points = 0;
  // Lines less certain than these are not reported (rad, m; > 0, infinity: all
  // reported): a line whose 2-sigma interval is wider than the distance to the
  // next wall cannot be told from it, and eqs. 3.8-3.10 are first-order — a
  // short, far or noisy fit is where they fail first.
  double max_alpha_sigma_rad = std::numeric_limits<double>::infinity();
  double max_r_sigma_m = std::numeric_limits<double>::infinity();

  // Throws std::invalid_argument naming the first invalid field.
  void Validate() const;

  // Per-sensor presets. The thesis used n_f = 7 for the SICK PLS 100 and the
  // Acuity AccuRange 3000, and n_f = 15 for the Leuze RS3 (§3.2.4).
  static LineExtractionOptions SickPls100();
  static LineExtractionOptions AccuRange3000();
  static LineExtractionOptions LeuzeRs3();
  static LineExtractionOptions SickLms200();
};

}  // namespace pavilion::core
