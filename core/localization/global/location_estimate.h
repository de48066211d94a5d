#pragma once

// Estimating the robot location from a supporting set without a prior (thesis
// §5.4.2): the extended information filter with zero prior information (eq.
// 5.66), i.e. the weighted least-squares solution of eq. 5.67 through the
// pseudoinverse (eq. 5.68), iterated to convergence because the measurement
// model is non-linear in the heading.

#include <span>

#include "core/localization/global/location_hypothesis.h"
#include "core/localization/measurement_prediction.h"

namespace pavilion::core {

struct LocationEstimateOptions {
  // Gauss-Newton iterations of eq. 5.67 at most; >= 1. Chosen: from the
  // closed-form start below, two or three reach 1e-9 m.
  int max_iterations = 8;
  double converged_m = 1e-7;  // stop when the step is below this (m and rad); > 0
  // location_available (§5.4.2) is true when grad h^T R^-1 grad h is
  // non-singular. Numerically, nearly parallel lines leave it regular but
  // with metres of uncertainty along them, which would let every gate pass:
  // the location counts as available only when its position and heading
  // standard deviations are at most these. Chosen: a quarter of the 2 m
  // scale of the hall's features; 10 deg.
  double max_position_sigma_m = 0.5;
  double max_heading_sigma_rad = 0.1745;

  void Validate() const;  // throws std::invalid_argument naming the field
};

struct LocationEstimate {
  bool available = false;          // location_available of Algorithm 1
  PoseWithCovariance location;     // x^ and P = (grad h^T R^-1 grad h)^-1 (eq. 5.63 with 5.66)
  double joint_mahalanobis = 0.0;  // sum of v^T S^-1 v over the pairings at x^
};

// The location from the non-star pairings of `support` (local features of
// `local`). The start: the heading from the line pairings' angle differences
// (or from the bearing of two point pairings), then the position from the
// linear equations r_g - n_g . t = r_l (lines) and t = p_g - R p_l (points).
// Not available when the supporting set fixes no heading or no position, or
// the result is too uncertain (see the options).
LocationEstimate EstimateLocation(const MeasurementPredictor& predictor, const LocalMap& local,
                                  std::span<const Pairing> support,
                                  const LocationEstimateOptions& options = {});

}  // namespace pavilion::core
