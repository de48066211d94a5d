// The dynamic window in wheel-speed space (nav/reactive/dynamic_window.h):
// safety against the exact swept octagon, progress, limits, goal poses.
#include "nav/reactive/dynamic_window.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/geometry/polygon.h"
#include "core/odometry/diff_drive.h"
#include "core/random/random_stream.h"
#include "core/types/pose2.h"

namespace pavilion::nav {
namespace {

constexpr double kFlat_m = 0.34;  // Robox-like octagon, 0.68 m across flats
constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
const double kCorner_m = kFlat_m / std::cos(kPi / 8.0);

core::Polygon2 Octagon() {
  core::Polygon2 p;
  for (int k = 0; k < 8; ++k) {
    const double a = kPi / 8.0 + k * kPi / 4.0;
    p.emplace_back(kCorner_m * std::cos(a), kCorner_m * std::sin(a));
  }
  return p;
}

DynamicWindowOptions RoboxOptions() {
  DynamicWindowOptions o;
  o.wheelbase_m = 0.6;
  return o;
}

// Time-stepped sweep of the EXACT octagon (no margin): the command held one
// period, then both wheels braked proportionally at max_wheel_accel_mps2;
// integrated with core::DiffDriveStep every kDt_s, each point tested with
// core::Contains in the moving robot frame.
bool SweptOctagonTouches(const DynamicWindowOptions& o, const WheelVelocity& command,
                         const std::vector<Eigen::Vector2d>& points) {
  constexpr double kDt_s = 5e-4;
  const core::Polygon2 octagon = Octagon();
  const double peak = std::max(std::abs(command.left_mps), std::abs(command.right_mps));
  const double brake_s = peak / o.max_wheel_accel_mps2;
  const double total_s = o.period_s + brake_s;
  std::vector<Eigen::Vector2d> near;
  const double reach_m = peak * total_s + kCorner_m;
  for (const Eigen::Vector2d& p : points) {
    if (p.norm() <= reach_m + 0.1) near.push_back(p);
  }
  core::Pose2 pose;
  for (double t = 0.0; t <= total_s + kDt_s; t += kDt_s) {
    for (const Eigen::Vector2d& p : near) {
      if (core::Contains(octagon, pose.Inverse() * p)) return true;
    }
    const double mid_s = t + 0.5 * kDt_s;
    const double scale =
        mid_s <= o.period_s ? 1.0 : std::max(0.0, 1.0 - (mid_s - o.period_s) / brake_s);
    pose = core::DiffDriveStep(
        pose, {command.left_mps * scale * kDt_s, command.right_mps * scale * kDt_s}, o.wheelbase_m);
  }
  return false;
}

// A random scene: clutter, wall segments and people-like clusters, all at
// least kNearest_m from the robot centre (outside the grown octagon).
std::vector<Eigen::Vector2d> RandomScene(core::RandomStream& rng) {
  constexpr double kNearest_m = 0.42;
  std::vector<Eigen::Vector2d> points;
  auto add = [&](const Eigen::Vector2d& p) {
    if (p.norm() >= kNearest_m) points.push_back(p);
  };
  const int clutter = static_cast<int>(rng.UniformInt(0, 25));
  for (int i = 0; i < clutter; ++i) {
    const double r = rng.Uniform(kNearest_m, 3.0);
    const double a = rng.Uniform(-kPi, kPi);
    add({r * std::cos(a), r * std::sin(a)});
  }
  const int walls = static_cast<int>(rng.UniformInt(0, 2));
  for (int w = 0; w < walls; ++w) {
    const double d = rng.Uniform(0.45, 2.5);
    const double a = rng.Uniform(-kPi, kPi);
    const Eigen::Vector2d n(std::cos(a), std::sin(a));
    const Eigen::Vector2d t(-n.y(), n.x());
    for (double s = -2.0; s <= 2.0; s += 0.02) add(d * n + s * t);
  }
  const int people = static_cast<int>(rng.UniformInt(0, 3));
  for (int k = 0; k < people; ++k) {
    const double r = rng.Uniform(0.7, 3.0);
    const double a = rng.Uniform(-kPi, kPi);
    const double radius = rng.Uniform(0.15, 0.25);
    const Eigen::Vector2d c(r * std::cos(a), r * std::sin(a));
    for (double b = 0.0; b < 2.0 * kPi; b += 0.03 / radius) {
      add(c + radius * Eigen::Vector2d(std::cos(b), std::sin(b)));
    }
  }
  return points;
}

// Free path: the octagon grown by the margin and one table cell, swept
// straight ahead for the braking distance from the slowest forward grid
// speed plus one period, holds no point.
bool HasFreePath(const DynamicWindow& dwa, const std::vector<Eigen::Vector2d>& points) {
  const DynamicWindowOptions& o = dwa.options();
  const double v = o.max_wheel_accel_mps2 * o.period_s;
  const double length_m = dwa.StoppingArc({v, v}) + v * o.period_s;
  const double half_width_m = kFlat_m + o.safety_margin_m + o.table_cell_m;
  const double front_m = kFlat_m + o.safety_margin_m + o.table_cell_m + length_m;
  return std::none_of(points.begin(), points.end(), [&](const Eigen::Vector2d& p) {
    return p.x() > 0.0 && p.x() <= front_m && std::abs(p.y()) <= half_width_m;
  });
}

// 1,200 seeded random scenes: no command chosen as admissible lets the exact
// octagon touch a point during its period and braking, every command keeps
// the acceleration limits, 121 candidates are evaluated, and >= 90% of the
// scenes with a free path get a forward command.
TEST(DynamicWindowTest, RandomScenesSafeAndMoving) {
  const DynamicWindowOptions o = RoboxOptions();
  DynamicWindow dwa(o, Octagon());
  core::RandomStream rng(14, 3);
  const double step_mps = o.max_wheel_accel_mps2 * o.period_s;
  int free_scenes = 0, free_forward = 0, blocked = 0, rejections = 0;
  constexpr int kScenes = 1200;
  for (int scene = 0; scene < kScenes; ++scene) {
    WheelVelocity current;
    do {
      current = {rng.Uniform(-0.8, 0.8), rng.Uniform(-0.8, 0.8)};
    } while (0.5 * (current.left_mps + current.right_mps) < 0.0 ||
             0.5 * (current.left_mps + current.right_mps) > o.max_speed_mps);
    const std::vector<Eigen::Vector2d> points = RandomScene(rng);
    DwaGoal goal;
    const double bearing = rng.Uniform(-0.5 * kPi, 0.5 * kPi);
    const double range = rng.Uniform(1.0, 6.0);
    goal.target_in_robot = range * Eigen::Vector2d(std::cos(bearing), std::sin(bearing));
    const DwaResult r = dwa.Choose(current, points, goal);
    ASSERT_EQ(r.candidates_evaluated, 121);
    EXPECT_LE(std::abs(r.command.left_mps - current.left_mps), step_mps + 1e-12);
    EXPECT_LE(std::abs(r.command.right_mps - current.right_mps), step_mps + 1e-12);
    EXPECT_FALSE(r.in_collision);
    rejections += r.exact_rejections;
    if (r.admissible_found) {
      EXPECT_FALSE(SweptOctagonTouches(o, r.command, points)) << "scene " << scene;
    } else {
      ++blocked;
    }
    if (HasFreePath(dwa, points)) {
      ++free_scenes;
      if (r.command.left_mps + r.command.right_mps > 0.0) ++free_forward;
    }
  }
  RecordProperty("free_scenes", free_scenes);
  RecordProperty("free_forward", free_forward);
  RecordProperty("blocked", blocked);
  RecordProperty("exact_rejections", rejections);
  EXPECT_GT(free_scenes, kScenes / 3);
  EXPECT_LT(free_scenes, kScenes);  // the scenes include blocked fronts too
  EXPECT_GE(free_forward, 0.9 * free_scenes);
}

// The exact-geometry variant (the benchmark's baseline) is safe as well.
TEST(DynamicWindowTest, ExactGeometryScenesSafe) {
  DynamicWindowOptions o = RoboxOptions();
  o.clearance_geometry = ClearanceGeometry::kExact;
  DynamicWindow dwa(o, Octagon());
  core::RandomStream rng(14, 4);
  int admissible = 0;
  for (int scene = 0; scene < 200; ++scene) {
    const WheelVelocity current{rng.Uniform(0.0, 0.6), rng.Uniform(0.0, 0.6)};
    const std::vector<Eigen::Vector2d> points = RandomScene(rng);
    DwaGoal goal;
    goal.target_in_robot = {3.0, rng.Uniform(-3.0, 3.0)};
    const DwaResult r = dwa.Choose(current, points, goal);
    if (!r.admissible_found) continue;
    ++admissible;
    EXPECT_FALSE(SweptOctagonTouches(o, r.command, points)) << "scene " << scene;
  }
  EXPECT_GT(admissible, 150);
}

// Kinematics of one period at constant wheel speeds (DiffDriveStep, 10 sub-steps).
core::Pose2 Drive(const core::Pose2& pose, const WheelVelocity& w, const DynamicWindowOptions& o) {
  constexpr int kSubsteps = 10;
  core::Pose2 next = pose;
  const double dt = o.period_s / kSubsteps;
  for (int i = 0; i < kSubsteps; ++i) {
    next = core::DiffDriveStep(next, {w.left_mps * dt, w.right_mps * dt}, o.wheelbase_m);
  }
  return next;
}

Eigen::Vector2d InRobot(const core::Pose2& world_from_robot, const Eigen::Vector2d& p_in_world) {
  return world_from_robot.Inverse() * p_in_world;
}

// In free space the robot turns to a target off to the side, heads for it
// and settles at the translation limit.
TEST(DynamicWindowTest, FreeSpaceHeadsToTargetAtSteadySpeed) {
  const DynamicWindowOptions o = RoboxOptions();
  DynamicWindow dwa(o, Octagon());
  const Eigen::Vector2d target_in_world(30.0, 10.0);
  core::Pose2 pose;
  WheelVelocity w;
  for (int k = 0; k < 100; ++k) {
    DwaGoal goal;
    goal.target_in_robot = InRobot(pose, target_in_world);
    const DwaResult r = dwa.Choose(w, {}, goal);
    ASSERT_TRUE(r.admissible_found);
    w = r.command;
    pose = Drive(pose, w, o);
    if (k >= 60) {  // 6 s on: steady
      EXPECT_NEAR(0.5 * (w.left_mps + w.right_mps), o.max_speed_mps, 0.02) << k;
      const Eigen::Vector2d to = InRobot(pose, target_in_world);
      EXPECT_LT(std::abs(std::atan2(to.y(), to.x())), 3.0 * kDeg) << k;
    }
  }
}

// The caller's speed limit caps the translation.
TEST(DynamicWindowTest, RespectsCallerSpeedLimit) {
  DynamicWindow dwa(RoboxOptions(), Octagon());
  WheelVelocity w;
  DwaGoal goal;
  goal.target_in_robot = {10.0, 0.0};
  goal.speed_limit_mps = 0.25;
  for (int k = 0; k < 40; ++k) w = dwa.Choose(w, {}, goal).command;
  EXPECT_LE(0.5 * (w.left_mps + w.right_mps), 0.25 + 1e-9);
  EXPECT_GE(0.5 * (w.left_mps + w.right_mps), 0.25 - 0.02);
}

// Pose mode: the robot drives to the last node and turns on the spot to its
// heading, ending within 2 cm and 2 degrees (simulated at 10 Hz).
TEST(DynamicWindowTest, PoseModeEndsAtGoalPose) {
  const DynamicWindowOptions o = RoboxOptions();
  DynamicWindow dwa(o, Octagon());
  const core::Pose2 goal_in_world{2.5, 1.2, 100.0 * kDeg};
  core::Pose2 pose;
  WheelVelocity w;
  bool reached = false;
  for (int k = 0; k < 600 && !(reached && w.left_mps == 0.0 && w.right_mps == 0.0); ++k) {
    DwaGoal goal;
    goal.pose_goal = true;
    goal.goal_in_robot = InRobot(pose, goal_in_world.translation());
    goal.target_in_robot = goal.goal_in_robot;
    goal.goal_heading_in_robot_rad = core::NormalizeAngle(goal_in_world.theta_rad - pose.theta_rad);
    const DwaResult r = dwa.Choose(w, {}, goal);
    reached = r.goal_reached;
    w = r.command;
    pose = Drive(pose, w, o);
  }
  EXPECT_TRUE(reached);
  EXPECT_LT((pose.translation() - goal_in_world.translation()).norm(), 0.02);
  EXPECT_LT(std::abs(core::NormalizeAngle(pose.theta_rad - goal_in_world.theta_rad)), 2.0 * kDeg);
}

// Boxed in at standstill, stop is the only admissible command; a point
// inside the robot is reported as a collision and the robot brakes.
TEST(DynamicWindowTest, StopWhenBoxedInAndBrakeInCollision) {
  const DynamicWindowOptions o = RoboxOptions();
  DynamicWindow dwa(o, Octagon());
  std::vector<Eigen::Vector2d> ring;
  for (int k = 0; k < 360; ++k) {
    ring.emplace_back(0.375 * std::cos(k * kDeg), 0.375 * std::sin(k * kDeg));
  }
  DwaGoal goal;
  goal.target_in_robot = {5.0, 0.0};
  const DwaResult boxed = dwa.Choose({}, ring, goal);
  EXPECT_TRUE(boxed.admissible_found);
  EXPECT_EQ(boxed.command.left_mps, 0.0);
  EXPECT_EQ(boxed.command.right_mps, 0.0);
  const std::vector<Eigen::Vector2d> inside = {{0.2, 0.0}};
  const DwaResult hit = dwa.Choose({0.5, 0.5}, inside, goal);
  EXPECT_TRUE(hit.in_collision);
  EXPECT_FALSE(hit.admissible_found);
  EXPECT_NEAR(hit.command.left_mps, 0.4, 1e-12);  // one period of full braking
  EXPECT_NEAR(hit.command.right_mps, 0.4, 1e-12);
}

// A wall ahead closer than the full-speed stopping reach: the robot slows or
// turns, its command clear of the wall.
TEST(DynamicWindowTest, WallAheadSlowsOrTurns) {
  const DynamicWindowOptions o = RoboxOptions();
  DynamicWindow dwa(o, Octagon());
  std::vector<Eigen::Vector2d> wall;
  for (double y = -2.0; y <= 2.0; y += 0.02) wall.emplace_back(0.6, y);
  DwaGoal goal;
  goal.target_in_robot = {5.0, 0.0};
  const WheelVelocity current{0.6, 0.6};
  const DwaResult r = dwa.Choose(current, wall, goal);
  ASSERT_TRUE(r.admissible_found);
  EXPECT_GT(dwa.StoppingArc(current), 0.6 - kFlat_m - o.safety_margin_m);
  EXPECT_FALSE(r.command.left_mps == 0.6 && r.command.right_mps == 0.6);
  EXPECT_FALSE(SweptOctagonTouches(o, r.command, wall));
  EXPECT_GT(r.points_in_reach, 0);
  EXPECT_LT(r.time_to_collision_s, o.ttc_horizon_s);
}

// The same inputs give the same command; the drawn arc follows it.
TEST(DynamicWindowTest, DeterministicAndArcFollowsCommand) {
  DynamicWindow a(RoboxOptions(), Octagon());
  DynamicWindow b(RoboxOptions(), Octagon());
  core::RandomStream rng(14, 5);
  const std::vector<Eigen::Vector2d> points = RandomScene(rng);
  DwaGoal goal;
  goal.target_in_robot = {3.0, 1.0};
  const DwaResult ra = a.Choose({0.3, 0.35}, points, goal);
  const DwaResult rb = b.Choose({0.3, 0.35}, points, goal);
  EXPECT_EQ(ra.command.left_mps, rb.command.left_mps);
  EXPECT_EQ(ra.command.right_mps, rb.command.right_mps);
  const std::vector<Eigen::Vector2d> arc = a.ChosenArc(ra, 1.0);
  ASSERT_EQ(arc.size(), 21u);
  EXPECT_EQ(arc.front(), Eigen::Vector2d::Zero());
  const Eigen::Vector3d end = PoseAfter(
      TwistFromWheels(ra.command.left_mps, ra.command.right_mps, RoboxOptions().wheelbase_m), 1.0);
  EXPECT_NEAR((arc.back() - end.head<2>()).norm(), 0.0, 1e-12);
}

// Bad options name the field; a clockwise polygon and a too short look-ahead are refused.
TEST(DynamicWindowTest, RejectsBadOptions) {
  auto message = [](DynamicWindowOptions o) {
    try {
      o.Validate();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  DynamicWindowOptions o;
  o.samples_per_wheel = 12;
  EXPECT_NE(message(o).find("samples_per_wheel"), std::string::npos);
  o = {};
  o.max_speed_mps = 2.0;
  EXPECT_NE(message(o).find("max_speed_mps"), std::string::npos);
  o = {};
  o.weight_heading = o.weight_speed = o.weight_clearance = 0.0;
  EXPECT_NE(message(o).find("weight_"), std::string::npos);
  EXPECT_EQ(message(DynamicWindowOptions{}), "");
  core::Polygon2 clockwise = Octagon();
  std::reverse(clockwise.begin(), clockwise.end());
  EXPECT_THROW(DynamicWindow(RoboxOptions(), clockwise), std::invalid_argument);
  o = RoboxOptions();
  o.lookahead_m = 0.2;
  EXPECT_THROW(DynamicWindow(o, Octagon()), std::invalid_argument);
  DynamicWindow dwa(RoboxOptions(), Octagon());
  EXPECT_THROW(dwa.Choose({std::nan(""), 0.0}, {}, DwaGoal{}), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::nav
