// The chi-square distribution behind every validation gate (eqs. 4.16, 5.47, 5.58).
#include "core/math/chi_square.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace pavilion::core {
namespace {

// Quantiles match published table values (Abramowitz & Stegun, Table 26.8).
TEST(ChiSquareTest, QuantilesMatchTables) {
  EXPECT_NEAR(ChiSquareQuantile(0.95, 1), 3.841458820694124, 1e-10);
  EXPECT_NEAR(ChiSquareQuantile(0.95, 2), 5.991464547107979, 1e-10);
  EXPECT_NEAR(ChiSquareQuantile(0.95, 3), 7.814727903251178, 1e-10);
  EXPECT_NEAR(ChiSquareQuantile(0.99, 3), 11.344866730144373, 1e-9);
  EXPECT_NEAR(ChiSquareQuantile(0.05, 10), 3.940299136119769, 1e-9);
  EXPECT_NEAR(ChiSquareQuantile(0.975, 100), 129.5611971427257, 1e-7);
}

// The cdf matches the closed forms for 1 dof, erf(sqrt(x/2)), and 2 dof,
// 1 - exp(-x/2), and the quantile inverts the cdf, for small and large dof.
TEST(ChiSquareTest, CdfMatchesClosedFormsAndQuantileInvertsIt) {
  for (double x : {0.01, 0.5, 1.0, 3.0, 10.0, 30.0}) {
    EXPECT_NEAR(ChiSquareCdf(x, 1), std::erf(std::sqrt(0.5 * x)), 1e-13) << x;
    EXPECT_NEAR(ChiSquareCdf(x, 2), 1.0 - std::exp(-0.5 * x), 1e-13) << x;
  }
  for (int dof : {1, 2, 3, 7, 600}) {
    for (double p : {0.001, 0.025, 0.5, 0.95, 0.975, 0.999}) {
      EXPECT_NEAR(ChiSquareCdf(ChiSquareQuantile(p, dof), dof), p, 1e-11) << dof << " " << p;
    }
  }
}

// Out-of-range arguments throw instead of returning nonsense.
TEST(ChiSquareTest, RejectsBadArguments) {
  EXPECT_THROW(ChiSquareQuantile(0.0, 2), std::invalid_argument);
  EXPECT_THROW(ChiSquareQuantile(1.0, 2), std::invalid_argument);
  EXPECT_THROW(ChiSquareQuantile(0.5, 0), std::invalid_argument);
  EXPECT_THROW(ChiSquareCdf(1.0, 0), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::core
