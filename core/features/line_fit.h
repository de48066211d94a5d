#pragma once

#include <array>
#include <optional>
#include <span>
#include <vector>

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

// A reading prepared once for many fits: weight w = 1/sigma^2 (eq. 3.11), the
// bearing's cosine and sine, and the Cartesian point. Fits over prepared points
// need no trigonometry.
struct FitPoint {
  double range_m = 0.0;
  double cos_bearing = 1.0;
  double sin_bearing = 0.0;
  double weight = 1.0;
};

// Prepares a reading; nullopt for a non-finite value or a non-positive sigma.
std::optional<FitPoint> PrepareFitPoint(const PolarPoint& point);

// FitLine over prepared points (same result).
std::optional<Line> FitLinePrepared(std::span<const FitPoint> points);

// Fits of every run of consecutive prepared points in O(1) each, from prefix
// sums of the weighted moments: eqs. 3.4-3.5 with N and D written in second
// moments about the weighted mean, and eqs. 3.8-3.10 as quadratic forms in the
// moment matrix of (sin th, cos th, rho sin 2th, rho cos 2th) — the derivatives
// d alpha/d rho_i and d r/d rho_i are linear in those per-point terms with
// coefficients common to the run, and var_i = 1/w_i. For the sliding windows of
// the extraction (§3.2.2) and its clusters (unions of runs). The differences of
// prefix sums lose ~1e-16 of the scan's total moments: for ranges <= 80 m and
// sigma >= 1 mm the fitted alpha agrees with FitLinePrepared to ~1e-12, and a
// residual sum (FitMembers) is exact to ~1e-16 of the scan's sum w rho^2.
class PrefixLineFits {
 public:
  PrefixLineFits() = default;  // empty: Rebuild before fitting
  explicit PrefixLineFits(std::span<const FitPoint> points);
  // The sums of `points`, replacing those held (reusing the table's memory).
  void Rebuild(std::span<const FitPoint> points);
  // kFast computes alpha with a polynomial atan2 good to 1e-7 rad (for the
  // sliding windows, whose alpha sigma is of the order of 1e-2 rad); kExact
  // with std::atan2.
  enum class Precision { kExact, kFast };
  // The fit of points [begin, end); nullopt when degenerate.
  std::optional<Line> Fit(int begin, int end, Precision precision = Precision::kExact) const;
  // The fit of the points `members` (ascending indices, no repeats) in
  // O(runs log n) for runs of consecutive indices. `residual_sum`, when given,
  // receives the weighted residual sum of squares about the fit,
  // sum w_i (rho_i cos(theta_i - alpha) - r)^2: the minimum of the objective of
  // eqs. 3.4-3.5, the smaller eigenvalue (S - sqrt(N^2 + D^2)) / 2 of the
  // weighted scatter matrix about the mean (S its trace, N and D of eq. 3.4).
  std::optional<Line> FitMembers(std::span<const int> members,
                                 double* residual_sum = nullptr) const;

 private:
  // Per prefix: w, wx, wy, wxx, wyy, wxy, w rho^2, and the 10 entries of
  // sum w g g^T with g = (st, ct, rho s2t, rho c2t).
  static constexpr int kMoments = 17;
  using Moments = std::array<double, kMoments>;
  static std::optional<Line> FitMoments(const Moments& sums, Precision precision,
                                        double* residual_sum = nullptr);
  // Row i: the sums over points [0, i); n + 1 rows.
  std::vector<Moments> prefix_;
};

}  // namespace pavilion::core
