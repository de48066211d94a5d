// The path follower on an ideal unicycle: it reaches the goal, stays near the
// path, and keeps its speed, acceleration and turn-rate limits.
#include "nav/control/path_follower.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace pavilion::nav {
namespace {

double DistanceToPath(const std::vector<Eigen::Vector2d>& path, const Eigen::Vector2d& p) {
  double best = 1e9;
  for (std::size_t k = 1; k < path.size(); ++k) {
    const Eigen::Vector2d ab = path[k] - path[k - 1];
    const double t = std::clamp((p - path[k - 1]).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    best = std::min(best, (path[k - 1] + t * ab - p).norm());
  }
  return best;
}

TEST(PathFollower, FollowsACorridorWithCornersToTheGoal) {
  // Out along a corridor, a right angle, a U-turn back along a parallel one.
  const std::vector<Eigen::Vector2d> path = {{0, 0}, {10, 0}, {10, 3}, {2, 3}};
  PathFollowerOptions options;
  PathFollower follower(path, options);
  core::Pose2 pose{0.0, 0.0, 0.0};
  const double dt = 0.01;
  double previous_v = 0.0;
  double max_deviation = 0.0;
  double t = 0.0;
  for (; t < 200.0 && !follower.done(); t += dt) {
    const VelocityCommand c = follower.Update(pose, dt);
    EXPECT_LE(c.linear_mps, options.max_speed_mps + 1e-12);
    EXPECT_GE(c.linear_mps, 0.0);
    EXPECT_LE(std::abs(c.angular_radps), options.max_turn_rate_radps + 1e-12);
    EXPECT_LE(std::abs(c.linear_mps - previous_v), options.max_accel_mps2 * dt + 1e-12);
    previous_v = c.linear_mps;
    pose.x_m += c.linear_mps * std::cos(pose.theta_rad) * dt;
    pose.y_m += c.linear_mps * std::sin(pose.theta_rad) * dt;
    pose.theta_rad = core::NormalizeAngle(pose.theta_rad + c.angular_radps * dt);
    max_deviation = std::max(max_deviation, DistanceToPath(path, pose.translation()));
  }
  EXPECT_TRUE(follower.done());
  EXPECT_LT((pose.translation() - path.back()).norm(), options.goal_tolerance_m + 0.02);
  EXPECT_LT(max_deviation, 0.25);  // corners are cut by less than half a look-ahead
  // 21 m at <= 0.6 m/s with two corners: about 40-60 s.
  EXPECT_GT(t, 21.0 / options.max_speed_mps);
  EXPECT_LT(t, 80.0);
}

TEST(PathFollower, ConvertsToWheelSpeeds) {
  const WheelSpeeds w = ToWheelSpeeds({0.5, 1.0}, 0.1, 0.1, 0.4);
  EXPECT_NEAR(w.left_radps, (0.5 - 0.2) / 0.1, 1e-12);
  EXPECT_NEAR(w.right_radps, (0.5 + 0.2) / 0.1, 1e-12);
}

TEST(PathFollower, ValidatesOptions) {
  PathFollowerOptions o;
  o.max_speed_mps = 0.0;
  EXPECT_THROW(o.Validate(), std::invalid_argument);
  EXPECT_THROW(PathFollower({}, PathFollowerOptions{}), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::nav
