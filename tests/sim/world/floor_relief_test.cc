// The uneven floor (sim/world/floor_relief.h): the waves' height, gradient
// and normal agree, a drawn relief keeps every slope within its maximum and
// reaches near it, its heights are correlated over metres and not across a
// hall, and its draw is deterministic.
#include "sim/world/floor_relief.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace pavilion::sim {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;
// expo_hall's floor, the largest of the shipped worlds' in one direction.
const Eigen::Vector2d kMin(-14.0, -3.0);
const Eigen::Vector2d kMax(18.0, 10.0);

FloorRelief Draw(std::uint64_t seed, const FloorReliefOptions& options = {}) {
  core::RandomStream random(seed, core::RandomStream::StreamId("floor_relief_test"));
  return DrawFloorRelief(options, kMin, kMax, &random);
}

TEST(FloorRelief, GradientAndNormalAgreeWithTheHeights) {
  const FloorRelief relief = Draw(1);
  ASSERT_FALSE(relief.flat());
  core::RandomStream random(7, core::RandomStream::StreamId("points"));
  constexpr double kStepM = 1e-5;
  for (int k = 0; k < 200; ++k) {
    const Eigen::Vector2d p(random.Uniform(kMin.x(), kMax.x()), random.Uniform(kMin.y(), kMax.y()));
    const Eigen::Vector2d dx(kStepM, 0.0), dy(0.0, kStepM);
    const Eigen::Vector2d numeric(
        (relief.HeightAt(p + dx) - relief.HeightAt(p - dx)) / (2 * kStepM),
        (relief.HeightAt(p + dy) - relief.HeightAt(p - dy)) / (2 * kStepM));
    EXPECT_NEAR((relief.GradientAt(p) - numeric).norm(), 0.0, 1e-8);
    const FloorRelief::Sample sample = relief.At(p);  // the same values in one pass
    EXPECT_EQ(sample.height_m, relief.HeightAt(p));
    EXPECT_EQ(sample.gradient, relief.GradientAt(p));
    const Eigen::Vector3d n = relief.NormalAt(p);
    EXPECT_EQ(sample.Normal(), n);
    EXPECT_NEAR(n.norm(), 1.0, 1e-12);
    // The normal is perpendicular to both tangents.
    EXPECT_NEAR(n.dot(Eigen::Vector3d(1.0, 0.0, numeric.x())), 0.0, 1e-8);
    EXPECT_NEAR(n.dot(Eigen::Vector3d(0.0, 1.0, numeric.y())), 0.0, 1e-8);
  }
  const FloorRelief flat;
  EXPECT_TRUE(flat.flat());
  EXPECT_EQ(flat.HeightAt({3.0, 4.0}), 0.0);
  EXPECT_EQ(flat.NormalAt({3.0, 4.0}), Eigen::Vector3d::UnitZ());
}

// The slope field: nowhere steeper than the maximum (checked on a grid five
// times finer than the draw's and at random points), its steepest within the
// draw's curvature margin of it, and its typical slope a fraction of it.
TEST(DrawFloorRelief, NoSlopeSteeperThanTheMaximumAndTheSteepestNearIt) {
  for (const std::uint64_t seed : {1u, 2u, 3u}) {
    const FloorReliefOptions options;
    const FloorRelief relief = Draw(seed, options);
    const double limit = std::tan(options.max_slope_rad);
    double steepest = 0.0, sum_squares = 0.0;
    int samples = 0;
    constexpr double kFineM = 0.01;
    // A 4 m x 4 m patch at the finest spacing, the whole floor at 5 cm offset by half a cell.
    for (double x = 0.0; x <= 4.0; x += kFineM) {
      for (double y = 0.0; y <= 4.0; y += kFineM) {
        steepest = std::max(steepest, relief.GradientAt({x, y}).norm());
      }
    }
    for (double x = kMin.x() + 0.025; x < kMax.x(); x += 0.05) {
      for (double y = kMin.y() + 0.025; y < kMax.y(); y += 0.05) {
        const double s = relief.GradientAt({x, y}).norm();
        steepest = std::max(steepest, s);
        sum_squares += s * s;
        ++samples;
      }
    }
    const double rms = std::sqrt(sum_squares / samples);
    std::printf("seed %d: steepest %.3f deg, rms %.3f deg (limit %.3f deg)\n",
                static_cast<int>(seed), std::atan(steepest) / kDeg, std::atan(rms) / kDeg,
                options.max_slope_rad / kDeg);
    EXPECT_LE(steepest, limit) << seed;
    EXPECT_GT(steepest, 0.93 * limit) << seed;
    EXPECT_GT(rms, 0.2 * limit) << seed;
    EXPECT_LT(rms, 0.6 * limit) << seed;
    // Heights of a few millimetres: the 8 m waves at most a centimetre or so.
    double lowest = 0.0, highest = 0.0;
    for (double x = kMin.x(); x <= kMax.x(); x += 0.25) {
      for (double y = kMin.y(); y <= kMax.y(); y += 0.25) {
        lowest = std::min(lowest, relief.HeightAt({x, y}));
        highest = std::max(highest, relief.HeightAt({x, y}));
      }
    }
    EXPECT_GT(highest - lowest, 0.002) << seed;
    EXPECT_LT(highest - lowest, 0.05) << seed;
  }
}

// Correlation of the heights at a lag, over random points and directions.
double HeightCorrelation(const FloorRelief& relief, double lag_m) {
  core::RandomStream random(11, core::RandomStream::StreamId("lags"));
  std::vector<double> a, b;
  for (int k = 0; k < 4000; ++k) {
    const Eigen::Vector2d p(random.Uniform(kMin.x(), kMax.x()), random.Uniform(kMin.y(), kMax.y()));
    const double direction = random.Uniform(0.0, 2.0 * std::numbers::pi);
    a.push_back(relief.HeightAt(p));
    b.push_back(
        relief.HeightAt(p + lag_m * Eigen::Vector2d(std::cos(direction), std::sin(direction))));
  }
  const auto mean = [](const std::vector<double>& v) {
    double s = 0.0;
    for (double x : v) s += x;
    return s / v.size();
  };
  const double ma = mean(a), mb = mean(b);
  double sab = 0.0, saa = 0.0, sbb = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    sab += (a[k] - ma) * (b[k] - mb);
    saa += (a[k] - ma) * (a[k] - ma);
    sbb += (b[k] - mb) * (b[k] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

// A floor is smooth under a robot (its wheels 0.2-0.4 m apart see nearly the
// same height) and forgets across a room: the longest waves set the
// correlation length, a few metres.
TEST(DrawFloorRelief, HeightsAreCorrelatedUnderARobotNotAcrossTheHall) {
  const FloorRelief relief = Draw(4);
  EXPECT_GT(HeightCorrelation(relief, 0.1), 0.95);
  EXPECT_GT(HeightCorrelation(relief, 0.5), 0.6);
  EXPECT_LT(std::abs(HeightCorrelation(relief, 12.0)), 0.35);
}

TEST(DrawFloorRelief, IsDeterministicAndScalesWithTheMaximum) {
  const FloorRelief a = Draw(5), b = Draw(5), c = Draw(6);
  ASSERT_EQ(a.waves().size(), b.waves().size());
  for (std::size_t k = 0; k < a.waves().size(); ++k) {
    EXPECT_EQ(a.waves()[k].amplitude_m, b.waves()[k].amplitude_m);
    EXPECT_EQ(a.waves()[k].wavevector_radpm, b.waves()[k].wavevector_radpm);
  }
  EXPECT_NE(a.HeightAt({1.0, 1.0}), c.HeightAt({1.0, 1.0}));
  // Half the maximum: the same waves at half the amplitude.
  FloorReliefOptions half;
  half.max_slope_rad = 0.25 * kDeg;
  const FloorRelief h = Draw(5, half);
  for (const Eigen::Vector2d& p : {Eigen::Vector2d(1.0, 2.0), Eigen::Vector2d(-7.0, 5.5)}) {
    EXPECT_NEAR(h.HeightAt(p), a.HeightAt(p) * std::tan(0.25 * kDeg) / std::tan(0.5 * kDeg), 1e-12);
  }
}

TEST(DrawFloorRelief, RejectsBadOptionsNamingTheField) {
  core::RandomStream random(1, core::RandomStream::StreamId("x"));
  FloorReliefOptions o;
  o.max_slope_rad = 0.1;
  EXPECT_THROW(DrawFloorRelief(o, kMin, kMax, &random), std::invalid_argument);
  o = {};
  o.min_wavelength_m = 9.0;  // above the maximum
  EXPECT_THROW(DrawFloorRelief(o, kMin, kMax, &random), std::invalid_argument);
  o = {};
  o.waves = 0;
  EXPECT_THROW(DrawFloorRelief(o, kMin, kMax, &random), std::invalid_argument);
  EXPECT_THROW(DrawFloorRelief({}, kMax, kMin, &random), std::invalid_argument);
  EXPECT_THROW(FloorRelief({{{1.0, 0.0}, -0.001, 0.0}}), std::invalid_argument);
  try {
    o = {};
    o.waves = 0;
    o.Validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("FloorReliefOptions.waves"), std::string::npos);
  }
}

}  // namespace
}  // namespace pavilion::sim
