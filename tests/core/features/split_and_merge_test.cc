#include "core/features/split_and_merge.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/features/line_fit.h"
#include "core/random/random_stream.h"
#include "tests/support/synthetic_room.h"

namespace pavilion::core {
namespace {

// Synthetic room scans as in line_extraction_test.cc.
constexpr double kPi = std::numbers::pi;
constexpr int kReadings = 361;  // LMS 200: 0.5 deg over 180 deg
constexpr double kRangeSigmaM = 0.01;
constexpr double kMaxRangeM = 8.0;
constexpr double kMinWallLengthM = 1.0;
constexpr double kMatchAlphaRad = 3.0 * kPi / 180.0;
constexpr double kMatchRM = 0.05;
constexpr int kCornerReadingsLost = 3;

using testing::SimulatedScan;
using testing::TrueLine;
using testing::WallElement;

std::vector<WallElement> Room() { return testing::RoomWithPillar(); }

SimulatedScan Simulate(const std::vector<WallElement>& walls, const Pose2& world_from_sensor,
                       RandomStream* rng) {
  return testing::SimulateScan({walls, {}}, world_from_sensor, rng,
                               {kReadings, kRangeSigmaM, kMaxRangeM});
}

struct Visibility {
  int first = -1;
  int last = -1;
  double length_m = 0.0;
  bool occluded = false;  // other readings between first and last
};
std::vector<Visibility> VisibleParts(std::size_t walls, const SimulatedScan& truth) {
  std::vector<Visibility> parts(walls);
  for (int i = 0; i < kReadings; ++i) {
    const int k = truth.wall_hit[i];
    if (k < 0) continue;
    if (parts[k].first < 0) parts[k].first = i;
    parts[k].last = i;
  }
  auto point = [&](int i) {
    const LaserReading& r = truth.scan.readings[i];
    return Eigen::Vector2d(r.range_m * std::cos(r.bearing_rad),
                           r.range_m * std::sin(r.bearing_rad));
  };
  for (std::size_t k = 0; k < walls; ++k) {
    Visibility& v = parts[k];
    if (v.first < 0) continue;
    v.length_m = (point(v.last) - point(v.first)).norm();
    for (int i = v.first; i <= v.last; ++i) {
      v.occluded = v.occluded || truth.wall_hit[i] != static_cast<int>(k);
    }
  }
  return parts;
}

bool Matches(const Line& extracted, const Line& truth) {
  return std::abs(NormalizeAngle(extracted.alpha_rad - truth.alpha_rad)) < kMatchAlphaRad &&
         std::abs(extracted.r_m - truth.r_m) < kMatchRM;
}

const Pose2 kPoses[] = {{3.0, 2.0, 0.3}, {1.5, 1.2, 0.8}, {6.5, 1.5, 2.4}, {2.0, 4.0, -0.9}};

// Noise-free: every visible wall >= 1 m found once with exact (alpha, r), its
// readings all but a few at the corners, nothing else; the segment equals
// FitLine + MakeSegment on its own readings.
TEST(SplitAndMergeTest, FindsEveryWallOfANoiseFreeRoomExactly) {
  const SplitAndMergeOptions options = SplitAndMergeOptions::SickLms200();
  const std::vector<WallElement> walls = Room();
  for (const Pose2& pose : kPoses) {
    const SimulatedScan scan = Simulate(walls, pose, nullptr);
    const std::vector<Visibility> visible = VisibleParts(walls.size(), scan);
    const std::vector<Segment> segments = SplitAndMerge(scan.scan, options);
    for (std::size_t k = 0; k < walls.size(); ++k) {
      if (visible[k].length_m < kMinWallLengthM) continue;
      const Line truth = TrueLine(walls[k], pose);
      int matches = 0;
      for (const Segment& seg : segments) {
        if (!Matches(seg.line, truth)) continue;
        ++matches;
        EXPECT_NEAR(NormalizeAngle(seg.line.alpha_rad - truth.alpha_rad), 0.0, 1e-9);
        EXPECT_NEAR(seg.line.r_m, truth.r_m, 1e-9);
        EXPECT_GE(seg.first_index, visible[k].first);
        EXPECT_LE(seg.last_index, visible[k].last);
        EXPECT_EQ(seg.point_count, seg.last_index - seg.first_index + 1);
        if (visible[k].occluded) continue;
        EXPECT_LE(seg.first_index, visible[k].first + kCornerReadingsLost);
        EXPECT_GE(seg.last_index, visible[k].last - kCornerReadingsLost);
      }
      // Merging joins adjacent segments only: a wall seen on both sides of
      // the pillar gives one segment per side.
      if (visible[k].occluded) {
        EXPECT_EQ(matches, 2) << "wall " << k;
      } else {
        EXPECT_EQ(matches, 1) << "wall " << k;
      }
    }
    for (const Segment& seg : segments) {
      bool any = false;
      for (const WallElement& wall : walls) any = any || Matches(seg.line, TrueLine(wall, pose));
      EXPECT_TRUE(any) << "spurious line alpha " << seg.line.alpha_rad << " r " << seg.line.r_m;
      // Same final fit and endpoints as ExtractLines' (eqs. 3.4-3.10, 5.3-5.16).
      std::vector<PolarPoint> points;
      for (int i = seg.first_index; i <= seg.last_index; ++i) {
        const LaserReading& r = scan.scan.readings[i];
        points.push_back({r.range_m, r.bearing_rad, options.range_sigma_m});
      }
      const std::optional<Line> fit = FitLine(points);
      ASSERT_TRUE(fit.has_value());
      const Segment expected =
          MakeSegment(*fit, points.front().bearing_rad, points.back().bearing_rad, kPi / 360.0,
                      static_cast<int>(points.size()), seg.first_index, seg.last_index);
      EXPECT_NEAR(seg.line.alpha_rad, expected.line.alpha_rad, 1e-12);
      EXPECT_NEAR(seg.line.r_m, expected.line.r_m, 1e-12);
      EXPECT_TRUE(seg.line.covariance.isApprox(expected.line.covariance, 1e-9));
      EXPECT_NEAR(seg.length_m, expected.length_m, 1e-9);
      EXPECT_NEAR(seg.length_variance_m2, expected.length_variance_m2, 1e-12);
    }
  }
}

// Noisy scans (sigma = 1 cm): the walls >= 1 m are found, and unoccluded ones
// once. The 5 cm chord threshold lets a few readings of a short pillar face
// join the other face's segment, which biases its fit: 9 such lines in these
// 200 scans (ExtractLines: none), a weakness of the baseline, bounded here.
TEST(SplitAndMergeTest, NoisyRoomScansFindTheWalls) {
  RandomStream rng(41, 1);
  const std::vector<WallElement> walls = Room();
  int expected = 0;
  int found = 0;
  int split = 0;
  int spurious = 0;
  for (int s = 0; s < 200; ++s) {
    const Pose2& pose = kPoses[s % 4];
    const SimulatedScan truth = Simulate(walls, pose, nullptr);
    const SimulatedScan noisy = Simulate(walls, pose, &rng);
    const std::vector<Visibility> visible = VisibleParts(walls.size(), truth);
    const std::vector<Segment> segments =
        SplitAndMerge(noisy.scan, SplitAndMergeOptions::SickLms200());
    for (const Segment& seg : segments) {
      bool any = false;
      for (const WallElement& wall : walls) any = any || Matches(seg.line, TrueLine(wall, pose));
      spurious += !any;
    }
    for (std::size_t k = 0; k < walls.size(); ++k) {
      if (visible[k].length_m < kMinWallLengthM) continue;
      ++expected;
      int matches = 0;
      for (const Segment& seg : segments) matches += Matches(seg.line, TrueLine(walls[k], pose));
      found += matches > 0;
      split += matches > 1 && !visible[k].occluded;
    }
  }
  ASSERT_GT(expected, 400);
  EXPECT_EQ(found, expected);
  EXPECT_LE(spurious, 0.1 * 200);
  EXPECT_LE(split, 0.02 * expected);
  std::printf("[ info ] split-and-merge: %d walls, %d found, %d unoccluded split, %d spurious\n",
              expected, found, split, spurious);
}

// Two collinear wall pieces with a 1 m opening: split at the gap (two
// segments) unless merging fuses them (one line); without gap splitting the
// chord test alone keeps them together.
TEST(SplitAndMergeTest, SplitsAtGaps) {
  const std::vector<WallElement> walls = {{{3, -3}, {3, -0.5}}, {{3, 0.5}, {3, 3}}};
  const Pose2 pose{0.0, 0.0, 0.0};
  const SimulatedScan scan = Simulate(walls, pose, nullptr);
  SplitAndMergeOptions options;
  options.merge = false;
  std::vector<Segment> segments = SplitAndMerge(scan.scan, options);
  ASSERT_EQ(segments.size(), 2u);
  EXPECT_NEAR(segments[0].line.r_m, 3.0, 1e-9);
  EXPECT_NEAR(segments[1].line.r_m, 3.0, 1e-9);
  EXPECT_LT(segments[0].last_index, segments[1].first_index);
  EXPECT_NEAR(segments[0].last_endpoint.position_m.y(), -0.5, 0.03);
  EXPECT_NEAR(segments[1].first_endpoint.position_m.y(), 0.5, 0.03);

  options.merge = true;
  segments = SplitAndMerge(scan.scan, options);
  ASSERT_EQ(segments.size(), 1u);
  EXPECT_NEAR(segments[0].line.r_m, 3.0, 1e-9);
  EXPECT_NEAR(segments[0].line.alpha_rad, 0.0, 1e-9);

  options.merge = false;
  options.split_at_gaps = false;
  EXPECT_EQ(SplitAndMerge(scan.scan, options).size(), 1u);

  // A step in depth (a wall 0.5 m behind another, parallel) is a gap too.
  const std::vector<WallElement> step = {{{3, -3}, {3, 0}}, {{3.5, 0}, {3.5, 3}}};
  options = SplitAndMergeOptions{};
  segments = SplitAndMerge(Simulate(step, pose, nullptr).scan, options);
  ASSERT_EQ(segments.size(), 2u);
  EXPECT_NEAR(segments[0].line.r_m, 3.0, 1e-9);
  EXPECT_NEAR(segments[1].line.r_m, 3.5, 1e-9);
}

// Degenerate inputs: empty, all invalid, too few points, coincident points,
// invalid readings with garbage ranges skipped.
TEST(SplitAndMergeTest, DegenerateInputs) {
  const SplitAndMergeOptions options;
  EXPECT_TRUE(SplitAndMerge(LaserScan{}, options).empty());
  LaserScan scan = Simulate(Room(), kPoses[0], nullptr).scan;
  LaserScan invalid = scan;
  for (LaserReading& r : invalid.readings) r.valid = false;
  EXPECT_TRUE(SplitAndMerge(invalid, options).empty());
  LaserScan one;
  one.readings.push_back({2.0, 0.0, 0.0, true, false});
  EXPECT_TRUE(SplitAndMerge(one, options).empty());
  LaserScan same;  // ten readings of one point
  for (int i = 0; i < 10; ++i) same.readings.push_back({2.0, 0.1, 0.0, true, false});
  EXPECT_TRUE(SplitAndMerge(same, options).empty());
  LaserScan nonfinite = scan;
  nonfinite.readings[5].range_m = std::numeric_limits<double>::quiet_NaN();
  nonfinite.readings[6].range_m = -1.0;
  EXPECT_NO_THROW(SplitAndMerge(nonfinite, options));

  // Dropouts with garbage ranges inside walls neither split nor bias them.
  LaserScan dropouts = scan;
  for (int i = 0; i < kReadings; i += 17) {
    dropouts.readings[i].valid = false;
    dropouts.readings[i].range_m = 0.3;
  }
  const std::vector<Segment> clean = SplitAndMerge(scan, options);
  const std::vector<Segment> holes = SplitAndMerge(dropouts, options);
  ASSERT_EQ(clean.size(), holes.size());
  for (std::size_t k = 0; k < clean.size(); ++k) {
    EXPECT_NEAR(clean[k].line.alpha_rad, holes[k].line.alpha_rad, 1e-9);
    EXPECT_NEAR(clean[k].line.r_m, holes[k].line.r_m, 1e-9);
  }
}

// Options are validated, naming the field.
TEST(SplitAndMergeTest, ValidatesOptions) {
  SplitAndMergeOptions options;
  options.split_threshold_m = 0.0;
  try {
    options.Validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("split_threshold_m"), std::string::npos);
  }
  options = SplitAndMergeOptions{};
  options.min_points = 1;
  EXPECT_THROW(SplitAndMerge(LaserScan{}, options), std::invalid_argument);
  options = SplitAndMergeOptions{};
  options.gap_lambda_rad = 2.0;
  EXPECT_THROW(options.Validate(), std::invalid_argument);
  EXPECT_NO_THROW(SplitAndMergeOptions::SickLms200().Validate());
}

}  // namespace
}  // namespace pavilion::core
