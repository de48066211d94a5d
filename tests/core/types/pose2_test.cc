#include "core/types/pose2.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/random/random_stream.h"

namespace pavilion::core {
namespace {

constexpr double kTol = 1e-12;

// Compounding with the inverse gives the identity, in both orders.
TEST(Pose2Test, InverseComposesToIdentity) {
  RandomStream rng(1, 1);
  for (int i = 0; i < 100; ++i) {
    const Pose2 a{rng.Uniform(-10, 10), rng.Uniform(-10, 10), rng.Uniform(-3, 3)};
    for (const Pose2& e : {a * a.Inverse(), a.Inverse() * a}) {
      EXPECT_NEAR(e.x_m, 0.0, kTol);
      EXPECT_NEAR(e.y_m, 0.0, kTol);
      EXPECT_NEAR(e.theta_rad, 0.0, kTol);
    }
  }
}

// Compounding is associative and agrees with transforming points.
TEST(Pose2Test, CompoundingIsAssociativeAndMatchesPointTransform) {
  RandomStream rng(2, 1);
  for (int i = 0; i < 100; ++i) {
    const Pose2 a{rng.Uniform(-5, 5), rng.Uniform(-5, 5), rng.Uniform(-3, 3)};
    const Pose2 b{rng.Uniform(-5, 5), rng.Uniform(-5, 5), rng.Uniform(-3, 3)};
    const Pose2 c{rng.Uniform(-5, 5), rng.Uniform(-5, 5), rng.Uniform(-3, 3)};
    const Pose2 l = (a * b) * c;
    const Pose2 r = a * (b * c);
    EXPECT_NEAR(l.x_m, r.x_m, 1e-9);
    EXPECT_NEAR(l.y_m, r.y_m, 1e-9);
    EXPECT_NEAR(NormalizeAngle(l.theta_rad - r.theta_rad), 0.0, 1e-12);
    const Eigen::Vector2d p(rng.Uniform(-1, 1), rng.Uniform(-1, 1));
    EXPECT_TRUE(((a * b) * p).isApprox(a * (b * p), 1e-12));
  }
}

// A quarter turn about the origin maps the x axis onto the y axis.
TEST(Pose2Test, QuarterTurnRotatesPoints) {
  const Pose2 world_from_robot{1.0, 2.0, std::numbers::pi / 2};
  const Eigen::Vector2d hit_in_robot(1.0, 0.0);
  const Eigen::Vector2d hit_in_world = world_from_robot * hit_in_robot;
  EXPECT_NEAR(hit_in_world.x(), 1.0, kTol);
  EXPECT_NEAR(hit_in_world.y(), 3.0, kTol);
}

// Angles wrap into (-pi, pi], with pi itself kept.
TEST(Pose2Test, NormalizeAngleWrapsIntoHalfOpenInterval) {
  EXPECT_NEAR(NormalizeAngle(3 * std::numbers::pi), std::numbers::pi, kTol);
  EXPECT_NEAR(NormalizeAngle(-std::numbers::pi), std::numbers::pi, kTol);
  EXPECT_NEAR(NormalizeAngle(2 * std::numbers::pi + 0.1), 0.1, kTol);
  EXPECT_NEAR(NormalizeAngle(-0.1), -0.1, kTol);
}

}  // namespace
}  // namespace pavilion::core
