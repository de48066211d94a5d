#include "core/random/random_stream.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

namespace pavilion::core {
namespace {

// The same seed and stream id give the same sequence; other ids or seeds do not.
TEST(RandomStreamTest, StreamsAreReproducibleAndDistinct) {
  RandomStream a(42, 7), b(42, 7), c(42, 8), d(43, 7);
  int same_c = 0, same_d = 0;
  for (int i = 0; i < 1000; ++i) {
    const auto x = a.NextU64();
    EXPECT_EQ(x, b.NextU64());
    same_c += x == c.NextU64();
    same_d += x == d.NextU64();
  }
  EXPECT_EQ(same_c, 0);
  EXPECT_EQ(same_d, 0);
}

// Uniform draws pass a chi-square test over 20 equal bins (p > 0.001).
TEST(RandomStreamTest, UniformPassesChiSquare) {
  RandomStream rng(3, 1);
  constexpr int kBins = 20, kDraws = 200000;
  std::array<int, kBins> counts{};
  for (int i = 0; i < kDraws; ++i) {
    const double u = rng.Uniform();
    ASSERT_GE(u, 0.0);
    ASSERT_LT(u, 1.0);
    ++counts[static_cast<int>(u * kBins)];
  }
  double chi2 = 0.0;
  const double expected = static_cast<double>(kDraws) / kBins;
  for (int c : counts) chi2 += (c - expected) * (c - expected) / expected;
  EXPECT_LT(chi2, 43.82);  // chi-square(19) 99.9% quantile
}

// Normal draws have the requested mean and standard deviation, and the normal
// fraction within ±1σ and ±2σ, to within 5 standard errors.
TEST(RandomStreamTest, NormalMatchesMomentsAndQuantiles) {
  RandomStream rng(4, 1);
  constexpr int kDraws = 200000;
  constexpr double kMean = 1.5, kSigma = 0.3;
  double sum = 0.0, sum_sq = 0.0;
  int within1 = 0, within2 = 0;
  for (int i = 0; i < kDraws; ++i) {
    const double x = rng.Normal(kMean, kSigma);
    sum += x;
    sum_sq += x * x;
    within1 += std::abs(x - kMean) < kSigma;
    within2 += std::abs(x - kMean) < 2 * kSigma;
  }
  const double mean = sum / kDraws;
  const double var = sum_sq / kDraws - mean * mean;
  EXPECT_NEAR(mean, kMean, 5 * kSigma / std::sqrt(kDraws));
  // Var of the sample variance of a normal is 2σ⁴/n.
  EXPECT_NEAR(var, kSigma * kSigma, 5 * std::sqrt(2.0 / kDraws) * kSigma * kSigma);
  const double p1 = 0.682689492, p2 = 0.954499736;
  EXPECT_NEAR(within1 / double(kDraws), p1, 5 * std::sqrt(p1 * (1 - p1) / kDraws));
  EXPECT_NEAR(within2 / double(kDraws), p2, 5 * std::sqrt(p2 * (1 - p2) / kDraws));
}

// Integer draws cover the inclusive range evenly.
TEST(RandomStreamTest, UniformIntCoversInclusiveRange) {
  RandomStream rng(5, 1);
  std::array<int, 6> counts{};
  for (int i = 0; i < 60000; ++i) {
    const auto k = rng.UniformInt(10, 15);
    ASSERT_GE(k, 10);
    ASSERT_LE(k, 15);
    ++counts[k - 10];
  }
  for (int c : counts) EXPECT_NEAR(c, 10000, 5 * std::sqrt(10000 * 5.0 / 6.0));
}

// Stream ids from names are stable (FNV-1a) and differ for different names.
TEST(RandomStreamTest, StreamIdFromNameIsStable) {
  EXPECT_EQ(RandomStream::StreamId(""), 0xCBF29CE484222325ULL);
  EXPECT_EQ(RandomStream::StreamId("a"), 0xAF63DC4C8601EC8CULL);
  EXPECT_NE(RandomStream::StreamId("visitor_000"), RandomStream::StreamId("visitor_001"));
}

}  // namespace
}  // namespace pavilion::core
