#include "core/features/beacon_extraction.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/random/random_stream.h"

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;

// A 361-reading scan with no returns except the given reflector runs.
LaserScan EmptyScan() {
  LaserScan scan;
  for (int i = 0; i < 361; ++i) {
    LaserReading r;
    r.bearing_rad = -kPi / 2 + i * kPi / 360;
    r.range_m = 8.0;
    scan.readings.push_back(r);
  }
  return scan;
}

void Reflector(LaserScan* scan, int first, int last, double range) {
  for (int i = first; i <= last; ++i) {
    scan->readings[i].range_m = range;
    scan->readings[i].valid = true;
    scan->readings[i].reflector = true;
  }
}

TEST(BeaconExtraction, EstimatesRangeBearingAndTheirCovariance) {
  LaserScan scan = EmptyScan();
  Reflector(&scan, 100, 104, 3.0);  // five inliers
  scan.readings[90].valid = true;   // a normal return nearby is not a beacon
  scan.readings[90].range_m = 2.0;
  BeaconExtractionOptions o;
  const std::vector<Beacon> beacons = ExtractBeacons(scan, o);
  ASSERT_EQ(beacons.size(), 1u);
  const Beacon& b = beacons[0];
  EXPECT_EQ(b.point_count, 5);
  EXPECT_NEAR(b.range_m, 3.0, 1e-12);
  EXPECT_NEAR(b.bearing_rad, -kPi / 2 + 102 * kPi / 360, 1e-12);
  EXPECT_NEAR(b.polar_covariance(0, 0), 0.01 * 0.01 / 5, 1e-15);  // eq. 3.18
  const double sigma_theta = 0.25 * (kPi / 360) * 6;              // eq. 3.20
  EXPECT_NEAR(b.polar_covariance(1, 1), sigma_theta * sigma_theta, 1e-15);
  EXPECT_EQ(b.polar_covariance(0, 1), 0.0);
}

// Eqs. 3.17-3.18: the information-filter range has the variance sigma^2 / n_b.
TEST(BeaconExtraction, RangeVarianceMatchesMonteCarlo) {
  RandomStream rng(5, 6);
  BeaconExtractionOptions o;
  o.range_sigma_m = 0.02;
  double sum = 0.0, sum_sq = 0.0;
  const int draws = 4000;
  double predicted = 0.0;
  for (int d = 0; d < draws; ++d) {
    LaserScan scan = EmptyScan();
    Reflector(&scan, 200, 207, 4.0);
    for (int i = 200; i <= 207; ++i) scan.readings[i].range_m += rng.Normal(0.0, o.range_sigma_m);
    const std::vector<Beacon> beacons = ExtractBeacons(scan, o);
    ASSERT_EQ(beacons.size(), 1u);
    sum += beacons[0].range_m;
    sum_sq += beacons[0].range_m * beacons[0].range_m;
    predicted = beacons[0].polar_covariance(0, 0);
  }
  const double mean = sum / draws;
  const double variance = sum_sq / draws - mean * mean;
  EXPECT_NEAR(mean, 4.0, 5 * std::sqrt(predicted / draws));
  EXPECT_NEAR(variance, predicted, 0.1 * predicted);
}

TEST(BeaconExtraction, SplitsAtRangeJumpsAndGaps) {
  LaserScan scan = EmptyScan();
  Reflector(&scan, 50, 53, 2.0);
  Reflector(&scan, 54, 57, 5.0);    // adjacent in bearing, farther away
  Reflector(&scan, 300, 301, 6.0);  // another beacon after invalid readings
  BeaconExtractionOptions o;
  const std::vector<Beacon> beacons = ExtractBeacons(scan, o);
  ASSERT_EQ(beacons.size(), 3u);
  EXPECT_NEAR(beacons[0].range_m, 2.0, 1e-12);
  EXPECT_NEAR(beacons[1].range_m, 5.0, 1e-12);
  EXPECT_EQ(beacons[2].first_index, 300);
  o.min_points = 3;
  EXPECT_EQ(ExtractBeacons(scan, o).size(), 2u);  // the two-reading one is dropped
}

TEST(BeaconExtraction, CartesianCovarianceIsThePolarOnePropagated) {
  Beacon b;
  b.range_m = 2.0;
  b.bearing_rad = kPi / 2;
  b.polar_covariance << 1e-4, 0.0, 0.0, 1e-4;
  const Point2Uncertain p = b.Cartesian();
  EXPECT_NEAR(p.position_m.x(), 0.0, 1e-12);
  EXPECT_NEAR(p.position_m.y(), 2.0, 1e-12);
  EXPECT_NEAR(p.covariance(1, 1), 1e-4, 1e-12);        // range along y
  EXPECT_NEAR(p.covariance(0, 0), 4.0 * 1e-4, 1e-12);  // rho^2 sigma_theta^2 across
}

TEST(BeaconExtraction, OptionsAreValidated) {
  BeaconExtractionOptions o;
  o.range_sigma_m = 0.0;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = {};
  o.min_points = 0;
  EXPECT_THROW(ExtractBeacons(EmptyScan(), o), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::core
