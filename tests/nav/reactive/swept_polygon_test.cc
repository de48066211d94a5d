// Exact contact of a polygon moving on an arc with a world-fixed point
// (nav/reactive/swept_polygon.h), against a brute-force time-stepped sweep.
#include "nav/reactive/swept_polygon.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "core/geometry/polygon.h"
#include "core/odometry/diff_drive.h"
#include "core/random/random_stream.h"
#include "core/types/pose2.h"

namespace pavilion::nav {
namespace {

constexpr double kFlat_m = 0.34;  // Robox-like octagon: 0.68 m across flats
const double kCorner_m = kFlat_m / std::cos(std::numbers::pi / 8.0);

core::Polygon2 Octagon() {
  core::Polygon2 p;
  for (int k = 0; k < 8; ++k) {
    const double a = std::numbers::pi / 8.0 + k * std::numbers::pi / 4.0;
    p.emplace_back(kCorner_m * std::cos(a), kCorner_m * std::sin(a));
  }
  return p;
}

// First time (s) at which the point is strictly inside the polygon when the
// robot integrates the twist with core::DiffDriveStep in steps moving no
// polygon or point by more than `step_m`; +inf if not before `max_s`.
double BruteForceTime(const core::Polygon2& polygon, const BodyTwist& twist,
                      const Eigen::Vector2d& point, double step_m, double max_s, double* dt_s) {
  constexpr double kBase_m = 1.0;  // any wheelbase: only the twist matters
  const double motion_mps =
      std::abs(twist.v_mps) + std::abs(twist.omega_radps) * (point.norm() + kCorner_m);
  *dt_s = step_m / motion_mps;
  core::Pose2 pose;
  const core::WheelTravel step{(twist.v_mps - 0.5 * kBase_m * twist.omega_radps) * *dt_s,
                               (twist.v_mps + 0.5 * kBase_m * twist.omega_radps) * *dt_s};
  for (double t = 0.0; t <= max_s; t += *dt_s) {
    if (core::Contains(polygon, pose.Inverse() * point)) return t;
    pose = core::DiffDriveStep(pose, step, kBase_m);
  }
  return std::numeric_limits<double>::infinity();
}

// Exact contact times match a 1 mm time-stepped sweep for random points and
// twists (forward, backward, turning, on the spot, straight).
TEST(SweptPolygonTest, MatchesBruteForceSweep) {
  core::RandomStream rng(14, 1);
  const core::Polygon2 octagon = Octagon();
  constexpr double kStep_m = 1e-3;
  int hits = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    const double r_m = rng.Uniform(0.3, 1.2);  // mostly within reach of a turn
    const double a_rad = rng.Uniform(-std::numbers::pi, std::numbers::pi);
    const Eigen::Vector2d p(r_m * std::cos(a_rad), r_m * std::sin(a_rad));
    if (core::Contains(octagon, p)) continue;
    BodyTwist twist{rng.Uniform(-0.6, 0.6), rng.Uniform(-2.0, 2.0)};
    if (trial % 5 == 0) twist.omega_radps = 0.0;
    if (trial % 5 == 1) twist.v_mps = 0.0;
    const double max_s = twist.omega_radps != 0.0
                             ? 2.0 * std::numbers::pi / std::abs(twist.omega_radps)
                             : 5.0 / std::abs(twist.v_mps);
    double dt_s = 0.0;
    const double brute_s = BruteForceTime(octagon, twist, p, kStep_m, max_s, &dt_s);
    const double exact_s = ExactTimeToCollision(octagon, twist, p);
    // DiffDriveStep's chord error over the run adds a few micrometres.
    const double tolerance_s = dt_s + 1e-5 * max_s;
    if (std::isfinite(brute_s)) {
      ++hits;
      EXPECT_LE(exact_s, brute_s + tolerance_s) << "trial " << trial;
      EXPECT_GE(exact_s, brute_s - tolerance_s) << "trial " << trial;
    } else {
      EXPECT_GE(exact_s, max_s - tolerance_s) << "trial " << trial;
    }
  }
  EXPECT_GT(hits, 150);  // the sample exercises contacts, not only misses
}

// Closed-form cases: straight ahead and behind, a point turned into a flat.
TEST(SweptPolygonTest, KnownGeometry) {
  const core::Polygon2 octagon = Octagon();
  EXPECT_NEAR(ExactArcLengthToCollision(octagon, 0.0, {1.0, 0.1}), 1.0 - kFlat_m, 1e-12);
  EXPECT_NEAR(ExactTimeToCollision(octagon, {-0.5, 0.0}, {-1.0, -0.1}), (1.0 - kFlat_m) / 0.5,
              1e-12);
  EXPECT_TRUE(std::isinf(ExactArcLengthToCollision(octagon, 0.0, {1.0, 0.5})));
  // A point at radius 0.36 on the x axis meets the front flat x = 0.34 after
  // acos(0.34/0.36) of rotation either way.
  const double angle = std::acos(kFlat_m / 0.36);
  EXPECT_NEAR(ExactRotationToCollision(octagon, true, {0.36, 0.0}), angle, 1e-12);
  EXPECT_NEAR(ExactRotationToCollision(octagon, false, {0.36, 0.0}), angle, 1e-12);
  // Beyond the circumradius rotation never touches it; inside means now.
  EXPECT_TRUE(std::isinf(ExactRotationToCollision(octagon, true, {0.0, kCorner_m + 1e-6})));
  EXPECT_EQ(ExactTimeToCollision(octagon, {0.3, 0.2}, {0.1, 0.1}), 0.0);
  EXPECT_TRUE(std::isinf(ExactTimeToCollision(octagon, {0.0, 0.0}, {1.0, 0.0})));
}

// A huge but finite radius agrees with the straight line (no precision loss).
TEST(SweptPolygonTest, NearlyStraightArcMatchesStraightLine) {
  const core::Polygon2 octagon = Octagon();
  const Eigen::Vector2d p(2.0, 0.2);
  const double straight = ExactArcLengthToCollision(octagon, 0.0, p);
  EXPECT_NEAR(ExactArcLengthToCollision(octagon, 1e-7, p), straight, 1e-6);
  EXPECT_NEAR(ExactArcLengthToCollision(octagon, -1e-7, p), straight, 1e-6);
}

// Inflation moves every edge out by the offset and keeps the polygon convex.
// The swept outline holds the polygon at its start and at the end of the
// arc, with no vertex moving more than the step between copies.
TEST(SweptPolygonTest, SweptOutlineFollowsTheArc) {
  const core::Polygon2 square = {{-0.3, -0.3}, {0.3, -0.3}, {0.3, 0.3}, {-0.3, 0.3}};
  const auto has_near = [](const std::vector<Eigen::Vector2d>& points, const Eigen::Vector2d& p) {
    return std::any_of(points.begin(), points.end(),
                       [&](const Eigen::Vector2d& q) { return (q - p).norm() < 1e-9; });
  };
  // A quarter turn left on a 1 m radius: 0.5 m/s, 0.5 rad/s for pi s.
  std::vector<Eigen::Vector2d> points;
  const core::Pose2 frame{2.0, 1.0, 0.0};
  AppendSweptOutline(square, BodyTwist{0.5, 0.5}, std::numbers::pi, 0.1, 0.05, frame, &points);
  const core::Pose2 end = frame * core::Pose2{1.0, 1.0, std::numbers::pi / 2.0};
  for (const Eigen::Vector2d& v : square) {
    EXPECT_TRUE(has_near(points, frame * v));
    EXPECT_TRUE(has_near(points, end * v));
  }
  // A vertex moves at most (0.5 m/s + 0.5 rad/s x 0.42 m) x pi s = 2.24 m:
  // 23 steps of 0.1 m, 24 copies of 4 edges x 12 samples.
  EXPECT_EQ(points.size(), 24u * 4u * 12u);
  // Standing still: one copy.
  points.clear();
  AppendSweptOutline(square, BodyTwist{}, 1.0, 0.1, 0.05, core::Pose2{}, &points);
  EXPECT_EQ(points.size(), 4u * 12u);
}

TEST(SweptPolygonTest, InflationOffsetsEveryEdge) {
  const core::Polygon2 grown = InflateConvexPolygon(Octagon(), 0.05);
  ASSERT_TRUE(IsConvexCounterClockwise(grown));
  EXPECT_NEAR(Circumradius(grown), (kFlat_m + 0.05) / std::cos(std::numbers::pi / 8.0), 1e-12);
  EXPECT_NEAR(ExactArcLengthToCollision(grown, 0.0, {1.0, 0.0}), 1.0 - kFlat_m - 0.05, 1e-12);
}

// Clockwise, non-convex and degenerate polygons are refused.
TEST(SweptPolygonTest, RecognizesConvexCounterClockwise) {
  core::Polygon2 octagon = Octagon();
  EXPECT_TRUE(IsConvexCounterClockwise(octagon));
  EXPECT_FALSE(IsConvexCounterClockwise({octagon.rbegin(), octagon.rend()}));
  EXPECT_FALSE(IsConvexCounterClockwise({{0, 0}, {1, 0}, {0.2, 0.2}, {0, 1}}));
  EXPECT_FALSE(IsConvexCounterClockwise({{0, 0}, {1, 0}}));
}

// Wheel speeds map to the twist of a differential drive.
TEST(SweptPolygonTest, TwistFromWheels) {
  const BodyTwist t = TwistFromWheels(0.2, 0.4, 0.5);
  EXPECT_DOUBLE_EQ(t.v_mps, 0.3);
  EXPECT_DOUBLE_EQ(t.omega_radps, 0.4);
  const Eigen::Vector3d pose = PoseAfter({1.0, std::numbers::pi / 2.0}, 1.0);
  EXPECT_NEAR(pose.x(), 2.0 / std::numbers::pi, 1e-12);
  EXPECT_NEAR(pose.y(), 2.0 / std::numbers::pi, 1e-12);
}

}  // namespace
}  // namespace pavilion::nav
