#pragma once

// The two statistical tests on (alpha, r) line estimates of the line
// extraction (thesis §3.2.2-3.2.3): the model fidelity of a sliding window's
// fit against its neighbours' (eqs. 3.12-3.15) and the collinearity distance
// of two lines (eq. 3.16), in closed-form 2x2 algebra.

#include <Eigen/Core>

#include "core/features/uncertain_geometry.h"

namespace pavilion::core {

// A symmetric 2x2 matrix [a b; b c] of (alpha, r) with the closed-form algebra
// the fidelity and collinearity tests need.
struct Sym2 {
  double a = 0.0, b = 0.0, c = 0.0;

  static Sym2 Of(const Eigen::Matrix2d& m) { return {m(0, 0), 0.5 * (m(0, 1) + m(1, 0)), m(1, 1)}; }
  double Determinant() const { return a * c - b * b; }
  Sym2 Inverse() const {  // requires Determinant() != 0
    const double inv = 1.0 / Determinant();
    return {c * inv, -b * inv, a * inv};
  }
  Sym2 operator+(const Sym2& o) const { return {a + o.a, b + o.b, c + o.c}; }
  // v^T M^-1 v for v = (x, y), without forming the inverse.
  double InverseQuadratic(double x, double y) const {
    return (c * x * x - 2.0 * b * x * y + a * y * y) / Determinant();
  }
};

// A window's fit as the fidelity test uses it.
struct WindowFit {
  double alpha_rad = 0.0;
  double r_m = 0.0;
  Sym2 covariance;
  Sym2 information;  // covariance^-1
};

// The model fidelity test d_i <= d_m (eq. 3.15) with the distance d_i of eq.
// 3.12 for the model points (the window fits windows[0..2] at i - 1, i, i + 1)
// and their information-filter mean (eqs. 3.13-3.14). Angles are taken
// relative to the middle window's, so differences never wrap.
bool FidelityPasses(const WindowFit* windows, double threshold);

// Squared Mahalanobis distance of two lines, eq. 3.16 (alpha relative to a's);
// +inf when the summed covariance is singular.
double CollinearityDistance(const Line& a, const Line& b);

}  // namespace pavilion::core
