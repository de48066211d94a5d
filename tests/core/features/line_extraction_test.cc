#include "core/features/line_extraction.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <set>
#include <stdexcept>
#include <vector>

#include "core/math/chi_square.h"
#include "core/random/random_stream.h"
#include "tests/support/synthetic_room.h"

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr int kReadings = 361;         // LMS 200: 0.5 deg over 180 deg
constexpr double kRangeSigmaM = 0.01;  // Gaussian range noise
constexpr double kMaxRangeM = 8.0;
constexpr double kMinWallLengthM = 1.0;  // walls at least this long must be found
constexpr double kGate95 = 5.991464547;  // chi^2(2) quantile at 0.95
// Loose association of an extracted line to a true element (not the gate).
constexpr double kMatchAlphaRad = 3.0 * kPi / 180.0;
constexpr double kMatchRM = 0.05;
constexpr int kCornerReadingsLost = 3;
constexpr double kAssociationGate = 13.815510558;  // chi^2(2) quantile at 0.999

using testing::SimulatedScan;
using testing::TrueLine;
using testing::WallElement;
using World = testing::SyntheticWorld;

World Room() { return {testing::RoomWithPillar(), {}}; }

SimulatedScan Simulate(const World& world, const Pose2& world_from_sensor, RandomStream* rng) {
  return testing::SimulateScan(world, world_from_sensor, rng,
                               {kReadings, kRangeSigmaM, kMaxRangeM});
}

// The part of each wall seen by the noise-free scan: first and last reading
// hitting it (-1 when unseen) and the length between them.
struct Visibility {
  int first = -1;
  int last = -1;
  double length_m = 0.0;
};
std::vector<Visibility> VisibleParts(const World& world, const Pose2& world_from_sensor,
                                     const SimulatedScan& truth) {
  std::vector<Visibility> parts(world.walls.size());
  for (int i = 0; i < kReadings; ++i) {
    const int k = truth.wall_hit[i];
    if (k < 0) continue;
    if (parts[k].first < 0) parts[k].first = i;
    parts[k].last = i;
  }
  auto point = [&](int i) {
    const LaserReading& r = truth.scan.readings[i];
    return world_from_sensor * Eigen::Vector2d(r.range_m * std::cos(r.bearing_rad),
                                               r.range_m * std::sin(r.bearing_rad));
  };
  for (Visibility& v : parts) {
    if (v.first >= 0) v.length_m = (point(v.last) - point(v.first)).norm();
  }
  return parts;
}

double GateDistance(const Line& extracted, const Line& truth) {
  const Eigen::Vector2d e(NormalizeAngle(extracted.alpha_rad - truth.alpha_rad),
                          extracted.r_m - truth.r_m);
  return e.dot(extracted.covariance.inverse() * e);
}

// An extracted line belongs to a true element when it is close in (alpha, r)
// either geometrically or statistically (short, uncertain segments).
bool Matches(const Line& extracted, const Line& truth) {
  return (std::abs(NormalizeAngle(extracted.alpha_rad - truth.alpha_rad)) < kMatchAlphaRad &&
          std::abs(extracted.r_m - truth.r_m) < kMatchRM) ||
         GateDistance(extracted, truth) <= kAssociationGate;
}

// The wall that supports a segment: at least 90% of its point count, or all
// but one reading (the window union may take the next face's first reading at
// a corner), hits that wall among the readings it spans, else -1 (a spurious
// line, e.g. legs).
int SupportingWall(const Segment& seg, const SimulatedScan& scan, int walls) {
  constexpr double kSupportFraction = 0.9;
  const double support = std::min(kSupportFraction * seg.point_count, seg.point_count - 1.0);
  std::vector<int> hits(walls, 0);
  for (int i = seg.first_index; i <= seg.last_index; ++i) {
    if (scan.wall_hit[i] >= 0) ++hits[scan.wall_hit[i]];
  }
  for (int k = 0; k < walls; ++k) {
    if (hits[k] >= support) return k;
  }
  return -1;
}

struct Stats {
  int expected = 0;  // (scan, wall) pairs with a visible wall >= 1 m
  int found = 0;     // ... matched by at least one segment
  int split = 0;     // ... matched by more than one segment (oversegmentation)
  int matched = 0;   // segments matching an expected wall
  int in_gate = 0;   // ... whose (alpha, r) error is inside the 95% gate
  int segments = 0;
  int spurious = 0;  // segments not supported by the readings of one wall
  int scans_with_spurious = 0;
  int inconsistent = 0;  // wall-supported segments whose line misses the wall's
  double seconds = 0.0;
};

const Pose2 kPoses[] = {{3.0, 2.0, 0.3}, {1.5, 1.2, 0.8}, {6.5, 1.5, 2.4}, {2.0, 4.0, -0.9}};

// Extracts lines from `scans` noisy scans of the room (poses cycling through
// kPoses), with legs drawn in front of the sensor when `legs` is set.
Stats Evaluate(const LineExtractionOptions& options, int scans, bool legs, std::uint64_t seed) {
  RandomStream rng(seed, 1);
  Stats stats;
  for (int s = 0; s < scans; ++s) {
    const Pose2& pose = kPoses[s % 4];
    World world = Room();
    if (legs) {
      // A person: two legs 10-15 cm wide, 0.5-4 m in front of the sensor.
      const double range = rng.Uniform(0.5, 4.0);
      const double bearing = pose.theta_rad + rng.Uniform(-1.2, 1.2);
      const Eigen::Vector2d c =
          pose.translation() + range * Eigen::Vector2d(std::cos(bearing), std::sin(bearing));
      const Eigen::Vector2d side(-std::sin(bearing), std::cos(bearing));
      const double gap = rng.Uniform(0.15, 0.3);
      world.legs.push_back({c + 0.5 * gap * side, rng.Uniform(0.05, 0.075)});
      world.legs.push_back({c - 0.5 * gap * side, rng.Uniform(0.05, 0.075)});
    }
    const SimulatedScan truth = Simulate(world, pose, nullptr);
    const SimulatedScan noisy = Simulate(world, pose, &rng);
    const std::vector<Visibility> visible = VisibleParts(world, pose, truth);
    const auto start = std::chrono::steady_clock::now();
    const std::vector<Segment> segments = ExtractLines(noisy.scan, options);
    stats.seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    stats.segments += static_cast<int>(segments.size());
    int spurious = 0;
    for (const Segment& seg : segments) {
      const int wall = SupportingWall(seg, noisy, static_cast<int>(world.walls.size()));
      if (wall < 0) {
        ++spurious;
      } else {
        stats.inconsistent += !Matches(seg.line, TrueLine(world.walls[wall], pose));
      }
    }
    stats.spurious += spurious;
    stats.scans_with_spurious += spurious > 0;
    for (std::size_t k = 0; k < world.walls.size(); ++k) {
      if (visible[k].length_m < kMinWallLengthM) continue;
      ++stats.expected;
      const Line true_line = TrueLine(world.walls[k], pose);
      std::set<int> lines;  // pieces of one line (eq. 5.17) count once
      for (const Segment& seg : segments) {
        if (!Matches(seg.line, true_line) || !lines.insert(seg.line_id).second) continue;
        ++stats.matched;
        stats.in_gate += GateDistance(seg.line, true_line) <= kGate95;
      }
      stats.found += !lines.empty();
      stats.split += lines.size() > 1;
    }
  }
  return stats;
}

// On noise-free readings of walls every visible wall of at least 1 m is found
// once, its (alpha, r) exact, its readings all but a few at the corners
// (segmentation loses the readings whose windows straddle a corner), and
// nothing else is extracted.
TEST(LineExtractionTest, FindsEveryWallOfANoiseFreeRoom) {
  const LineExtractionOptions options = LineExtractionOptions::SickLms200();
  for (const Pose2& pose : kPoses) {
    const World world = Room();
    const SimulatedScan scan = Simulate(world, pose, nullptr);
    const std::vector<Visibility> visible = VisibleParts(world, pose, scan);
    const std::vector<Segment> segments = ExtractLines(scan.scan, options);
    for (std::size_t k = 0; k < world.walls.size(); ++k) {
      if (visible[k].length_m < kMinWallLengthM) continue;
      const Line truth = TrueLine(world.walls[k], pose);
      // One line; a wall seen on both sides of the pillar comes in two pieces
      // sharing it (eq. 5.17).
      std::set<int> lines;
      int first = std::numeric_limits<int>::max();
      int last = -1;
      double length_m = 0.0;
      for (const Segment& seg : segments) {
        if (!Matches(seg.line, truth)) continue;
        lines.insert(seg.line_id);
        EXPECT_NEAR(NormalizeAngle(seg.line.alpha_rad - truth.alpha_rad), 0.0, 1e-9);
        EXPECT_NEAR(seg.line.r_m, truth.r_m, 1e-9);
        first = std::min(first, seg.first_index);
        last = std::max(last, seg.last_index);
        length_m += seg.length_m;
      }
      EXPECT_EQ(lines.size(), 1u) << "wall " << k;
      EXPECT_GE(first, visible[k].first);
      EXPECT_LE(first, visible[k].first + kCornerReadingsLost);
      EXPECT_LE(last, visible[k].last);
      EXPECT_GE(last, visible[k].last - kCornerReadingsLost);
      EXPECT_LE(length_m, visible[k].length_m + 1e-9);
    }
    for (const Segment& seg : segments) {
      bool any = false;
      for (const WallElement& wall : world.walls)
        any = any || Matches(seg.line, TrueLine(wall, pose));
      EXPECT_TRUE(any) << "spurious line alpha " << seg.line.alpha_rad << " r " << seg.line.r_m;
    }
  }
}

// Over 200 noisy scans (sigma = 1 cm) every wall of at least 1 m is found, no
// spurious line appears, few walls are split in two, few wall fragments are
// biased beyond the association gate, and >= 90% of the (alpha, r) errors lie
// inside the 95% chi^2(2) gate of the predicted covariance.
TEST(LineExtractionTest, NoisyRoomScansAreFoundAndConsistent) {
  const Stats stats = Evaluate(LineExtractionOptions::SickLms200(), 200, false, 31);
  ASSERT_GT(stats.expected, 400);
  EXPECT_EQ(stats.found, stats.expected);
  EXPECT_EQ(stats.spurious, 0);
  EXPECT_LE(stats.split, 0.03 * stats.expected);  // measured 0.7%
  EXPECT_LE(stats.inconsistent, 0.05 * 200);
  EXPECT_GE(stats.in_gate, 0.9 * stats.matched);
  std::printf(
      "[ info ] %d walls, %d found, %d split, %d inconsistent fragments, %.1f%% in the 95%% "
      "gate, %.1f us per %d-reading scan\n",
      stats.expected, stats.found, stats.split, stats.inconsistent,
      100.0 * stats.in_gate / stats.matched, 1e6 * stats.seconds / 200, kReadings);
}

// Legs 10-15 cm wide, 0.5-4 m away, produce no segment in >= 99% of 200 scans,
// and the walls behind them are still found (occluded parts fused, eq. 3.16).
TEST(LineExtractionTest, RejectsLegs) {
  const Stats stats = Evaluate(LineExtractionOptions::SickLms200(), 200, true, 32);
  EXPECT_LE(stats.scans_with_spurious, 2);
  EXPECT_GE(stats.found, 0.95 * stats.expected);
  EXPECT_GE(stats.in_gate, 0.9 * stats.matched);
  std::printf("[ info ] legs: %d scans with a spurious line, %d/%d walls found\n",
              stats.scans_with_spurious, stats.found, stats.expected);
}

// The n_f sweep behind the LMS 200 preset (printed, not asserted beyond the
// preset's own bounds, which the tests above check).
TEST(LineExtractionTest, WindowSizeSweepForLms200) {
  for (int nf : {5, 7, 9, 11, 13, 15}) {
    LineExtractionOptions options = LineExtractionOptions::SickLms200();
    options.window_size = nf;
    const Stats clean = Evaluate(options, 100, false, 33);
    const Stats legs = Evaluate(options, 100, true, 34);
    std::printf(
        "[ info ] n_f %2d: found %.3f split %.3f gate %.3f spurious+inconsistent/scan %.3f | legs: "
        "found %.3f split %.3f gate %.3f scans with spurious %.3f | %.1f us/scan\n",
        nf, 1.0 * clean.found / clean.expected, 1.0 * clean.split / clean.expected,
        1.0 * clean.in_gate / clean.matched, (clean.spurious + clean.inconsistent) / 100.0,
        1.0 * legs.found / legs.expected, 1.0 * legs.split / legs.expected,
        1.0 * legs.in_gate / legs.matched, legs.scans_with_spurious / 100.0,
        1e6 * clean.seconds / 100);
  }
}

// Invalid readings are skipped: dropouts inside a wall do not split or bias it.
TEST(LineExtractionTest, SkipsInvalidReadings) {
  const Pose2 pose = kPoses[0];
  const World world = Room();
  SimulatedScan scan = Simulate(world, pose, nullptr);
  for (int i = 0; i < kReadings; i += 17) {
    scan.scan.readings[i].valid = false;
    scan.scan.readings[i].range_m = 0.3;  // garbage that must be ignored
  }
  const std::vector<Segment> segments =
      ExtractLines(scan.scan, LineExtractionOptions::SickLms200());
  for (const Segment& seg : segments) {
    bool any = false;
    for (const WallElement& wall : world.walls)
      any = any || Matches(seg.line, TrueLine(wall, pose));
    EXPECT_TRUE(any);
  }
  EXPECT_FALSE(segments.empty());
}

// Options are validated, naming the field.
TEST(LineExtractionTest, ValidatesOptions) {
  LineExtractionOptions options;
  options.window_size = 8;
  try {
    options.Validate();
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("window_size"), std::string::npos);
  }
  options = LineExtractionOptions{};
  options.significance = 1.0;
  EXPECT_THROW(ExtractLines(LaserScan{}, options), std::invalid_argument);
  EXPECT_TRUE(ExtractLines(LaserScan{}, LineExtractionOptions{}).empty());
  EXPECT_NEAR(ChiSquare2Quantile(0.95), kGate95, 1e-6);
}

}  // namespace
}  // namespace pavilion::core
