#include "sim/bodies/body_motion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace pavilion::sim {
namespace {

// Segments play in order, in the body frame, and the body stops after the last.
TEST(BodyMotionTest, ScriptedSegmentsPlayInOrder) {
  ScriptedMotionOptions o;
  o.segments = {{2.0, {0.5, 0.0}, 0.0}, {1.0, {0.0, 0.0}, 1.0}};
  ScriptedMotion m(o);
  BodyState s;
  s.pose.theta_rad = std::numbers::pi / 2;  // facing +y
  PlanarVelocity v = m.Update(0.5, s);
  EXPECT_NEAR(v.linear_mps.x(), 0.0, 1e-12);
  EXPECT_NEAR(v.linear_mps.y(), 0.5, 1e-12);
  v = m.Update(2.5, s);
  EXPECT_NEAR(v.linear_mps.norm(), 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(v.yaw_rate_radps, 1.0);
  v = m.Update(3.5, s);
  EXPECT_DOUBLE_EQ(v.linear_mps.norm(), 0.0);
  EXPECT_DOUBLE_EQ(v.yaw_rate_radps, 0.0);
  o.loop = true;
  ScriptedMotion looped(o);
  EXPECT_NEAR(looped.Update(3.5, s).linear_mps.y(), 0.5, 1e-12);
}

// World-frame segments ignore the body's heading.
TEST(BodyMotionTest, WorldFrameIgnoresHeading) {
  ScriptedMotionOptions o;
  o.body_frame = false;
  o.segments = {{1.0, {0.3, -0.2}, 0.0}};
  ScriptedMotion m(o);
  BodyState s;
  s.pose.theta_rad = 1.0;
  const PlanarVelocity v = m.Update(0.1, s);
  EXPECT_DOUBLE_EQ(v.linear_mps.x(), 0.3);
  EXPECT_DOUBLE_EQ(v.linear_mps.y(), -0.2);
}

// A random walker keeps its speed, changes heading on average every
// mean_leg_s, turns when blocked, and repeats itself for the same stream.
TEST(BodyMotionTest, RandomWalkLegsAndBlocking) {
  RandomWalkOptions o;
  o.speed_mps = 1.0;
  o.mean_leg_s = 2.0;
  RandomWalkMotion a(o, core::RandomStream(1, 9));
  RandomWalkMotion b(o, core::RandomStream(1, 9));
  BodyState moving;
  int changes = 0;
  Eigen::Vector2d last(0, 0);
  constexpr double kDt = 0.01;
  constexpr int kSteps = 100000;  // 1000 s
  for (int i = 0; i < kSteps; ++i) {
    const PlanarVelocity va = a.Update(i * kDt, moving);
    const PlanarVelocity vb = b.Update(i * kDt, moving);
    ASSERT_EQ(va.linear_mps, vb.linear_mps);
    EXPECT_NEAR(va.linear_mps.norm(), 1.0, 1e-12);
    moving.velocity_mps = va.linear_mps;
    if (!va.linear_mps.isApprox(last)) ++changes;
    last = va.linear_mps;
  }
  // Poisson count with mean 500: within 5 standard deviations.
  EXPECT_NEAR(changes, 500, 5 * std::sqrt(500.0));

  RandomWalkMotion c(o, core::RandomStream(2, 9));
  BodyState stuck;  // zero velocity: blocked
  const Eigen::Vector2d first = c.Update(0.0, stuck).linear_mps;
  Eigen::Vector2d now = first;
  double t = 0.0;
  while (now.isApprox(first) && t < 10.0) {
    t += kDt;
    now = c.Update(t, stuck).linear_mps;
  }
  EXPECT_LE(t, o.blocked_s + 2 * kDt);  // turned once blocked for blocked_s
}

// The message Validate() throws; empty when it accepts.
template <typename Options>
std::string ValidateMessage(const Options& o) {
  try {
    o.Validate();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

// Confirms that the defaults are valid and each out-of-range field is rejected
// with its name (the scenario loader reports it at that field's key).
TEST(BodyMotionOptions, ValidateNamesTheField) {
  EXPECT_EQ(ValidateMessage(VelocitySegment{}), "");
  EXPECT_EQ(ValidateMessage(RandomWalkOptions{}), "");
  VelocitySegment seg;
  seg.duration_s = 0.0;
  EXPECT_NE(ValidateMessage(seg).find("duration_s"), std::string::npos);
  seg = {};
  seg.velocity_mps.x() = std::nan("");
  EXPECT_NE(ValidateMessage(seg).find("velocity_mps"), std::string::npos);
  seg = {};
  seg.yaw_rate_radps = -101.0;
  EXPECT_NE(ValidateMessage(seg).find("yaw_rate_radps"), std::string::npos);
  RandomWalkOptions walk;
  walk.speed_mps = 5.5;
  EXPECT_NE(ValidateMessage(walk).find("speed_mps"), std::string::npos);
  walk = {};
  walk.mean_leg_s = 0.0;
  EXPECT_NE(ValidateMessage(walk).find("mean_leg_s"), std::string::npos);
  walk = {};
  walk.blocked_ratio = 1.5;
  EXPECT_NE(ValidateMessage(walk).find("blocked_ratio"), std::string::npos);
  walk = {};
  walk.blocked_s = -1.0;
  EXPECT_NE(ValidateMessage(walk).find("blocked_s"), std::string::npos);
}

}  // namespace
}  // namespace pavilion::sim
