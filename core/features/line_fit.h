#pragma once

#include <optional>
#include <span>

#include "core/features/uncertain_geometry.h"

namespace pavilion::core {

// One range reading in polar form, in the sensor frame.
struct PolarPoint {
  double range_m = 0.0;        // rho_i
  double bearing_rad = 0.0;    // theta_i
  double range_sigma_m = 0.0;  // sigma_rho_i > 0; weight w_i = 1 / sigma^2 (eq. 3.11)
};

// Weighted least-squares line through the points minimizing perpendicular
// errors, in closed form (eqs. 3.4-3.5), with the first-order covariance of
// (alpha, r) from the range uncertainties alone (eqs. 3.8-3.10; bearing noise is
// neglected as in the thesis). The result has r >= 0 (the line is visible from
// the sensor, eq. B.4). Returns nullopt for fewer than two points, a non-finite
// or non-positive sigma, or a degenerate point set (all points coincident).
std::optional<Line> FitLine(std::span<const PolarPoint> points);

}  // namespace pavilion::core
