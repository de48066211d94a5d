// The laser's systematic and correlated errors (sim::LaserSystematicErrors,
// issue 20): each has the statistics it claims, and turning one on changes
// what it should and nothing else (every other draw stays as it was).
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numeric>
#include <string>
#include <vector>

#include "sim/sensors/laser_scanner.h"

namespace pavilion::sim {
namespace {

using core::LaserResponse;
using core::Pose2;

constexpr double kMountHeightM = 0.3;
constexpr std::uint64_t kSeed = 77;

// A 10 m x 6 m room whose four walls are separate elements (inner faces
// x = 0.05, x = 9.95, y = 0.05, y = 5.95), and a dark panel.
WorldDescription FourWallRoom() {
  WorldDescription w;
  w.name = "systematic_test";
  Material paint;
  w.materials["paint"] = paint;
  Material velvet;
  velvet.laser = LaserResponse::kDark;
  w.materials["velvet"] = velvet;
  w.floor = {{-5, -5}, {15, 11}, "paint", {}};
  const auto wall = [&](const std::string& id, Eigen::Vector2d a, Eigen::Vector2d b,
                        const std::string& material) {
    Wall x;
    x.id = id;
    x.points_m = {a, b};
    x.thickness_m = 0.1;
    x.height_m = 2.0;
    x.material = material;
    w.walls.push_back(x);
  };
  wall("south", {-0.5, 0.0}, {10.5, 0.0}, "paint");
  wall("east", {10.0, -0.5}, {10.0, 6.5}, "paint");
  wall("north", {10.5, 6.0}, {-0.5, 6.0}, "paint");
  wall("west", {0.0, 6.5}, {0.0, -0.5}, "paint");
  return w;
}

// The LMS 200 without quantization (differences are exact) and without mixed
// pixels (a reading at a corner would mix two walls' biases).
LaserScannerOptions Lms200() {
  LaserScannerOptions o = LaserScannerOptions::Profile("sick_lms200");
  o.range_resolution_m = 0.0;
  o.beam_divergence_rad = 0.0;
  return o;
}

LaserScanner Scanner(const LaserScannerOptions& o, Pose2 mount = {}) {
  return LaserScanner("laser", o, mount, kMountHeightM, core::RandomStream(kSeed, 1));
}

const Pose2 kRobot{4.0, 2.5, 0.3};

struct Shot {
  core::LaserScan scan;
  core::LaserScanTruth truth;
};
Shot ScanOnce(LaserScanner* scanner, const World& world, const Pose2& robot, double t_s) {
  Shot s;
  s.scan = scanner->ScanFrom(world, robot, t_s, -1, &s.truth);
  return s;
}

// Each element reads long or short by one bias, the same in every scan and
// from every pose; over many seeds the biases have the configured sigma.
TEST(LaserSystematicTest, SurfaceBiasRepeatsFromScanToScan) {
  World world(FourWallRoom(), {});
  LaserScannerOptions o = Lms200();
  o.noise = false;
  o.systematic.surface_bias_sigma_m = 0.005;
  o.systematic.surface_seed = 11;
  LaserScanner scanner = Scanner(o);
  std::map<int, double> bias;
  for (const Pose2& robot : {kRobot, Pose2{7.0, 4.0, 2.0}, Pose2{2.0, 1.5, -1.0}}) {
    const Shot s = ScanOnce(&scanner, world, robot, 0.0);
    for (std::size_t i = 0; i < s.scan.readings.size(); ++i) {
      if (!s.scan.readings[i].valid) continue;
      const double error = s.scan.readings[i].range_m - s.truth.true_range_m[i];
      const auto [it, added] = bias.try_emplace(s.truth.element[i], error);
      EXPECT_NEAR(error, it->second, 1e-9) << "reading " << i;
    }
  }
  ASSERT_EQ(bias.size(), 4u);  // the four walls, each its own bias
  EXPECT_NE(bias.begin()->second, std::next(bias.begin())->second);

  // Across seeds: sample sigma of 2000 draws within 5 % (its standard error is 1.6 %).
  double sum2 = 0.0;
  int n = 0;
  for (std::uint64_t seed = 1; seed <= 500; ++seed) {
    o.systematic.surface_seed = seed;
    LaserScanner draw = Scanner(o);
    const Shot s = ScanOnce(&draw, world, kRobot, 0.0);
    std::map<int, double> per_element;
    for (std::size_t i = 0; i < s.scan.readings.size(); ++i) {
      if (s.scan.readings[i].valid) {
        per_element[s.truth.element[i]] = s.scan.readings[i].range_m - s.truth.true_range_m[i];
      }
    }
    for (const auto& [element, b] : per_element) {
      sum2 += b * b;
      ++n;
    }
  }
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.005, 0.05 * 0.005) << n << " biases";
}

// The correlated noise is a stationary AR(1) process along the readings:
// sigma as configured, correlation exp(-k / length) at lag k.
TEST(LaserSystematicTest, CorrelatedNoiseHasItsSigmaAndCorrelationLength) {
  World world(FourWallRoom(), {});
  LaserScannerOptions o = Lms200();
  o.range_sigma_m = 0.0;  // white noise off: the errors are the correlated process alone
  o.systematic.correlated_sigma_m = 0.004;
  o.systematic.correlation_readings = 4.0;
  o.systematic.seed = 5;
  LaserScanner scanner = Scanner(o);
  std::vector<double> lag_sum(9, 0.0);
  std::vector<int> lag_n(9, 0);
  for (int k = 0; k < 300; ++k) {
    const Shot s = ScanOnce(&scanner, world, kRobot, 0.1 * k);
    std::vector<double> e(s.scan.readings.size());
    for (std::size_t i = 0; i < e.size(); ++i) {
      ASSERT_TRUE(s.scan.readings[i].valid);  // a closed room: every reading returns
      e[i] = s.scan.readings[i].range_m - s.truth.true_range_m[i];
    }
    for (int lag = 0; lag <= 8; ++lag) {
      for (std::size_t i = 0; i + lag < e.size(); ++i) {
        lag_sum[lag] += e[i] * e[i + lag];
        ++lag_n[lag];
      }
    }
  }
  const double variance = lag_sum[0] / lag_n[0];
  EXPECT_NEAR(std::sqrt(variance), 0.004, 0.04 * 0.004);
  for (int lag : {1, 4, 8}) {
    const double rho = lag_sum[lag] / lag_n[lag] / variance;
    EXPECT_NEAR(rho, std::exp(-lag / 4.0), 0.05) << "lag " << lag;
  }
}

// The rays leave from the true mount (file mount composed with the error);
// the scan reports the file's mount.
TEST(LaserSystematicTest, MountErrorMovesTheRaysNotTheReportedMount) {
  World world(FourWallRoom(), {});
  const Pose2 file_mount{0.15, 0.05, 0.0};
  const Pose2 error{0.004, -0.003, 0.002};
  LaserScannerOptions o = Lms200();
  o.noise = false;
  o.systematic.mount_error = error;
  LaserScanner scanner = Scanner(o, file_mount);
  const Shot s = ScanOnce(&scanner, world, kRobot, 0.0);
  EXPECT_EQ(s.scan.robot_from_sensor.x_m, file_mount.x_m);
  EXPECT_EQ(s.scan.robot_from_sensor.theta_rad, file_mount.theta_rad);
  const Pose2 truth = kRobot * file_mount * error;
  EXPECT_NEAR(s.truth.world_from_sensor[0].x_m, truth.x_m, 1e-12);
  EXPECT_NEAR(s.truth.world_from_sensor[0].theta_rad, truth.theta_rad, 1e-12);
  // The beam straight ahead meets the east wall's face at x = 9.95 from the true pose.
  LaserScannerOptions ahead = o;
  ahead.fov_rad = 0.02;
  ahead.beams = 3;
  ahead.first_bearing_rad = -0.01;
  ahead.sweep_s = 0.0;
  ahead.interlaced_turns = 1;
  LaserScanner straight = Scanner(ahead, file_mount);
  const Pose2 facing_east{4.0, 2.5, 0.0};
  const Shot e = ScanOnce(&straight, world, facing_east, 0.0);
  const Pose2 sensor = facing_east * file_mount * error;
  EXPECT_NEAR(e.scan.readings[1].range_m, (9.95 - sensor.x_m) / std::cos(sensor.theta_rad), 1e-6);
}

// Weak returns read long: nothing at the white target's amplitude, the whole
// bias three decades below it.
TEST(LaserSystematicTest, IntensityBiasGrowsAsTheReturnWeakens) {
  World world(FourWallRoom(), {});
  LaserScannerOptions o = Lms200();
  o.noise = false;
  o.beam_divergence_rad = 0.0;
  o.systematic.intensity_bias_m = 0.03;
  LaserScanner biased = Scanner(o);
  LaserScannerOptions plain = o;
  plain.systematic.intensity_bias_m = 0.0;
  LaserScanner ideal = Scanner(plain);
  const Pose2 robot{4.0, 2.5, 0.0};
  const Shot b = ScanOnce(&biased, world, robot, 0.0);
  const Shot i = ScanOnce(&ideal, world, robot, 0.0);
  for (std::size_t k = 0; k < b.scan.readings.size(); k += 17) {
    ASSERT_TRUE(b.scan.readings[k].valid);
    const double r = i.truth.true_range_m[k];
    // The incidence from the geometry: the reading's own beam against the wall met.
    const double a_expected = b.scan.readings[k].range_m - i.scan.readings[k].range_m;
    EXPECT_GE(a_expected, 0.0);
    EXPECT_LE(a_expected, 0.03 + 1e-12);
    if (std::abs(b.scan.readings[k].bearing_rad) < 1e-9) {
      // Head-on at 5.95 m: amplitude (2 / 5.95)^2, bias 0.03 * log10((5.95/2)^2) / 3.
      EXPECT_NEAR(a_expected, 0.03 * std::log10(std::pow(r / 2.0, 2)) / 3.0, 1e-9);
    }
  }
}

// Weak returns are noisier: the white σ and intensity_sigma_m times the same
// amplitude law as the bias, in quadrature. The draws are the plain scan's, so
// each reading's error is the plain one's scaled by exactly that ratio; over
// many scans the head-on reading at 5.95 m has the σ it claims.
TEST(LaserSystematicTest, IntensityNoiseGrowsAsTheReturnWeakens) {
  World world(FourWallRoom(), {});
  LaserScannerOptions plain = Lms200();  // white noise on, σ 1 cm
  LaserScannerOptions o = plain;
  o.systematic.intensity_sigma_m = 0.03;
  LaserScanner noisy = Scanner(o);
  LaserScanner reference = Scanner(plain);
  const Pose2 facing_east{4.0, 2.5, 0.0};
  // Head-on at 5.95 m: amplitude (2 / 5.95)^2, weakness log10((5.95 / 2)^2) / 3.
  const double weakness = std::log10(std::pow(5.95 / 2.0, 2)) / 3.0;
  const double sigma = std::hypot(plain.range_sigma_m, 0.03 * weakness);
  double sum2 = 0.0;
  constexpr int kScans = 800;
  for (int scan = 0; scan < kScans; ++scan) {
    const Shot n = ScanOnce(&noisy, world, facing_east, 0.05 * scan);
    const Shot r = ScanOnce(&reference, world, facing_east, 0.05 * scan);
    EXPECT_EQ(n.scan.stamp_s, r.scan.stamp_s);
    for (std::size_t k = 0; k < n.scan.readings.size(); ++k) {
      ASSERT_EQ(n.scan.readings[k].valid, r.scan.readings[k].valid);
      if (!n.scan.readings[k].valid) continue;
      const double truth = n.truth.true_range_m[k];
      const double e_noisy = n.scan.readings[k].range_m - truth;
      const double e_plain = r.scan.readings[k].range_m - truth;
      // Never less noise; the same sign as the plain draw.
      EXPECT_GE(std::abs(e_noisy), std::abs(e_plain) - 1e-12);
      EXPECT_GE(e_noisy * e_plain, 0.0);
      if (std::abs(n.scan.readings[k].bearing_rad) < 1e-9) {
        EXPECT_NEAR(e_noisy, e_plain * sigma / plain.range_sigma_m, 1e-9);
        sum2 += e_noisy * e_noisy;
      }
    }
  }
  // Sample σ of 800 draws within 8 % (its standard error is 2.5 %).
  EXPECT_NEAR(std::sqrt(sum2 / kScans), sigma, 0.08 * sigma);
}

// Turning an error on changes only what it should: the white noise draws
// stay the same, so the difference is the error itself.
TEST(LaserSystematicTest, EachErrorChangesOnlyWhatItShould) {
  World world(FourWallRoom(), {});
  const LaserScannerOptions base = Lms200();  // white noise on
  LaserScanner ideal = Scanner(base);
  const Shot reference = ScanOnce(&ideal, world, kRobot, 0.5);

  LaserScannerOptions with_bias = base;
  with_bias.systematic.surface_bias_sigma_m = 0.01;
  with_bias.systematic.surface_seed = 3;
  LaserScanner biased = Scanner(with_bias);
  const Shot b = ScanOnce(&biased, world, kRobot, 0.5);
  std::map<int, double> offsets;
  for (std::size_t i = 0; i < b.scan.readings.size(); ++i) {
    const double d = b.scan.readings[i].range_m - reference.scan.readings[i].range_m;
    const auto [it, added] = offsets.try_emplace(b.truth.element[i], d);
    EXPECT_NEAR(d, it->second, 1e-9);
  }
  EXPECT_EQ(b.scan.stamp_s, reference.scan.stamp_s);

  LaserScannerOptions with_jitter = base;
  with_jitter.systematic.stamp_jitter_s = 0.001;
  with_jitter.systematic.seed = 9;
  LaserScanner jittered = Scanner(with_jitter);
  const Shot j = ScanOnce(&jittered, world, kRobot, 0.5);
  for (std::size_t i = 0; i < j.scan.readings.size(); ++i) {
    EXPECT_EQ(j.scan.readings[i].range_m, reference.scan.readings[i].range_m);
  }
  EXPECT_NE(j.scan.stamp_s, reference.scan.stamp_s);
  EXPECT_NEAR(j.scan.stamp_s, reference.scan.stamp_s, 0.005);

  LaserScannerOptions with_correlated = base;
  with_correlated.systematic.correlated_sigma_m = 0.004;
  with_correlated.systematic.seed = 9;
  LaserScanner correlated = Scanner(with_correlated);
  const Shot c = ScanOnce(&correlated, world, kRobot, 0.5);
  double max_step = 0.0, max_diff = 0.0;
  for (std::size_t i = 1; i < c.scan.readings.size(); ++i) {
    const double d0 = c.scan.readings[i - 1].range_m - reference.scan.readings[i - 1].range_m;
    const double d1 = c.scan.readings[i].range_m - reference.scan.readings[i].range_m;
    max_step = std::max(max_step, std::abs(d1 - d0));
    max_diff = std::max(max_diff, std::abs(d1));
  }
  EXPECT_GT(max_diff, 0.004);  // the process is there ...
  EXPECT_LT(max_step, 0.02);   // ... and smooth: innovations of 4 mm * sqrt(1 - e^-2) ≈ 3.7 mm
}

TEST(LaserSystematicTest, ValidateNamesTheField) {
  LaserScannerOptions o = Lms200();
  o.systematic.correlation_readings = 0.0;
  try {
    o.Validate();
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("correlation_readings"), std::string::npos);
  }
  o = Lms200();
  o.systematic.mount_error = Pose2{0.2, 0.0, 0.0};
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = Lms200();
  o.systematic.intensity_sigma_m = -0.01;
  try {
    o.Validate();
    FAIL() << "expected an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("intensity_sigma_m"), std::string::npos);
  }
}

}  // namespace
}  // namespace pavilion::sim
