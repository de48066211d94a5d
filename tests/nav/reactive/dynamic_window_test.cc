// The dynamic window in wheel-speed space (nav/reactive/dynamic_window.h):
// safety against the exact swept octagon, progress, limits, goal poses.
#include "nav/reactive/dynamic_window.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/geometry/polygon.h"
#include "core/odometry/diff_drive.h"
#include "core/random/random_stream.h"
#include "core/types/pose2.h"
#include "nav/reactive/swept_polygon.h"
#include "tests/support/pygmalion_outline.h"

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

// A slot 0.76 m wide, closed 5 cm before the front: the octagon (0.68 m
// across its flats, 0.73 m across its corners) cannot turn in it, and the
// table's cells leave it no straight motion faster than a crawl (2 cm more
// than the margin on each side is within a cell diagonal). Told to reverse
// towards a point behind with the exact geometry, it backs straight out;
// without `reverse` it cannot turn to face the point, and with the table it
// crawls.
double BackOutOfASlot(bool reverse, bool exact) {
  const DynamicWindowOptions o = RoboxOptions();
  DynamicWindow dwa(o, Octagon());
  std::vector<Eigen::Vector2d> walls;
  for (double x = -3.0; x <= 0.39; x += 0.02) {
    walls.emplace_back(x, 0.38);
    walls.emplace_back(x, -0.38);
  }
  for (double y = -0.38; y <= 0.38; y += 0.02) walls.emplace_back(0.39, y);
  core::Pose2 pose;
  WheelVelocity w;
  std::vector<Eigen::Vector2d> in_robot;
  for (int k = 0; k < 50; ++k) {  // 5 s
    in_robot.clear();
    for (const Eigen::Vector2d& p : walls) in_robot.push_back(InRobot(pose, p));
    DwaGoal goal;
    goal.target_in_robot = InRobot(pose, {-3.0, 0.0});
    goal.reverse = reverse;
    goal.exact_clearance = exact;
    goal.speed_limit_mps = 0.3;
    const DwaResult r = dwa.Choose(w, in_robot, goal);
    EXPECT_FALSE(SweptOctagonTouches(o, r.command, in_robot)) << k;
    w = r.command;
    pose = Drive(pose, w, o);
  }
  EXPECT_LT(std::abs(pose.theta_rad), 5.0 * kDeg);
  return pose.x_m;
}

TEST(DynamicWindowTest, BacksOutOfASlotItCannotTurnIn) {
  EXPECT_LT(BackOutOfASlot(/*reverse=*/true, /*exact=*/true), -1.0);  // up to 0.3 m/s, 5 s
  EXPECT_GT(BackOutOfASlot(/*reverse=*/false, /*exact=*/true), -0.2);
  EXPECT_GT(BackOutOfASlot(/*reverse=*/true, /*exact=*/false), -0.3);
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

// Signed Euclidean distance from the point to the exact octagon: the
// distance to the nearest edge outside, minus the depth inside.
double OctagonSignedDistance(const core::Polygon2& octagon, const Eigen::Vector2d& p) {
  double nearest_m = 1e9;
  double depth_m = 1e9;
  for (std::size_t i = 0; i < octagon.size(); ++i) {
    const Eigen::Vector2d a = octagon[i];
    const Eigen::Vector2d d = octagon[(i + 1) % octagon.size()] - a;
    const double s = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    nearest_m = std::min(nearest_m, (p - a - s * d).norm());
    depth_m = std::min(depth_m, (a - p).dot(Eigen::Vector2d(d.y(), -d.x()).normalized()));
  }
  return depth_m > 0.0 ? -depth_m : nearest_m;
}

// A person-like ring of points (radius 0.15-0.25 m, 2 cm spacing) touching
// the front of the octagon at a random bearing within ±67.5° (the front flat,
// the front diagonals and their corners): its nearest point is `gap_m` from
// the octagon (negative: that deep inside it).
std::vector<Eigen::Vector2d> PersonTouchingFront(core::RandomStream& rng, double gap_m,
                                                 double* bearing_rad) {
  const core::Polygon2 octagon = Octagon();
  *bearing_rad = rng.Uniform(-67.5 * kDeg, 67.5 * kDeg);
  const Eigen::Vector2d u(std::cos(*bearing_rad), std::sin(*bearing_rad));
  const double radius_m = rng.Uniform(0.15, 0.25);
  double lo_m = kCorner_m, hi_m = 2.0;  // the centre's range along u: bisect
  for (int k = 0; k < 100; ++k) {
    const double mid_m = 0.5 * (lo_m + hi_m);
    (OctagonSignedDistance(octagon, mid_m * u) < radius_m + gap_m ? lo_m : hi_m) = mid_m;
  }
  const Eigen::Vector2d centre = lo_m * u;
  // Start the ring at the point nearest to the octagon.
  double best_m = 1e9, start_rad = 0.0;
  auto search = [&](double from_rad, double to_rad, double step_rad) {
    for (double a = from_rad; a < to_rad; a += step_rad) {
      const Eigen::Vector2d p = centre + radius_m * Eigen::Vector2d(std::cos(a), std::sin(a));
      const double d_m = OctagonSignedDistance(octagon, p);
      if (d_m < best_m) best_m = d_m, start_rad = a;
    }
  };
  search(0.0, 2.0 * kPi, 1e-3);
  search(start_rad - 1e-3, start_rad + 1e-3, 1e-6);
  std::vector<Eigen::Vector2d> ring;
  for (double b = 0.0; b < 2.0 * kPi - 1e-9; b += 0.02 / radius_m) {
    ring.push_back(centre +
                   radius_m * Eigen::Vector2d(std::cos(start_rad + b), std::sin(start_rad + b)));
  }
  // Inside the octagon the circle's depth is not dist(centre) - radius:
  // slide the ring along u until its deepest point is exactly gap_m.
  for (int k = 0; k < 50; ++k) {
    double nearest_m = 1e9;
    for (const Eigen::Vector2d& p : ring)
      nearest_m = std::min(nearest_m, OctagonSignedDistance(octagon, p));
    for (Eigen::Vector2d& p : ring) p += (gap_m - nearest_m) * u;
  }
  return ring;
}

// Over the command held one period, then braked proportionally (the window's
// model), for `duration_s`: the largest drop (m) of any point's signed
// distance to the exact octagon below its value now, and the smallest
// distance at the end.
struct ClearanceChange {
  double worst_drop_m = 0.0;
  double start_min_m = 0.0;
  double end_min_m = 0.0;
};
ClearanceChange SweepClearance(const DynamicWindowOptions& o, const WheelVelocity& command,
                               const std::vector<Eigen::Vector2d>& points, double duration_s) {
  constexpr double kDt_s = 1e-3;
  const core::Polygon2 octagon = Octagon();
  const double peak = std::max(std::abs(command.left_mps), std::abs(command.right_mps));
  const double brake_s = peak / o.max_wheel_accel_mps2;
  std::vector<double> start;
  ClearanceChange change;
  change.start_min_m = 1e9;
  for (const Eigen::Vector2d& p : points) {
    start.push_back(OctagonSignedDistance(octagon, p));
    change.start_min_m = std::min(change.start_min_m, start.back());
  }
  core::Pose2 pose;
  for (double t = 0.0; t < duration_s; t += kDt_s) {
    const double mid_s = t + 0.5 * kDt_s;
    const double scale =
        mid_s <= o.period_s ? 1.0 : std::max(0.0, 1.0 - (mid_s - o.period_s) / brake_s);
    pose = core::DiffDriveStep(
        pose, {command.left_mps * scale * kDt_s, command.right_mps * scale * kDt_s}, o.wheelbase_m);
    change.end_min_m = 1e9;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double d_m = OctagonSignedDistance(octagon, pose.Inverse() * points[i]);
      change.worst_drop_m = std::max(change.worst_drop_m, start[i] - d_m);
      change.end_min_m = std::min(change.end_min_m, d_m);
    }
  }
  return change;
}

// The tolerance of the escape tests: the window lets a contact point get
// kContactSlack_m deeper (mitred), the mitred and Euclidean distances differ
// near corners; 1 mm bounds both for points within the 2 cm margin.
constexpr double kEscapeDrop_m = 1e-3;

// Runs `scenes` stalled robots touched at the front by a person `gap_m` from
// the octagon, with the target behind or beside: every command moves, no
// point's distance drops by more than kEscapeDrop_m within 0.5 s, and the
// clearance grows by twice that.
void ExpectEscapes(double gap_m, std::uint64_t stream, bool expect_collision) {
  const DynamicWindowOptions o = RoboxOptions();
  DynamicWindow dwa(o, Octagon());
  core::RandomStream rng(14, stream);
  constexpr int kScenes = 250;
  // Twice the drop tolerance, a seventh of the straight-back stopping travel
  // from standstill (1.5 cm); stopping gains 0, turning on the spot <= 0.
  const double min_gain_m = 2.0 * kEscapeDrop_m;
  double smallest_gain_m = 1e9;
  for (int scene = 0; scene < kScenes; ++scene) {
    double bearing_rad = 0.0;
    const std::vector<Eigen::Vector2d> person = PersonTouchingFront(rng, gap_m, &bearing_rad);
    DwaGoal goal;
    const double target_rad = bearing_rad + kPi + rng.Uniform(-0.5 * kPi, 0.5 * kPi);
    goal.target_in_robot =
        rng.Uniform(1.0, 3.0) * Eigen::Vector2d(std::cos(target_rad), std::sin(target_rad));
    const DwaResult r = dwa.Choose({}, person, goal);
    ASSERT_TRUE(r.admissible_found) << "scene " << scene;
    EXPECT_GT(r.contact_points, 0);
    if (expect_collision) {
      EXPECT_TRUE(r.in_collision) << "scene " << scene;
    }
    EXPECT_FALSE(r.command.left_mps == 0.0 && r.command.right_mps == 0.0) << "scene " << scene;
    const ClearanceChange change = SweepClearance(o, r.command, person, 0.5);
    EXPECT_NEAR(change.start_min_m, gap_m, 1e-6);
    EXPECT_LE(change.worst_drop_m, kEscapeDrop_m) << "scene " << scene;
    EXPECT_GE(change.end_min_m - change.start_min_m, min_gain_m) << "scene " << scene;
    smallest_gain_m = std::min(smallest_gain_m, change.end_min_m - change.start_min_m);
  }
  ::testing::Test::RecordProperty("smallest_gain_mm", std::to_string(1e3 * smallest_gain_m));
}

// A person touching the front (0-1 cm from the octagon) of a stopped robot:
// it backs or turns away, increasing the clearance, over 250 seeded scenes.
TEST(DynamicWindowTest, EscapesFromPersonTouchingFront) {
  core::RandomStream gaps(14, 6);
  for (int k = 0; k < 5; ++k) ExpectEscapes(gaps.Uniform(0.0, 0.01), 7 + k, false);
  ExpectEscapes(0.0, 12, false);
}

// The same with the nearest point 2 mm inside the polygon: in_collision is
// reported, yet the robot escapes instead of braking.
TEST(DynamicWindowTest, EscapesFromPointInsidePolygon) { ExpectEscapes(-0.002, 13, true); }

// Boxed in on all sides at 1 cm (square walls beside the flats, and an
// octagonal ring 1 cm outside every edge): from standstill stop is the only
// admissible command; creeping forward, the robot brakes to standstill.
TEST(DynamicWindowTest, StopsWhenBoxedInAtOneCentimetre) {
  const DynamicWindowOptions o = RoboxOptions();
  DynamicWindow dwa(o, Octagon());
  const double wall_m = kFlat_m + 0.01;
  std::vector<Eigen::Vector2d> square;
  for (double s = -wall_m; s <= wall_m + 1e-9; s += 0.01) {
    square.insert(square.end(), {{wall_m, s}, {-wall_m, s}, {s, wall_m}, {s, -wall_m}});
  }
  const core::Polygon2 ring_corners = InflateConvexPolygon(Octagon(), 0.01);
  std::vector<Eigen::Vector2d> ring;
  for (std::size_t i = 0; i < ring_corners.size(); ++i) {
    const Eigen::Vector2d a = ring_corners[i];
    const Eigen::Vector2d b = ring_corners[(i + 1) % ring_corners.size()];
    for (double s = 0.0; s < 1.0; s += 0.05) ring.push_back(a + s * (b - a));
  }
  DwaGoal goal;
  goal.target_in_robot = {-2.0, 1.0};
  for (const std::vector<Eigen::Vector2d>* box : {&square, &ring}) {
    for (const WheelVelocity current : {WheelVelocity{}, WheelVelocity{0.05, 0.05}}) {
      const DwaResult r = dwa.Choose(current, *box, goal);
      EXPECT_EQ(r.admissible_found, current.left_mps == 0.0);
      EXPECT_FALSE(r.in_collision);
      EXPECT_GT(r.contact_points, 0);
      EXPECT_LE(r.candidates_admissible, 1);
      EXPECT_EQ(r.command.left_mps, 0.0);
      EXPECT_EQ(r.command.right_mps, 0.0);
    }
  }
}

// Crawling at a grid speed, the window's standstill sample is exactly zero —
// summed from the window's edges it came out as 1e-17 m/s, a "move" that
// scored the full clearance stopping never gets — so a robot in a passage
// 5 cm wider than it on each side, a post half across it 4 cm ahead and its
// target straight ahead, moves (it backs off the post to find room) instead
// of standing still (two deadlocked Robox stood so for minutes).
TEST(DynamicWindowTest, MovesOffAPostAheadFromACrawl) {
  const DynamicWindowOptions o = RoboxOptions();
  DynamicWindow dwa(o, Octagon());
  std::vector<Eigen::Vector2d> post;
  for (double x = -1.0; x <= 1.5; x += 0.02) {
    post.emplace_back(x, kFlat_m + 0.05);
    post.emplace_back(x, -kFlat_m - 0.05);
  }
  for (double y = -kFlat_m - 0.05; y <= -0.05; y += 0.02) post.emplace_back(kFlat_m + 0.04, y);
  DwaGoal goal;
  goal.target_in_robot = {1.5, 0.0};
  for (const double crawl_mps : {-0.06, -0.04, -0.02, 0.02, 0.04, 0.06, 0.08}) {
    const DwaResult r = dwa.Choose({crawl_mps, crawl_mps}, post, goal);
    ASSERT_TRUE(r.admissible_found) << crawl_mps;
    for (const double w : {r.command.left_mps, r.command.right_mps}) {
      EXPECT_TRUE(w == 0.0 || std::abs(w) >= 1e-6) << crawl_mps << " " << w;
    }
    EXPECT_GT(std::max(std::abs(r.command.left_mps), std::abs(r.command.right_mps)), 0.01)
        << crawl_mps;
    EXPECT_FALSE(SweptOctagonTouches(o, r.command, post)) << crawl_mps;
  }
}

// A hull whose side is two facets 1.4° apart (as a mesh hull's is), pressed
// along that side — bumper contacts 1 mm inside both facets — and at the
// front-right corner: forward and turning press in, and backing slides along
// the side (its rate is within kSlideSlope of tangential). The robot backs
// out instead of freezing, and no contact gets more than 1 mm deeper.
TEST(DynamicWindowTest, BacksAlongAContactOnAFacetedSide) {
  const DynamicWindowOptions o = RoboxOptions();
  core::Polygon2 faceted = Octagon();
  // Octagon() starts at +22.5°: vertices 5 and 6 bound the right flat (y = -kFlat_m).
  faceted.insert(faceted.begin() + 6, Eigen::Vector2d(0.0, -kFlat_m - 0.0035));
  DynamicWindow dwa(o, faceted);
  std::vector<Eigen::Vector2d> contacts;
  for (const double x : {-0.07, 0.07}) {
    // 1 mm inside the facet from (±0.14, -kFlat_m) to (0, -kFlat_m - 3.5 mm).
    const double facet_y =
        -kFlat_m - 0.0035 * (1.0 - std::abs(x) / (kCorner_m * std::sin(kPi / 8.0)));
    contacts.emplace_back(x, facet_y + 0.001);
  }
  const Eigen::Vector2d diagonal(std::cos(-kPi / 4.0), std::sin(-kPi / 4.0));
  const Eigen::Vector2d along(diagonal.y(), -diagonal.x());
  for (const double s : {-0.05, 0.0, 0.05}) {
    contacts.push_back((kFlat_m - 0.001) * diagonal + s * along);
  }
  DwaGoal goal;
  goal.target_in_robot = {1.5, -0.2};
  const DwaResult r = dwa.Choose({}, contacts, goal);
  ASSERT_TRUE(r.admissible_found);
  EXPECT_EQ(r.contact_points, 5);
  EXPECT_LT(r.command.left_mps + r.command.right_mps, 0.0);  // backs
  const ClearanceChange change = SweepClearance(o, r.command, contacts, 0.5);
  EXPECT_LE(change.worst_drop_m, kEscapeDrop_m);
}

// Pygmalion's outline (wheel hubs bulging 4 cm on the wheel axis) with a
// door post's barrier row 1.8-1.9 cm beside its left hub, straddling it, as
// in office_08's door (computer2000 seed 1): within the 2 cm margin every
// motion brings one of the two points nearer, so only standing is
// admissible. With the margin cut to 5 mm for the cycle (an escape's creep)
// the window backs straight away, never nearer than that to either point.
TEST(DynamicWindowTest, CreepsPastAPostBesideAHubWithAReducedMargin) {
  DynamicWindowOptions o;
  o.wheelbase_m = 0.38;
  o.max_speed_mps = 0.4;
  const core::Polygon2 hubbed = {{-0.225, -0.225}, {0.0, -0.2665}, {0.225, -0.225},
                                 {0.225, 0.225},   {0.0, 0.2665},  {-0.225, 0.225}};
  DynamicWindow dwa(o, hubbed);
  const std::vector<Eigen::Vector2d> post = {{0.0092, 0.2835}, {-0.0061, 0.2846}};
  DwaGoal goal;
  goal.reverse = true;
  goal.target_in_robot = {-1.0, 0.0};
  goal.speed_limit_mps = 0.05;
  goal.exact_clearance = true;
  const DwaResult held = dwa.Choose({}, post, goal);
  EXPECT_EQ(held.contact_points, 2);
  EXPECT_EQ(held.candidates_admissible, 1);  // standing
  EXPECT_EQ(held.command.left_mps, 0.0);
  EXPECT_EQ(held.command.right_mps, 0.0);
  goal.margin_m = 0.005;
  const DwaResult creep = dwa.Choose({}, post, goal);
  ASSERT_TRUE(creep.admissible_found);
  EXPECT_EQ(creep.contact_points, 0);
  EXPECT_LT(creep.command.left_mps, 0.0);
  EXPECT_LT(creep.command.right_mps, 0.0);
  // Held one period and braked: 5 mm of the margin kept from both points.
  core::Pose2 pose;
  double nearest_m = 1e9;
  for (double t = 0.0; t < 0.3; t += 1e-3) {
    const double scale = t < o.period_s ? 1.0 : 0.0;
    pose = core::DiffDriveStep(
        pose, {creep.command.left_mps * scale * 1e-3, creep.command.right_mps * scale * 1e-3},
        o.wheelbase_m);
    for (const Eigen::Vector2d& p : post) {
      Eigen::Vector2d normal;
      nearest_m = std::min(nearest_m, SignedDistance(hubbed, pose.Inverse() * p, &normal));
    }
  }
  EXPECT_GT(nearest_m, 0.005);
  // The reduced margin needs the exact geometry and may not exceed the options'.
  goal.exact_clearance = false;
  EXPECT_THROW(dwa.Choose({}, post, goal), std::invalid_argument);
  goal.exact_clearance = true;
  goal.margin_m = 0.03;
  EXPECT_THROW(dwa.Choose({}, post, goal), std::invalid_argument);
}

// Where Pygmalion stood for 18 hours (computer2000 seed 1, office_09's door,
// 34,030 s, the robot's frame): a door post's face cuts up to 1.7 cm into
// the right hub, its points on both sides of the wheel axis. Every motion the
// drive allows first takes one of them deeper, by about a millimetre, so the
// sliding test admits only standing, even with no margin. With
// the creep's 4 mm contact slack the window creeps forward, the way the face
// recedes from the hub, and no point gets more than that deeper.
TEST(DynamicWindowTest, CreepsOffAPostCornerPressingAHubWithAContactSlack) {
  DynamicWindowOptions o;
  o.wheelbase_m = 0.38;
  o.max_speed_mps = 0.4;
  const core::Polygon2 outline = pavilion::testing::PygmalionWheeledOutline();
  DynamicWindow dwa(o, outline);
  const std::vector<Eigen::Vector2d> post = {{-0.021, -0.248}, {-0.007, -0.248}, {0.004, -0.261},
                                             {0.016, -0.259},  {0.039, -0.269},  {0.062, -0.280}};
  DwaGoal goal;
  goal.target_in_robot = {1.0, 0.0};
  goal.speed_limit_mps = 0.05;
  goal.exact_clearance = true;
  goal.margin_m = 0.0;
  const DwaResult held = dwa.Choose({}, post, goal);
  EXPECT_TRUE(held.in_collision);
  EXPECT_EQ(held.command.left_mps, 0.0);
  EXPECT_EQ(held.command.right_mps, 0.0);
  goal.contact_slack_m = 0.004;
  const DwaResult creep = dwa.Choose({}, post, goal);
  ASSERT_TRUE(creep.admissible_found);
  EXPECT_GT(creep.command.left_mps + creep.command.right_mps, 0.0);
  // Held one period and braked: no point more than the slack deeper.
  std::vector<double> start;
  Eigen::Vector2d normal;
  for (const Eigen::Vector2d& p : post) start.push_back(SignedDistance(outline, p, &normal));
  core::Pose2 pose;
  double worst_m = 0.0;
  for (double t = 0.0; t < 0.3; t += 1e-3) {
    const double scale = t < o.period_s ? 1.0 : 0.0;
    pose = core::DiffDriveStep(
        pose, {creep.command.left_mps * scale * 1e-3, creep.command.right_mps * scale * 1e-3},
        o.wheelbase_m);
    for (std::size_t i = 0; i < post.size(); ++i) {
      worst_m =
          std::max(worst_m, start[i] - SignedDistance(outline, pose.Inverse() * post[i], &normal));
    }
  }
  EXPECT_LE(worst_m, 0.004 + 1e-4);
  goal.contact_slack_m = 0.006;  // beyond kMaxContactSlack_m
  EXPECT_THROW(dwa.Choose({}, post, goal), std::invalid_argument);
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

// The speed controller's step: towards the command by at most the step on
// either wheel, both in proportion (the same straight line in (v_l, v_r)),
// and exactly onto it once within reach.
TEST(RampTowards, MovesBothWheelsInProportionAndStopsOnTheCommand) {
  const WheelVelocity a = RampTowards({0.0, 0.0}, {0.5, 0.25}, 0.1);
  EXPECT_DOUBLE_EQ(a.left_mps, 0.1);
  EXPECT_DOUBLE_EQ(a.right_mps, 0.05);
  const WheelVelocity b = RampTowards({0.4, -0.4}, {0.0, 0.0}, 0.1);  // braking a turn
  EXPECT_DOUBLE_EQ(b.left_mps, 0.3);
  EXPECT_DOUBLE_EQ(b.right_mps, -0.3);
  const WheelVelocity c = RampTowards({0.45, 0.2}, {0.5, 0.25}, 0.1);
  EXPECT_EQ(c.left_mps, 0.5);
  EXPECT_EQ(c.right_mps, 0.25);
  // Twenty steps of 5 ms at 1 m/s² reach anything the 10 Hz window allows.
  WheelVelocity v{0.3, 0.3};
  for (int k = 0; k < 20; ++k) v = RampTowards(v, {0.2, 0.4}, 1.0 * 0.005);
  EXPECT_EQ(v.left_mps, 0.2);
  EXPECT_EQ(v.right_mps, 0.4);
}

}  // namespace
}  // namespace pavilion::nav
