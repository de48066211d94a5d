#include "scenarios/realism/scan_residuals.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iostream>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "scenarios/realism/realism_comparison.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;

// A scan of the straight wall whose normal points at `normal_rad` from the
// sensor, at distance `distance_m`, seen at bearings [first_deg, last_deg] in
// steps of step_deg, with Gaussian range noise of `sigma_m` (0: none).
core::LaserScan WallScan(double distance_m, double normal_rad, double first_deg, double last_deg,
                         double step_deg, double sigma_m, std::mt19937* rng) {
  std::normal_distribution<double> noise(0.0, 1.0);
  core::LaserScan scan;
  scan.max_range_m = 80.0;
  for (double deg = first_deg; deg <= last_deg + 1e-9; deg += step_deg) {
    core::LaserReading r;
    r.bearing_rad = deg * kDegToRad;
    r.range_m = distance_m / std::cos(r.bearing_rad - normal_rad);
    if (sigma_m > 0.0) r.range_m += sigma_m * noise(*rng);
    r.valid = true;
    scan.readings.push_back(r);
  }
  return scan;
}

// The p-quantile m of |e| for e a mixture, with equal weights, of the
// distributions whose |e| has CDF cdf(k, m) for k in [0, count): solves
// mean_k cdf(k, m) = p by bisection on [0, upper_m].
double MixtureQuantile(double p, int count, const std::function<double(int, double)>& cdf,
                       double upper_m) {
  double low = 0.0, high = upper_m;
  for (int iteration = 0; iteration < 100; ++iteration) {
    const double mid = 0.5 * (low + high);
    double mean = 0.0;
    for (int k = 0; k < count; ++k) mean += cdf(k, mid);
    (mean / count < p ? low : high) = mid;
  }
  return 0.5 * (low + high);
}

// Perpendicular scale of each reading of a wall scan: cos(incidence), times
// sqrt((N-2)/N) for the two degrees of freedom of the fitted line.
std::vector<double> NormalFactors(const core::LaserScan& scan, double normal_rad) {
  const double n = static_cast<double>(scan.readings.size());
  std::vector<double> factors;
  for (const core::LaserReading& r : scan.readings) {
    factors.push_back(std::cos(r.bearing_rad - normal_rad) * std::sqrt((n - 2.0) / n));
  }
  return factors;
}

// Median and p90 of the residuals of a wall with Gaussian range noise match
// the half-normal quantiles 0.674σ and 1.645σ (scaled by cos(incidence)).
TEST(ScanResidualsTest, GaussianNoiseGivesHalfNormalQuantiles) {
  constexpr double kSigmaM = 0.005;
  constexpr int kScans = 300;
  std::mt19937 rng(20);
  std::vector<core::LaserScan> scans;
  for (int s = 0; s < kScans; ++s)
    scans.push_back(WallScan(3.0, 0.0, -20, 20, 0.25, kSigmaM, &rng));
  const ScanResidualStatistics stats = ComputeScanResiduals(scans);
  const std::vector<double> factors = NormalFactors(scans.front(), 0.0);
  const int n = static_cast<int>(factors.size());
  const auto cdf = [&](int k, double m) {
    return std::erf(m / (kSigmaM * factors[static_cast<std::size_t>(k)] * std::numbers::sqrt2));
  };
  const double median = MixtureQuantile(0.5, n, cdf, 10 * kSigmaM);
  const double p90 = MixtureQuantile(0.9, n, cdf, 10 * kSigmaM);
  // The geometry hardly changes the textbook values.
  EXPECT_NEAR(median, 0.6745 * kSigmaM, 0.04 * 0.6745 * kSigmaM);
  EXPECT_NEAR(p90, 1.6449 * kSigmaM, 0.04 * 1.6449 * kSigmaM);
  EXPECT_EQ(stats.runs, kScans);
  ASSERT_EQ(stats.bins.size(), 3u);
  const ResidualBin& bin = stats.bins[1];  // ranges 3.0 ... 3.19 m
  EXPECT_EQ(bin.count, static_cast<std::int64_t>(kScans) * n);
  // Monte Carlo: ~48000 correlated-by-fit samples; the median's standard
  // error is ~0.7 %, the p90's ~1 %.
  EXPECT_NEAR(bin.median_abs_m, median, 0.03 * median);
  EXPECT_NEAR(bin.p90_abs_m, p90, 0.03 * p90);
  double mean_square = 0.0;
  for (double f : factors) mean_square += f * f * kSigmaM * kSigmaM / n;
  EXPECT_NEAR(bin.rms_m, std::sqrt(mean_square), 0.03 * std::sqrt(mean_square));
  EXPECT_EQ(stats.all.count, bin.count);
  EXPECT_DOUBLE_EQ(stats.all.median_abs_m, bin.median_abs_m);
}

// Each range bin receives exactly the wall readings of its range; readings
// beyond the last edge are in runs but in no bin.
TEST(ScanResidualsTest, BinsGetTheReadingsOfTheirRange) {
  std::mt19937 rng(7);
  // (distance, half field of view): ranges 1.5-1.96, 3-3.19, 6-6.13, 9-9.09 m.
  const std::vector<std::pair<double, double>> walls = {{1.5, 40}, {3.0, 20}, {6.0, 12}, {9.0, 8}};
  std::vector<core::LaserScan> scans;
  std::vector<std::int64_t> readings;
  for (const auto& [distance_m, half_deg] : walls) {
    scans.push_back(WallScan(distance_m, 0.0, -half_deg, half_deg, 0.25, 0.005, &rng));
    readings.push_back(static_cast<std::int64_t>(scans.back().readings.size()));
  }
  const ScanResidualStatistics stats = ComputeScanResiduals(scans);
  EXPECT_EQ(stats.runs, 4);
  EXPECT_EQ(stats.run_readings, readings[0] + readings[1] + readings[2] + readings[3]);
  ASSERT_EQ(stats.bins.size(), 3u);
  for (std::size_t b = 0; b < 3; ++b) {
    EXPECT_EQ(stats.bins[b].count, readings[b]) << "bin " << b;
    EXPECT_GT(stats.bins[b].median_abs_m, 0.002) << "bin " << b;
    EXPECT_LT(stats.bins[b].median_abs_m, 0.005) << "bin " << b;
  }
  EXPECT_DOUBLE_EQ(stats.bins[2].min_range_m, 4.0);
  EXPECT_DOUBLE_EQ(stats.bins[2].max_range_m, 8.0);
  EXPECT_EQ(stats.all.count, readings[0] + readings[1] + readings[2]);
  EXPECT_EQ(stats.no_returns, 0);
  EXPECT_EQ(stats.isolated, 0);
}

// Requantizing 1 mm-noise ranges to 5 cm makes the residuals uniform
// quantization noise: RMS step/√12, median step/4, p90 0.45 step (times the
// perpendicular factor cos(incidence)).
TEST(ScanResidualsTest, RequantizationGivesUniformQuantizationNoise) {
  constexpr double kStepM = 0.05;
  // An oblique wall 2.3-2.7 m away seen from 10° to 50° off its normal: ranges
  // 2.3-4.2 m, ~30 steps of 5 cm, so the quantization error's phase varies.
  constexpr double kNormalRad = 50.0 * kDegToRad;
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> distance(2.3, 2.7);
  std::vector<core::LaserScan> scans;
  for (int s = 0; s < 300; ++s) {
    scans.push_back(WallScan(distance(rng), kNormalRad, 0, 40, 0.25, 0.001, &rng));
  }
  ScanResidualOptions options;
  // Quantization spreads points ±2.5 cm, the chord's end points too: split
  // only clearly bent runs.
  options.straightness.split_distance_m = 0.08;
  options.bin_edges_m = {0.0, 8.0};
  const ScanResidualStatistics raw = ComputeScanResiduals(scans, options);
  options.requantize_step_m = kStepM;
  const ScanResidualStatistics quantized = ComputeScanResiduals(scans, options);
  EXPECT_EQ(raw.runs, 300);
  EXPECT_EQ(quantized.runs, 300);
  const std::vector<double> factors = NormalFactors(scans.front(), kNormalRad);
  const int n = static_cast<int>(factors.size());
  const auto cdf = [&](int k, double m) {
    return std::min(1.0, 2.0 * m / (kStepM * factors[static_cast<std::size_t>(k)]));
  };
  double mean_square = 0.0;
  for (double f : factors) mean_square += f * f * kStepM * kStepM / 12.0 / n;
  const double median = MixtureQuantile(0.5, n, cdf, kStepM);
  const double p90 = MixtureQuantile(0.9, n, cdf, kStepM);
  std::cout << "quantized: median " << quantized.all.median_abs_m << " (expected " << median
            << "), p90 " << quantized.all.p90_abs_m << " (" << p90 << "), rms "
            << quantized.all.rms_m << " (" << std::sqrt(mean_square) << ")\n";
  // Quantization noise of one wall is a sawtooth in the bearing, so the line
  // fit absorbs a little of it: 10 %.
  EXPECT_NEAR(quantized.all.median_abs_m, median, 0.1 * median);
  EXPECT_NEAR(quantized.all.p90_abs_m, p90, 0.1 * p90);
  EXPECT_NEAR(quantized.all.rms_m, std::sqrt(mean_square), 0.1 * std::sqrt(mean_square));
  // Raw: 1 mm Gaussian noise.
  EXPECT_LT(raw.all.median_abs_m, 0.001);
  EXPECT_GT(raw.all.median_abs_m, 0.0003);
  // The analysed ranges are on the 5 cm grid.
  std::vector<core::LaserScan> prepared;
  for (const core::LaserScan& s : scans) prepared.push_back(PrepareScanForResiduals(s, options));
  EXPECT_DOUBLE_EQ(DetectRangeStep(prepared).step_m, kStepM);
}

// No-return and isolated fractions of a constructed scan, exactly.
TEST(ScanResidualsTest, NoReturnAndIsolatedFractionsOfAConstructedScan) {
  // (range, valid): 2 no-returns, one beyond max_range_m, one rounding to 0.
  const std::vector<std::pair<double, bool>> readings = {
      {2.0, true},    // 0: neighbour 1 within 0.1 m
      {2.1, true},    // 1
      {30.0, false},  // 2: no-return
      {5.0, true},    // 3: isolated (2 invalid, 4 is 3 m nearer)
      {2.0, true},    // 4: neighbour 5 within 0.25 m
      {2.25, true},   // 5
      {12.0, true},   // 6: beyond max_range_m -> no-return
      {3.0, true},    // 7: isolated (6 and 8 no-returns)
      {0.01, true},   // 8: rounds to 0 -> no-return
      {4.0, true},    // 9: isolated (scan edge and 8)
  };
  core::LaserScan scan;
  for (const auto& [range_m, valid] : readings) {
    core::LaserReading r;
    r.range_m = range_m;
    r.valid = valid;
    scan.readings.push_back(r);
  }
  ScanResidualOptions options;
  options.max_range_m = 10.0;
  options.requantize_step_m = 0.05;
  const std::vector<core::LaserScan> scans = {scan, scan};
  const ScanResidualStatistics stats = ComputeScanResiduals(scans, options);
  EXPECT_EQ(stats.scans, 2);
  EXPECT_EQ(stats.readings, 20);
  EXPECT_EQ(stats.no_returns, 6);
  EXPECT_EQ(stats.isolated, 6);
  EXPECT_DOUBLE_EQ(stats.no_return_fraction, 0.3);
  EXPECT_DOUBLE_EQ(stats.isolated_fraction, 0.3);
  EXPECT_EQ(stats.runs, 0);
  EXPECT_EQ(stats.all.count, 0);
  // Reading 5 (2.25 m) is 0.25 m from reading 4: isolated with a 0.2 m jump.
  options.isolated_jump_m = 0.2;
  EXPECT_EQ(ComputeScanResiduals(scans, options).isolated, 10);
}

// Ranges rounded to 1 mm, 1 cm and 5 cm give back that step; unquantized
// ranges give 0; 1 mm ranges stored as 32-bit floats (scans.bin) still 1 mm.
TEST(ScanResidualsTest, DetectRangeStepFindsTheQuantization) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> range(0.3, 30.0);
  const auto scans_with = [&](double step_m, bool as_float) {
    std::vector<core::LaserScan> scans(20);
    for (core::LaserScan& scan : scans) {
      for (int i = 0; i < 181; ++i) {
        core::LaserReading r;
        r.range_m = range(rng);
        if (step_m > 0.0) r.range_m = step_m * std::round(r.range_m / step_m);
        if (as_float) r.range_m = static_cast<float>(r.range_m);
        r.valid = true;
        scan.readings.push_back(r);
      }
      scan.readings.front().valid = false;  // no-returns are not examined
      scan.readings.front().range_m = 0.0123456;
    }
    return scans;
  };
  for (const double step_m : {0.001, 0.01, 0.05}) {
    const RangeStepEstimate estimate = DetectRangeStep(scans_with(step_m, false));
    EXPECT_DOUBLE_EQ(estimate.step_m, step_m);
    EXPECT_DOUBLE_EQ(estimate.on_grid_fraction, 1.0);
    EXPECT_EQ(estimate.valid_readings, 20 * 180);
  }
  EXPECT_DOUBLE_EQ(DetectRangeStep(scans_with(0.001, true)).step_m, 0.001);
  EXPECT_DOUBLE_EQ(DetectRangeStep(scans_with(0.0, false)).step_m, 0.0);
  EXPECT_DOUBLE_EQ(DetectRangeStep(std::vector<core::LaserScan>{}).step_m, 0.0);
}

// Validate() names the offending field.
// Thinning keeps readings 0, k, 2k, ... with their bearings: a 0.5° scan
// becomes a 1° one, and isolated readings are counted at that spacing.
TEST(ScanResidualsTest, ThinningKeepsEveryKthReading) {
  // Nine readings at 2 m; reading 4 at 5 m; readings 3, 5 and 7 no-returns.
  core::LaserScan scan;
  for (int i = 0; i < 9; ++i) {
    core::LaserReading r;
    r.bearing_rad = 0.01 * i;
    r.range_m = i == 4 ? 5.0 : 2.0;
    r.valid = i != 3 && i != 5 && i != 7;
    scan.readings.push_back(r);
  }
  ScanResidualOptions thinned;
  thinned.keep_every = 2;
  const core::LaserScan thin = PrepareScanForResiduals(scan, thinned);
  ASSERT_EQ(thin.readings.size(), 5u);  // readings 0, 2, 4, 6, 8
  for (std::size_t i = 0; i < thin.readings.size(); ++i) {
    EXPECT_DOUBLE_EQ(thin.readings[i].bearing_rad, 0.02 * i);
  }
  const std::vector<core::LaserScan> one = {scan};
  // Full resolution: 4 and 6 (both neighbours invalid) and 8 (7 invalid, the
  // scan's edge) are isolated, 3 of 9. Thinned: 4 alone (neighbours 2 and 6 at
  // 2 m, 3 m away), 1 of 5.
  const ScanResidualStatistics full = ComputeScanResiduals(one, ScanResidualOptions{});
  const ScanResidualStatistics half = ComputeScanResiduals(one, thinned);
  EXPECT_EQ(full.readings, 9);
  EXPECT_NEAR(full.isolated_fraction, 3.0 / 9.0, 1e-12);
  EXPECT_EQ(half.readings, 5);
  EXPECT_NEAR(half.isolated_fraction, 1.0 / 5.0, 1e-12);
  thinned.keep_every = 0;
  EXPECT_THROW(thinned.Validate(), std::invalid_argument);
}

TEST(ScanResidualsTest, ValidateNamesTheField) {
  using pavilion::testing::ValidateMessage;
  ScanResidualOptions options;
  EXPECT_EQ(ValidateMessage(options), "");
  options.requantize_step_m = -0.01;
  EXPECT_TRUE(pavilion::testing::Contains(ValidateMessage(options), "requantize_step_m"));
  options = {};
  options.max_range_m = 0.0;
  EXPECT_TRUE(pavilion::testing::Contains(ValidateMessage(options), "max_range_m"));
  options = {};
  options.isolated_jump_m = -1.0;
  EXPECT_TRUE(pavilion::testing::Contains(ValidateMessage(options), "isolated_jump_m"));
  options = {};
  options.bin_edges_m = {0.0, 4.0, 2.0};
  EXPECT_TRUE(pavilion::testing::Contains(ValidateMessage(options), "bin_edges_m"));
  options = {};
  options.straightness.min_points = 2;
  EXPECT_TRUE(pavilion::testing::Contains(ValidateMessage(options), "min_points"));
}

// What docs/carmen_logs.md ("Residuals of long walls") reports per real log:
// the measured range step and bounds on the 2-4 m median |residual| (the
// measured value, 2026-12-05, within about ±30 %).
struct ExpectedLog {
  double step_m;
  double min_median_2_4_m;
  double max_median_2_4_m;
};
const std::map<std::string, ExpectedLog>& ExpectedLogs() {
  static const std::map<std::string, ExpectedLog> logs = {
      // aces and infinite-corridor print 1 cm values, but on a ~5 cm comb
      // (docs/carmen_logs.md): strict multiples give 1 cm.
      {"intel", {0.01, 0.003, 0.0055}},    {"aces", {0.01, 0.006, 0.011}},
      {"csail", {0.01, 0.004, 0.0075}},    {"freiburg-101", {0.01, 0.0035, 0.0065}},
      {"orebro", {0.001, 0.0023, 0.0045}}, {"infinite-corridor", {0.01, 0.0055, 0.0105}},
  };
  return logs;
}

// The six real logs: their range steps, and finite, plausible statistics.
TEST(ScanResidualsRealLogsTest, RangeStepsAndPlausibleResiduals) {
  const std::string dir = pavilion::testing::CarmenDataDir();
  if (dir.empty()) GTEST_SKIP() << "no CARMEN logs (set PAVILION_CARMEN_DIR)";
  std::vector<LogStatistics> real;
  for (const auto& [name, expected] : ExpectedLogs()) {
    const LogStatistics log = LoadCarmenLogStatistics(dir + "/" + name + "-corrected.log.gz");
    EXPECT_EQ(log.name, name);
    EXPECT_DOUBLE_EQ(log.range_step.step_m, expected.step_m) << name;
    EXPECT_GE(log.range_step.on_grid_fraction, kRangeStepMinOnGridFraction) << name;
    const ScanResidualStatistics& s = log.residuals;
    EXPECT_GT(s.no_return_fraction, 0.0) << name;
    EXPECT_LT(s.no_return_fraction, 0.5) << name;
    EXPECT_GE(s.isolated_fraction, 0.0) << name;
    EXPECT_LT(s.isolated_fraction, 0.15) << name;
    EXPECT_GT(s.runs, 50) << name;
    for (const ResidualBin& bin : s.bins) {
      EXPECT_TRUE(std::isfinite(bin.median_abs_m) && std::isfinite(bin.p90_abs_m)) << name;
      EXPECT_LE(bin.median_abs_m, bin.p90_abs_m) << name;
      EXPECT_LT(bin.p90_abs_m, 0.05) << name;  // runs are straight within 5 cm
    }
    EXPECT_GT(s.bins[1].count, 1000) << name;
    EXPECT_GE(s.bins[1].median_abs_m, expected.min_median_2_4_m) << name;
    EXPECT_LE(s.bins[1].median_abs_m, expected.max_median_2_4_m) << name;
    real.push_back(log);
  }
  std::cout << FormatRealismReport(CompareResiduals(real, {}));
}

}  // namespace
}  // namespace pavilion::scenarios
