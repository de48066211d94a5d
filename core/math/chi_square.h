#pragma once

namespace pavilion::core {

// The chi-square distribution with `dof` degrees of freedom: the law of the
// squared Mahalanobis distance of a `dof`-dimensional Gaussian innovation, on
// which every validation gate of the thesis rests (eqs. 4.16, 5.47, 5.58).

// The p-quantile for two degrees of freedom in closed form, -2 ln(1 - p): the
// gate of every 2-d test (eqs. 3.16, 4.16 for lines); p in [0, 1).
double ChiSquare2Quantile(double p);

// P(X <= x) for X ~ chi^2(dof); dof >= 1, x >= 0 (0 for x <= 0).
double ChiSquareCdf(double x, int dof);

// The p-quantile chi^2_{p,dof}: the x with ChiSquareCdf(x, dof) = p. Throws
// std::invalid_argument unless p is in (0, 1) and dof >= 1. Accurate to a
// relative 1e-12 (bisection on the regularized incomplete gamma function).
double ChiSquareQuantile(double p, int dof);

// The standard normal quantile z_p (Newton on Phi(z) = erfc(-z / sqrt 2) / 2);
// p in (0, 1).
double NormalQuantile(double p);

// The Wilson-Hilferty cube approximation of the chi^2(dof) quantile whose
// normal quantile is z: dof (1 - h + z sqrt h)^3, h = 2 / (9 dof); dof >= 1.
// Closed form, for tests evaluated per fit (line extraction's fit consistency).
double ChiSquareQuantileWilsonHilferty(int dof, double z);

}  // namespace pavilion::core
