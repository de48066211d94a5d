#include "core/features/line_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "core/random/random_stream.h"

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;

// Readings of the line (alpha, r) (r > 0) at the given bearings, exact ranges (eq. B.2).
std::vector<PolarPoint> PointsOnLine(double alpha, double r, double first_bearing,
                                     double last_bearing, int n, double sigma) {
  std::vector<PolarPoint> points;
  for (int i = 0; i < n; ++i) {
    const double theta = first_bearing + (last_bearing - first_bearing) * i / (n - 1);
    points.push_back({r / std::cos(theta - alpha), theta, sigma});
  }
  return points;
}

// Sample covariance of 2-vectors.
Eigen::Matrix2d SampleCovariance(const std::vector<Eigen::Vector2d>& xs) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& x : xs) mean += x;
  mean /= static_cast<double>(xs.size());
  Eigen::Matrix2d c = Eigen::Matrix2d::Zero();
  for (const auto& x : xs) c += (x - mean) * (x - mean).transpose();
  return c / static_cast<double>(xs.size() - 1);
}

// Compares covariances element-wise: variances within `rel`, the covariance
// within `rel` of sqrt(var_a var_b).
void ExpectCovarianceNear(const Eigen::Matrix2d& predicted, const Eigen::Matrix2d& empirical,
                          double rel) {
  EXPECT_NEAR(predicted(0, 0), empirical(0, 0), rel * empirical(0, 0));
  EXPECT_NEAR(predicted(1, 1), empirical(1, 1), rel * empirical(1, 1));
  EXPECT_NEAR(predicted(0, 1), empirical(0, 1), rel * std::sqrt(empirical(0, 0) * empirical(1, 1)));
}

// Noise-free points on a known line give back exactly its (alpha, r) with r >= 0,
// in every quadrant and with unequal weights (eqs. 3.4-3.5).
TEST(LineFitTest, RecoversKnownLineExactly) {
  RandomStream rng(11, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const double alpha = rng.Uniform(-kPi, kPi);
    const double r = rng.Uniform(0.2, 8.0);
    const double half_span = rng.Uniform(0.05, 1.2);
    const double center = alpha + rng.Uniform(-0.3, 0.3);
    std::vector<PolarPoint> points =
        PointsOnLine(alpha, r, center - half_span, center + half_span, 20, 0.01);
    for (PolarPoint& p : points) p.range_sigma_m = rng.Uniform(0.005, 0.05);
    const std::optional<Line> line = FitLine(points);
    ASSERT_TRUE(line.has_value());
    EXPECT_NEAR(NormalizeAngle(line->alpha_rad - alpha), 0.0, 1e-9);
    EXPECT_NEAR(line->r_m, r, 1e-9);
    EXPECT_GE(line->r_m, 0.0);
  }
}

// Two points suffice; fewer, bad sigmas or coincident points give no line.
TEST(LineFitTest, RejectsDegenerateInput) {
  EXPECT_TRUE(FitLine(PointsOnLine(0.2, 1.0, 0.0, 0.4, 2, 0.01)).has_value());
  EXPECT_FALSE(FitLine(std::vector<PolarPoint>{{1.0, 0.1, 0.01}}).has_value());
  EXPECT_FALSE(FitLine(std::vector<PolarPoint>{{1.0, 0.1, 0.01}, {1.0, 0.1, 0.01}}).has_value());
  EXPECT_FALSE(FitLine(std::vector<PolarPoint>{{1.0, 0.1, 0.0}, {1.0, 0.2, 0.01}}).has_value());
  EXPECT_FALSE(
      FitLine(std::vector<PolarPoint>{{std::nan(""), 0.1, 0.01}, {1.0, 0.2, 0.01}}).has_value());
}

// The covariance of eqs. 3.8-3.10 matches the scatter of (alpha, r) over 4000
// fits of noisy readings within 10%, for several geometries and weightings.
TEST(LineFitTest, CovarianceMatchesMonteCarlo) {
  struct Case {
    double alpha, r, first, last;
    int n;
  };
  const Case cases[] = {
      {0.3, 2.0, -0.2, 0.6, 50}, {-2.0, 4.0, -2.3, -1.9, 15}, {1.5, 1.0, 0.5, 2.4, 100}};
  RandomStream rng(12, 1);
  for (const Case& c : cases) {
    std::vector<PolarPoint> truth = PointsOnLine(c.alpha, c.r, c.first, c.last, c.n, 0.01);
    for (int i = 0; i < c.n; ++i) truth[i].range_sigma_m = 0.005 + 0.02 * (i % 3);
    const Line predicted = *FitLine(truth);
    std::vector<Eigen::Vector2d> samples;
    for (int draw = 0; draw < 4000; ++draw) {
      std::vector<PolarPoint> noisy = truth;
      for (PolarPoint& p : noisy) p.range_m += rng.Normal(0.0, p.range_sigma_m);
      const Line fit = *FitLine(noisy);
      samples.push_back(
          {predicted.alpha_rad + NormalizeAngle(fit.alpha_rad - predicted.alpha_rad), fit.r_m});
    }
    SCOPED_TRACE(c.alpha);
    ExpectCovarianceNear(predicted.covariance, SampleCovariance(samples), 0.10);
  }
}

// The O(1) window fits from prefix moments equal the direct fit (eqs. 3.4-3.10
// in moments), windows near and far, noisy, with unequal weights.
TEST(PrefixLineFits, WindowFitsEqualTheDirectFit) {
  RandomStream rng(21, 3);
  std::vector<FitPoint> points;
  for (int i = 0; i < 361; ++i) {
    const double bearing = -std::numbers::pi / 2 + i * std::numbers::pi / 360;
    const double range = 0.5 + 7.5 * std::abs(std::sin(0.05 * i)) + rng.Normal(0.0, 0.01);
    points.push_back(*PrepareFitPoint({range, bearing, 0.005 + 0.01 * (i % 4)}));
  }
  const PrefixLineFits prefix(points);
  for (int begin = 0; begin + 11 <= 361; begin += 7) {
    for (int length : {3, 11, 40}) {
      if (begin + length > 361) continue;
      const std::optional<Line> fast = prefix.Fit(begin, begin + length);
      const std::optional<Line> direct =
          FitLinePrepared(std::span<const FitPoint>(points.data() + begin, length));
      ASSERT_EQ(fast.has_value(), direct.has_value());
      if (!fast) continue;
      SCOPED_TRACE(begin);
      EXPECT_NEAR(NormalizeAngle(fast->alpha_rad - direct->alpha_rad), 0.0, 1e-9);
      EXPECT_NEAR(fast->r_m, direct->r_m, 1e-9);
      for (int k = 0; k < 4; ++k) {
        EXPECT_NEAR(fast->covariance(k), direct->covariance(k),
                    1e-7 * std::abs(direct->covariance(k)) + 1e-15);
      }
    }
  }
}

// Members given as runs (a cluster fused across a gap) fit as the direct fit of
// those points; the windows' polynomial atan2 agrees to 5e-8 rad.
TEST(PrefixLineFits, MemberFitsAndFastWindowsAgreeWithTheDirectFit) {
  RandomStream rng(22, 3);
  std::vector<FitPoint> points;
  for (int i = 0; i < 361; ++i) {
    const double bearing = -std::numbers::pi / 2 + i * std::numbers::pi / 360;
    const double range = 0.5 + 7.5 * std::abs(std::cos(0.03 * i)) + rng.Normal(0.0, 0.01);
    points.push_back(*PrepareFitPoint({range, bearing, 0.01}));
  }
  const PrefixLineFits prefix(points);
  std::vector<int> members;
  std::vector<FitPoint> subset;
  for (int i = 40; i < 300; ++i) {
    if (i % 50 < 20) continue;  // gaps
    members.push_back(i);
    subset.push_back(points[i]);
  }
  const std::optional<Line> runs = prefix.FitMembers(members);
  const std::optional<Line> direct = FitLinePrepared(subset);
  ASSERT_TRUE(runs && direct);
  EXPECT_NEAR(NormalizeAngle(runs->alpha_rad - direct->alpha_rad), 0.0, 1e-9);
  EXPECT_NEAR(runs->r_m, direct->r_m, 1e-9);
  for (int begin = 0; begin + 9 <= 361; ++begin) {
    const std::optional<Line> exact = prefix.Fit(begin, begin + 9);
    const std::optional<Line> fast = prefix.Fit(begin, begin + 9, PrefixLineFits::Precision::kFast);
    ASSERT_EQ(exact.has_value(), fast.has_value());
    if (!exact) continue;
    EXPECT_NEAR(NormalizeAngle(fast->alpha_rad - exact->alpha_rad), 0.0, 5e-8) << begin;
    EXPECT_NEAR(fast->r_m, exact->r_m, 1e-7) << begin;
  }
}

// A member fit's residual sum is the weighted sum of squared residuals about its
// line, sum w_i (rho_i cos(theta_i - alpha) - r)^2 (the minimum of the objective
// of eqs. 3.4-3.5), for members with gaps, noisy ranges and unequal weights, and
// vanishes on exact points. Prefix differences lose ~1e-16 of the scan's total
// sum w rho^2, which bounds the tolerance.
TEST(PrefixLineFits, MemberFitsReportTheirResidualSum) {
  RandomStream rng(23, 3);
  const double alpha = 0.4;
  const double r = 3.0;
  for (const double noise_scale : {1.0, 0.0}) {
    std::vector<FitPoint> points;
    double total_w_rho2 = 0.0;
    for (int i = 0; i < 361; ++i) {
      const double bearing = -0.6 + i * 1.6 / 360;
      const double sigma = 0.005 + 0.01 * (i % 4);
      const double range = r / std::cos(bearing - alpha) + noise_scale * rng.Normal(0.0, sigma);
      points.push_back(*PrepareFitPoint({range, bearing, sigma}));
      total_w_rho2 += points.back().weight * range * range;
    }
    const PrefixLineFits prefix(points);
    std::vector<int> members;
    for (int i = 30; i < 330; ++i) {
      if (i % 50 >= 20) members.push_back(i);  // runs with gaps
    }
    double residual_sum = -1.0;
    const std::optional<Line> line = prefix.FitMembers(members, &residual_sum);
    ASSERT_TRUE(line);
    double direct = 0.0;
    for (int k : members) {
      const FitPoint& p = points[k];
      const double d = p.range_m * (p.cos_bearing * std::cos(line->alpha_rad) +
                                    p.sin_bearing * std::sin(line->alpha_rad)) -
                       line->r_m;
      direct += p.weight * d * d;
    }
    SCOPED_TRACE(noise_scale);
    EXPECT_NEAR(residual_sum, direct, 1e-14 * total_w_rho2 + 1e-9 * direct);
    EXPECT_GE(residual_sum, 0.0);
  }
}

}  // namespace
}  // namespace pavilion::core
