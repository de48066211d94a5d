// UMBmark (Borenstein & Feng 1996): the signs and sizes of formulas (C1)–(C4)
// and the fixed point of the iteration (C6) on synthetic end-pose errors.
#include "core/odometry/umbmark.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace pavilion::core {
namespace {

constexpr double kSideM = 4.0;

// The first-order end-position errors of one CCW and one CW square with corner
// over-turn a and leg curvature γ: ε_ccw = 2L(γ + a)(1, −1), ε_cw = 2L(a − γ)(1, 1).
SquareErrors FirstOrderErrors(double a, double g) {
  return {{Eigen::Vector3d(2 * kSideM * (g + a), -2 * kSideM * (g + a), 0)},
          {Eigen::Vector3d(2 * kSideM * (a - g), 2 * kSideM * (a - g), 0)}};
}

// A wider true wheelbase under-turns every corner (a < 0) and a larger right
// wheel curves every leg to the left (γ > 0): the signs of (C2) and (C3).
TEST(UmbmarkTest, SignsFollowTheErrorTypes) {
  const double a = -0.01, g = 0.004;
  const SquareErrors e = FirstOrderErrors(a, g);
  const UmbmarkResult u = EstimateUmbmark(e.ccw, e.cw, kSideM, 1.0, 0.4);
  EXPECT_NEAR(u.corner_overturn_rad, a, 1e-12);
  EXPECT_NEAR(u.leg_curvature_rad, g, 1e-12);
  EXPECT_LT(u.turn_factor, 1.0);
  EXPECT_GT(u.radius_ratio_factor, 1.0);
  EXPECT_NEAR(u.e_max_syst_m, std::max(e.ccw[0].head<2>().norm(), e.cw[0].head<2>().norm()), 1e-12);
}

// UMBmark needs squares of both directions.
TEST(UmbmarkTest, RejectsMissingDirections) {
  EXPECT_THROW(EstimateUmbmark({}, {Eigen::Vector3d::Zero()}, kSideM, 1.0, 0.4),
               std::invalid_argument);
  EXPECT_THROW(EstimateUmbmark({Eigen::Vector3d::Zero()}, {}, kSideM, 1.0, 0.4),
               std::invalid_argument);
}

// Error-free squares leave the nominal model as it is, up to the straight-run scale.
TEST(UmbmarkTest, ZeroErrorsKeepTheNominalModelScaled) {
  const SquareErrors e = FirstOrderErrors(0.0, 0.0);
  const UmbmarkResult u = EstimateUmbmark(e.ccw, e.cw, kSideM, 1.01, 0.4);
  EXPECT_DOUBLE_EQ(u.turn_factor, 1.0);
  EXPECT_DOUBLE_EQ(u.radius_ratio_factor, 1.0);
  const WheelGeometry g = UmbmarkCorrectedGeometry({0.1, 0.1, 0.4}, u, 1.01);
  EXPECT_NEAR(g.left_wheel_radius_m, 0.101, 1e-15);
  EXPECT_NEAR(g.right_wheel_radius_m, 0.101, 1e-15);
  EXPECT_NEAR(g.wheelbase_m, 0.404, 1e-15);
}

// (C4): the corrected radii keep the mean scale S and take the ratio E_d; the
// wheelbase is b·S/ρ.
TEST(UmbmarkTest, CorrectedGeometryTakesTheFactors) {
  UmbmarkResult u;
  u.radius_ratio_factor = 1.02;
  u.turn_factor = 0.98;
  const WheelGeometry g = UmbmarkCorrectedGeometry({0.1, 0.1, 0.5}, u, 1.003);
  EXPECT_NEAR(g.right_wheel_radius_m / g.left_wheel_radius_m, 1.02, 1e-12);
  EXPECT_NEAR(0.5 * (g.left_wheel_radius_m + g.right_wheel_radius_m), 0.1003, 1e-12);
  EXPECT_NEAR(g.wheelbase_m, 0.5 * 1.003 / 0.98, 1e-12);
}

// (C1): a straight run's arc is its chord when the heading does not change,
// and a half circle's chord times π/2 when it changes by π.
TEST(UmbmarkTest, ArcLengthFromChord) {
  EXPECT_DOUBLE_EQ(ArcLengthFromChord(3.0, 0.0), 3.0);
  EXPECT_NEAR(ArcLengthFromChord(2.0, std::numbers::pi), std::numbers::pi, 1e-12);
  EXPECT_NEAR(ArcLengthFromChord(2.0, -std::numbers::pi), std::numbers::pi, 1e-12);
  // Small curvature: arc ≈ chord (1 + γ²/24).
  EXPECT_NEAR(ArcLengthFromChord(4.0, 0.01), 4.0 * (1 + 1e-4 / 24), 1e-9);
}

// (C6): when the re-integrated residuals show half of the remaining error (a
// stand-in for the second-order terms one pass leaves), the iteration still
// converges to the true a and γ.
TEST(UmbmarkTest, IterationConvergesToTheTrueErrors) {
  const double a_true = -0.008, g_true = 0.003;
  const WheelGeometry nominal{0.1, 0.1, 0.4};
  // The residuals of a model whose factors imply (a, γ): the first-order
  // errors of what is left, a_true − a and γ_true − γ, with a and γ read back
  // from the model through (C4).
  const auto residuals = [&](const WheelGeometry& g) {
    const double rho = nominal.wheelbase_m / g.wheelbase_m;  // scale 1
    const double a = (rho - 1) * std::numbers::pi / 2;
    const double q = g.right_wheel_radius_m / g.left_wheel_radius_m;
    const double h = (q - 1) / (q + 1);
    const double gamma = h * 2 * kSideM / g.wheelbase_m;
    return FirstOrderErrors(0.5 * (a_true - a), 0.5 * (g_true - gamma));
  };
  // Started from the nominal model, each pass removes half of what is left.
  UmbmarkResult start;
  SetUmbmarkFactors(kSideM, 1.0, nominal.wheelbase_m, &start);
  int iterations = 0;
  const UmbmarkResult u =
      IterateUmbmark(start, nominal, kSideM, 1.0, residuals, 1e-12, 200, &iterations);
  EXPECT_GT(iterations, 1);
  EXPECT_LT(iterations, 200);
  EXPECT_NEAR(u.corner_overturn_rad, a_true, 1e-9);
  EXPECT_NEAR(u.leg_curvature_rad, g_true, 1e-9);
}

}  // namespace
}  // namespace pavilion::core
