#include "core/math/chi_square.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace pavilion::core {
namespace {

constexpr int kMaxSeriesTerms = 10000;
constexpr double kSeriesTolerance = 1e-16;
constexpr int kBisectionSteps = 200;
constexpr double kQuantileRelativeTolerance = 1e-13;

// Regularized lower incomplete gamma P(a, x): the series for x < a + 1, else
// 1 - Q(a, x) from the Lentz continued fraction (Press et al., §6.2).
double RegularizedGammaP(double a, double x) {
  if (x <= 0.0) return 0.0;
  const double log_prefix = a * std::log(x) - x - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a;
    double sum = term;
    for (int n = 1; n < kMaxSeriesTerms; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * kSeriesTolerance) break;
    }
    return sum * std::exp(log_prefix);
  }
  constexpr double kTiny =
      std::numeric_limits<double>::min() / std::numeric_limits<double>::epsilon();
  double b = x + 1.0 - a;
  double c = 1.0 / kTiny;
  double d = 1.0 / b;
  double h = d;
  for (int i = 1; i < kMaxSeriesTerms; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < kTiny) d = kTiny;
    c = b + an / c;
    if (std::abs(c) < kTiny) c = kTiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < kSeriesTolerance) break;
  }
  return 1.0 - std::exp(log_prefix) * h;
}

}  // namespace

double ChiSquare2Quantile(double p) { return -2.0 * std::log1p(-p); }

double ChiSquareCdf(double x, int dof) {
  if (dof < 1) throw std::invalid_argument("ChiSquareCdf: dof must be >= 1");
  return RegularizedGammaP(0.5 * dof, 0.5 * x);
}

double ChiSquareQuantile(double p, int dof) {
  if (!(p > 0.0 && p < 1.0)) throw std::invalid_argument("ChiSquareQuantile: p must be in (0, 1)");
  if (dof < 1) throw std::invalid_argument("ChiSquareQuantile: dof must be >= 1");
  // Bracket: the cdf is increasing; grow the upper bound until it passes p.
  double lo = 0.0;
  double hi = dof + 10.0 * std::sqrt(2.0 * dof) + 10.0;
  while (ChiSquareCdf(hi, dof) < p) hi *= 2.0;
  for (int i = 0; i < kBisectionSteps && hi - lo > kQuantileRelativeTolerance * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (ChiSquareCdf(mid, dof) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double NormalQuantile(double p) {
  double z = 0.0;
  for (int i = 0; i < 100; ++i) {
    const double phi = 0.5 * std::erfc(-z / std::numbers::sqrt2);
    const double density = std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::numbers::pi);
    const double step = std::clamp((phi - p) / density, -1.0, 1.0);
    z -= step;
    if (std::abs(step) < 1e-12) break;
  }
  return z;
}

double ChiSquareQuantileWilsonHilferty(int dof, double z) {
  const double k = dof;
  const double h = 2.0 / (9.0 * k);
  const double c = 1.0 - h + z * std::sqrt(h);
  return k * c * c * c;
}

}  // namespace pavilion::core
