// SeriesDecimator: exact while small, bounded however long, extremes kept,
// deterministic, and strict about its input.

#include "scenarios/output/series_decimator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace pavilion::scenarios {
namespace {

// Up to max_points samples come back unchanged, in order.
TEST(SeriesDecimatorTest, ExactWhileUnderTheBudget) {
  SeriesDecimator d(100);
  for (int i = 0; i < 100; ++i) d.Add(0.1 * i, std::sin(i));
  ASSERT_TRUE(d.exact());
  const std::vector<SeriesPoint> p = d.points();
  ASSERT_EQ(p.size(), 100u);
  for (int i = 0; i < 100; ++i) {
    EXPECT_EQ(p[i].t, 0.1 * i);
    EXPECT_EQ(p[i].value, std::sin(i));
  }
  EXPECT_EQ(d.samples(), 100);
}

// A million samples leave at most max_points points, in time order, within
// the series' span, with its first and last sample.
TEST(SeriesDecimatorTest, BoundedForAnyNumberOfSamples) {
  for (const std::size_t n :
       {std::size_t{4}, std::size_t{7}, std::size_t{100}, std::size_t{5000}}) {
    SeriesDecimator d(n);
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, 1.0);
    const int samples = 1000000;
    for (int i = 0; i < samples; ++i) {
      d.Add(0.005 * i, noise(rng));
      if (i % 997 == 0) {
        ASSERT_LE(d.points().size(), d.max_points()) << "after " << i;
      }
    }
    const std::vector<SeriesPoint> p = d.points();
    EXPECT_LE(p.size(), d.max_points());
    EXPECT_FALSE(d.exact());
    EXPECT_TRUE(std::is_sorted(
        p.begin(), p.end(), [](const SeriesPoint& a, const SeriesPoint& b) { return a.t < b.t; }));
    EXPECT_EQ(p.front().t, 0.0);
  }
}

// A single spike in a long flat series survives, and so do the series'
// minimum and maximum.
TEST(SeriesDecimatorTest, KeepsSpikesAndExtremes) {
  SeriesDecimator d(200);
  const int samples = 2000000;
  double lowest = 1e9;
  double highest = -1e9;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(0.0, 0.01);
  for (int i = 0; i < samples; ++i) {
    double v = 0.02 + jitter(rng);
    if (i == 1234567) v = 5.0;  // one cycle's error spike
    if (i == 777) v = -1.0;     // and one dip
    lowest = std::min(lowest, v);
    highest = std::max(highest, v);
    d.Add(0.5 * i, v);
  }
  const std::vector<SeriesPoint> p = d.points();
  ASSERT_LE(p.size(), 200u);
  const auto [lo, hi] = std::minmax_element(
      p.begin(), p.end(),
      [](const SeriesPoint& a, const SeriesPoint& b) { return a.value < b.value; });
  EXPECT_EQ(lo->value, lowest);
  EXPECT_EQ(lo->t, 0.5 * 777);
  EXPECT_EQ(hi->value, highest);
  EXPECT_EQ(hi->t, 0.5 * 1234567);
  EXPECT_EQ(p.back().t, 0.5 * (samples - 1));  // the series' end stays on the axis
}

// The same samples give the same points; the points are samples.
TEST(SeriesDecimatorTest, Deterministic) {
  SeriesDecimator a(50);
  SeriesDecimator b(50);
  for (int i = 0; i < 100000; ++i) {
    const double v = std::fmod(i * 0.618033988749, 1.0);
    a.Add(i * 0.01, v);
    b.Add(i * 0.01, v);
  }
  const std::vector<SeriesPoint> pa = a.points();
  const std::vector<SeriesPoint> pb = b.points();
  ASSERT_EQ(pa.size(), pb.size());
  for (std::size_t k = 0; k < pa.size(); ++k) {
    EXPECT_EQ(pa[k].t, pb[k].t);
    EXPECT_EQ(pa[k].value, pb[k].value);
    const int i = static_cast<int>(std::lround(pa[k].t / 0.01));
    EXPECT_EQ(pa[k].value, std::fmod(i * 0.618033988749, 1.0));
  }
}

// Samples at one time and bursts after long gaps stay bounded and keep the
// extremes.
TEST(SeriesDecimatorTest, RepeatedTimesAndGaps) {
  SeriesDecimator d(10);
  for (int i = 0; i < 1000; ++i) d.Add(0.0, i % 17);
  for (int i = 0; i < 1000; ++i) d.Add(1e6 + i, -i);
  const std::vector<SeriesPoint> p = d.points();
  EXPECT_LE(p.size(), 10u);
  const auto [lo, hi] = std::minmax_element(
      p.begin(), p.end(),
      [](const SeriesPoint& a, const SeriesPoint& b) { return a.value < b.value; });
  EXPECT_EQ(lo->value, -999.0);
  EXPECT_EQ(hi->value, 16.0);
}

// Time going backwards or a non-finite sample is refused.
TEST(SeriesDecimatorTest, RefusesBadSamples) {
  SeriesDecimator d(10);
  d.Add(1.0, 0.0);
  EXPECT_THROW(d.Add(0.5, 0.0), std::invalid_argument);
  EXPECT_THROW(d.Add(2.0, std::nan("")), std::invalid_argument);
  EXPECT_THROW(d.Add(INFINITY, 0.0), std::invalid_argument);
  EXPECT_NO_THROW(d.Add(1.0, 3.0));  // equal times are fine
  EXPECT_EQ(d.samples(), 2);
}

}  // namespace
}  // namespace pavilion::scenarios
