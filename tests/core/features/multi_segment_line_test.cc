#include "core/features/multi_segment_line.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <vector>

#include "core/features/line_fit.h"
#include "core/random/random_stream.h"
#include "core/types/pose2.h"

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

Line MakeLine(double alpha, double r, double sa, double sr, double rho = 0.0) {
  Line line;
  line.alpha_rad = alpha;
  line.r_m = r;
  line.covariance << sa * sa, rho * sa * sr, rho * sa * sr, sr * sr;
  return line;
}

Segment SegmentOn(const Line& line, double first_bearing, double last_bearing) {
  const int first = static_cast<int>(std::lround(first_bearing / (0.5 * kDeg))) + 360;
  const int last = static_cast<int>(std::lround(last_bearing / (0.5 * kDeg))) + 360;
  return MakeSegment(line, first_bearing, last_bearing, 0.0, last - first + 1, first, last);
}

bool IsPositiveSemidefinite(const Eigen::Matrix2d& m) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(m);
  return solver.eigenvalues().minCoeff() >= -1e-15;
}

// A wall x = 3 interrupted by a door: the two segments' lines pass the chi^2
// test (3.16) and form one MS-line (5.17) whose information-filter covariance
// (3.14) is smaller than each member's.
TEST(MultiSegmentLineTest, CollinearSegmentsWithGapFormOneMsLine) {
  const Line a = MakeLine(0.004, 3.01, 0.01, 0.01, 0.3);
  const Line b = MakeLine(-0.003, 2.995, 0.008, 0.012, -0.2);
  const std::vector<Segment> segments = {SegmentOn(a, -33 * kDeg, -10 * kDeg),
                                         SegmentOn(b, 10 * kDeg, 33 * kDeg)};
  ASSERT_LT(LineMahalanobis2(a, b), -2.0 * std::log(1.0 - 0.99));
  const auto ms = GroupMultiSegmentLines(segments);
  ASSERT_EQ(ms.size(), 1u);
  ASSERT_EQ(ms[0].segments.size(), 2u);
  EXPECT_EQ(ms[0].segment_indices, (std::vector<int>{0, 1}));
  const Eigen::Matrix2d c = ms[0].line.covariance;
  EXPECT_LT(c.determinant(), a.covariance.determinant());
  EXPECT_LT(c.determinant(), b.covariance.determinant());
  EXPECT_LT(c(0, 0), a.covariance(0, 0));
  EXPECT_LT(c(0, 0), b.covariance(0, 0));
  EXPECT_LT(c(1, 1), a.covariance(1, 1));
  EXPECT_LT(c(1, 1), b.covariance(1, 1));
  EXPECT_TRUE(IsPositiveSemidefinite(a.covariance - c));
  EXPECT_TRUE(IsPositiveSemidefinite(b.covariance - c));
  // Eq. 3.13 by hand.
  const Eigen::Matrix2d ia = a.covariance.inverse();
  const Eigen::Matrix2d ib = b.covariance.inverse();
  const Eigen::Matrix2d cw = (ia + ib).inverse();
  const Eigen::Vector2d xw =
      cw * (ia * Eigen::Vector2d(a.alpha_rad, a.r_m) + ib * Eigen::Vector2d(b.alpha_rad, b.r_m));
  EXPECT_NEAR(ms[0].line.alpha_rad, xw(0), 1e-12);
  EXPECT_NEAR(ms[0].line.r_m, xw(1), 1e-12);
  EXPECT_TRUE(ms[0].line.covariance.isApprox(cw, 1e-12));
}

TEST(MultiSegmentLineTest, NonCollinearSegmentsStaySeparate) {
  // Two parallel walls 0.3 m apart (a depth step) and a perpendicular wall.
  const Line a = MakeLine(0.0, 3.0, 0.01, 0.01);
  const Line b = MakeLine(0.0, 3.3, 0.01, 0.01);
  const Line c = MakeLine(kPi / 2, 2.0, 0.01, 0.01);
  const std::vector<Segment> segments = {SegmentOn(a, -30 * kDeg, -10 * kDeg),
                                         SegmentOn(b, 10 * kDeg, 25 * kDeg),
                                         SegmentOn(c, 40 * kDeg, 120 * kDeg)};
  const auto ms = GroupMultiSegmentLines(segments);
  ASSERT_EQ(ms.size(), 3u);
  for (const auto& m : ms) EXPECT_EQ(m.segments.size(), 1u);
  MultiSegmentLineOptions only_multi;
  only_multi.min_segments = 2;
  EXPECT_TRUE(GroupMultiSegmentLines(segments, only_multi).empty());
}

// Collinear segments separated by another one (a wall behind a pillar) still
// form one MS-line; the pillar stays alone.
TEST(MultiSegmentLineTest, NonAdjacentCollinearSegmentsAreGrouped) {
  const Line wall = MakeLine(0.0, 4.0, 0.01, 0.01);
  const Line pillar = MakeLine(0.05, 2.0, 0.02, 0.01);
  const std::vector<Segment> segments = {SegmentOn(wall, -40 * kDeg, -5 * kDeg),
                                         SegmentOn(pillar, -3 * kDeg, 3 * kDeg),
                                         SegmentOn(wall, 5 * kDeg, 40 * kDeg)};
  const auto ms = GroupMultiSegmentLines(segments);
  ASSERT_EQ(ms.size(), 2u);
  EXPECT_EQ(ms[0].segment_indices, (std::vector<int>{0, 2}));
  EXPECT_EQ(ms[1].segment_indices, (std::vector<int>{1}));
  EXPECT_NEAR(ms[0].line.covariance(0, 0), 0.5 * 0.01 * 0.01, 1e-12);
}

// Angles on both sides of +-pi are fused without wrap-around bias.
TEST(MultiSegmentLineTest, FusionAcrossAngleWrap) {
  const Line a = MakeLine(kPi - 0.002, 2.0, 0.01, 0.01);
  const Line b = MakeLine(-kPi + 0.002, 2.0, 0.01, 0.01);
  const Line fused = FuseLines({a, b});
  EXPECT_NEAR(std::abs(NormalizeAngle(fused.alpha_rad - kPi)), 0.0, 1e-12);
  EXPECT_NEAR(fused.r_m, 2.0, 1e-12);
  EXPECT_LT(LineMahalanobis2(a, b), 1.0);
}

// Monte-Carlo check of the fused covariance: 2000 scans of a wall with a door,
// each piece fitted (3.4-3.10) and the two lines fused (3.13-3.14); the
// empirical sigmas of the fused (alpha, r) match the predicted ones within 10%.
TEST(MultiSegmentLineTest, FusedCovarianceMatchesMonteCarlo) {
  RandomStream rng(5, 17);
  constexpr double kSigma = 0.01;
  constexpr int kDraws = 2000;
  const double alpha_true = 10 * kDeg;
  const double r_true = 3.0;
  std::vector<Eigen::Vector2d> samples;
  Eigen::Matrix2d predicted = Eigen::Matrix2d::Zero();
  int grouped = 0;
  for (int draw = 0; draw < kDraws; ++draw) {
    std::vector<Segment> segments;
    for (const auto& [lo, hi] : {std::pair{-30.0, -8.0}, std::pair{12.0, 35.0}}) {
      std::vector<PolarPoint> points;
      for (double b = lo; b <= hi + 1e-9; b += 0.5) {
        const double theta = b * kDeg;
        const double rho = r_true / std::cos(theta - alpha_true) + rng.Normal(0.0, kSigma);
        points.push_back({rho, theta, kSigma});
      }
      const auto line = FitLine(points);
      ASSERT_TRUE(line.has_value());
      segments.push_back(SegmentOn(*line, lo * kDeg, hi * kDeg));
    }
    // At alpha = 0.99 about 1% of the pairs fail the chi^2 test by chance.
    if (GroupMultiSegmentLines(segments).size() == 1u) ++grouped;
    const Line fused = FuseLines({segments[0].line, segments[1].line});
    samples.emplace_back(NormalizeAngle(fused.alpha_rad - alpha_true), fused.r_m);
    predicted += fused.covariance / kDraws;
  }
  EXPECT_GE(grouped, 0.97 * kDraws);
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& s : samples) mean += s / kDraws;
  Eigen::Matrix2d empirical = Eigen::Matrix2d::Zero();
  for (const auto& s : samples) empirical += (s - mean) * (s - mean).transpose() / (kDraws - 1);
  EXPECT_NEAR(std::sqrt(empirical(0, 0)) / std::sqrt(predicted(0, 0)), 1.0, 0.10);
  EXPECT_NEAR(std::sqrt(empirical(1, 1)) / std::sqrt(predicted(1, 1)), 1.0, 0.10);
  const double rho_emp = empirical(0, 1) / std::sqrt(empirical(0, 0) * empirical(1, 1));
  const double rho_pred = predicted(0, 1) / std::sqrt(predicted(0, 0) * predicted(1, 1));
  EXPECT_NEAR(rho_emp, rho_pred, 0.1);
  EXPECT_NEAR(mean(0), 0.0, 4 * std::sqrt(predicted(0, 0) / kDraws) + 1e-4);
}

TEST(MultiSegmentLineTest, OptionsValidate) {
  MultiSegmentLineOptions o;
  o.significance = 1.0;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  o = {};
  o.min_segments = 0;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  EXPECT_THROW(FuseLines({}), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::core
