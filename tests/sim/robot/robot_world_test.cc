// The articulated robot model in the Bullet world: motors, wheel angles,
// systematic errors, slip under pushes, contacts, rays and sections.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>

#include "core/odometry/diff_drive.h"
#include "core/random/random_stream.h"
#include "sim/world/world.h"
#include "tests/support/world_robot.h"

namespace pavilion::sim {
namespace {

constexpr double kPi = std::numbers::pi;

// A 40 m × 40 m hall floor with one wall segment at x = 5 for bumping.
WorldDescription Hall(bool with_wall) {
  WorldDescription w;
  w.name = "hall";
  w.materials["floor"] = Material{0.8, 0.0, {0.5, 0.5, 0.5, 1}, core::LaserResponse::kNormal};
  w.materials["plastic"] = Material{0.4, 0.0, {0.2, 0.2, 0.8, 1}, core::LaserResponse::kNormal};
  w.materials["retro"] =
      Material{0.4, 0.0, {0.9, 0.9, 0.9, 1}, core::LaserResponse::kRetroReflective};
  w.floor = {{-20, -20}, {20, 20}, "floor", {}};
  if (with_wall) {
    Wall wall;
    wall.id = "wall";
    wall.points_m = {{5, -3}, {5, 3}};
    wall.thickness_m = 0.2;
    wall.height_m = 2.0;
    wall.material = "plastic";
    w.walls.push_back(wall);
  }
  return w;
}

RobotDescription TestRobot() { return pavilion::testing::PygmalionLikeModel("plastic"); }

pavilion::testing::WorldRobot Spec(const std::string& id, core::Pose2 pose) {
  pavilion::testing::WorldRobot spec;
  spec.id = id;
  spec.model = TestRobot();
  spec.pose = pose;
  return spec;
}

// Dead reckoning from the true wheel angles with the nominal model.
struct Odometer {
  core::Pose2 pose;
  double last_left = 0.0;
  double last_right = 0.0;
  void Update(const RobotState& s, const RobotDescription& m) {
    const core::WheelTravel travel{(s.left_wheel_rad - last_left) * m.left_wheel.radius_m,
                                   (s.right_wheel_rad - last_right) * m.right_wheel.radius_m};
    pose = core::DiffDriveStep(pose, travel, m.wheelbase_m());
    last_left = s.left_wheel_rad;
    last_right = s.right_wheel_rad;
  }
};

void Advance(World* world, int robot, double seconds, Odometer* odo) {
  const int steps = static_cast<int>(std::lround(seconds / world->step_s()));
  for (int i = 0; i < steps; ++i) {
    world->Step();
    if (odo != nullptr) odo->Update(world->robot_state(robot), world->robot_model(robot));
  }
}

TEST(RobotWorld, RestsOnItsWheelsAndCastersUpright) {
  World world(Hall(false), WorldOptions{});
  const int r = pavilion::testing::AddRobot(world, Spec("r", {1, 2, 0.5}));
  Advance(&world, r, 2.0, nullptr);
  const RobotState s = world.robot_state(r);
  EXPECT_NEAR(s.pose.x_m, 1.0, 2e-3);
  EXPECT_NEAR(s.pose.y_m, 2.0, 2e-3);
  EXPECT_NEAR(s.pose.theta_rad, 0.5, 2e-3);
  EXPECT_LT(s.tilt_rad, 0.02);
  EXPECT_NEAR(s.left_wheel_rad, 0.0, 0.02);
}

TEST(RobotWorld, ForwardWheelSpeedsDriveForwardAndRampAtTheAccelerationLimit) {
  World world(Hall(false), WorldOptions{});
  const int r = pavilion::testing::AddRobot(world, Spec("r", {0, 0, 0}));
  world.SetWheelSpeeds(r, 5.0, 5.0);
  Advance(&world, r, 0.5, nullptr);  // ramp at 10 rad/s² to 5 rad/s: ½·α·t² = 1.25 rad
  // The hinge motor is a soft constraint and lags the ramp by a few steps.
  EXPECT_NEAR(world.robot_state(r).left_wheel_rad, 1.25, 0.1);
  EXPECT_NEAR(world.robot_state(r).right_wheel_rad, 1.25, 0.1);
  Advance(&world, r, 1.5, nullptr);
  const RobotState s = world.robot_state(r);
  EXPECT_NEAR(s.left_wheel_radps, 5.0, 0.05);
  EXPECT_NEAR(s.right_wheel_radps, 5.0, 0.05);
  EXPECT_GT(s.left_wheel_rad, 0.0);
  // Ramp 0.5 s covers 1.25 rad, then 1.5 s at 5 rad/s: 8.75 rad of 9 cm wheels.
  EXPECT_NEAR(s.pose.x_m, 8.75 * 0.09, 0.03);
  EXPECT_NEAR(s.velocity_mps.x(), 0.45, 0.01);
  EXPECT_NEAR(s.pose.y_m, 0.0, 0.01);
}

TEST(RobotWorld, OppositeWheelSpeedsTurnCounterClockwise) {
  World world(Hall(false), WorldOptions{});
  const int r = pavilion::testing::AddRobot(world, Spec("r", {0, 0, 0}));
  world.SetWheelSpeeds(r, -2.0, 2.0);
  Advance(&world, r, 1.0, nullptr);
  const RobotState s = world.robot_state(r);
  EXPECT_GT(s.yaw_rate_radps, 0.0);
  EXPECT_NEAR(s.yaw_rate_radps, 2.0 * 0.09 * 2 / 0.4, 0.05);  // (v_r − v_l) / b
  EXPECT_NEAR(std::hypot(s.pose.x_m, s.pose.y_m), 0.0, 0.01);
}

TEST(RobotWorld, TenMetreStraightDriveOdometryWithinHalfAPercent) {
  World world(Hall(false), WorldOptions{});
  const int r = pavilion::testing::AddRobot(world, Spec("r", {-5, 0, 0}));
  Odometer odo{{-5, 0, 0}};
  world.SetWheelSpeeds(r, 0.5 / 0.09, 0.5 / 0.09);  // 0.5 m/s
  for (int i = 0; i < 6000 && world.robot_state(r).pose.x_m < 5.0; ++i) {
    world.Step();
    odo.Update(world.robot_state(r), world.robot_model(r));
  }
  const RobotState s = world.robot_state(r);
  const double travelled = std::hypot(s.pose.x_m + 5, s.pose.y_m);
  ASSERT_GT(travelled, 9.99);
  const double error = std::hypot(odo.pose.x_m - s.pose.x_m, odo.pose.y_m - s.pose.y_m);
  EXPECT_LT(error, 0.005 * travelled);
  EXPECT_NEAR(odo.pose.theta_rad, s.pose.theta_rad, 0.005);
}

// With the physical wheelbase b·f and the nominal b in the odometry, a turn of
// true angle Δθ = (s_r − s_l)/(b·f) is read as (s_r − s_l)/b = f·Δθ (eq. 2.7).
// Spins in place and returns the true (unwrapped) and the odometry's heading change.
std::pair<double, double> SpinHeadings(double wheelbase_factor) {
  World world(Hall(false), WorldOptions{});
  pavilion::testing::WorldRobot spec = Spec("r", {0, 0, 0});
  spec.systematic.wheelbase_factor = wheelbase_factor;
  const int r = pavilion::testing::AddRobot(world, spec);
  Odometer odo;
  world.SetWheelSpeeds(r, -1.5, 1.5);
  double unwrapped_true = 0.0, unwrapped_odo = 0.0;
  double last_true = 0.0, last_odo = 0.0;
  for (int i = 0; i < 2400; ++i) {  // 12 s at ≈ 0.66 rad/s: 1.25 turns
    world.Step();
    odo.Update(world.robot_state(r), spec.model);
    const double theta = world.robot_state(r).pose.theta_rad;
    unwrapped_true += std::remainder(theta - last_true, 2 * kPi);
    unwrapped_odo += std::remainder(odo.pose.theta_rad - last_odo, 2 * kPi);
    last_true = theta;
    last_odo = odo.pose.theta_rad;
  }
  return {unwrapped_true, unwrapped_odo};
}

TEST(RobotWorld, WheelbaseErrorTurnsOdometryHeadingByTheKinematicFactor) {
  const auto [true_nominal, odo_nominal] = SpinHeadings(1.0);
  const auto [true_wide, odo_wide] = SpinHeadings(1.03);
  ASSERT_GT(true_wide, 2 * kPi);
  // Without the error, the odometry follows the spin up to the wheels' scrub.
  const double scrub = odo_nominal / true_nominal;
  EXPECT_NEAR(scrub, 1.0, 0.01);
  // With it, the odometry over-reads the turn by the factor.
  EXPECT_NEAR(odo_wide / true_wide, 1.03 * scrub, 0.003);
}

TEST(RobotWorld, WheelRadiusRatioCurvesAStraightCommand) {
  World world(Hall(false), WorldOptions{});
  pavilion::testing::WorldRobot spec = Spec("r", {0, 0, 0});
  spec.systematic.wheel_radius_ratio = 1.01;  // right wheel 1 % larger: veers left
  const int r = pavilion::testing::AddRobot(world, spec);
  Odometer odo;
  world.SetWheelSpeeds(r, 5.0, 5.0);
  Advance(&world, r, 5.0, &odo);
  const RobotState s = world.robot_state(r);
  // Equal wheel speeds: Δθ = (r_R − r_L)·φ / b with mean radius kept.
  const double r_left = 2 * 0.09 / 2.01, r_right = 1.01 * r_left;
  const double expected = (r_right - r_left) * s.left_wheel_rad / 0.4;
  EXPECT_NEAR(s.pose.theta_rad, expected, 0.1 * expected);
  EXPECT_NEAR(odo.pose.theta_rad, 0.0, 1e-3);  // the odometry believes it went straight
}

TEST(RobotWorld, SidewaysPushSlipsUnseenByTheWheels) {
  World world(Hall(false), WorldOptions{});
  const int r = pavilion::testing::AddRobot(world, Spec("r", {0, 0, 0}));
  Advance(&world, r, 0.5, nullptr);
  Odometer odo;
  const RobotState before = world.robot_state(r);
  odo.pose = before.pose;
  odo.last_left = before.left_wheel_rad;
  odo.last_right = before.right_wheel_rad;
  world.ApplyRobotImpulse(r, {0.0, 80.0});  // 80 N·s on ≈ 53 kg: 1.5 m/s sideways
  Advance(&world, r, 2.0, &odo);
  const RobotState after = world.robot_state(r);
  const double moved = (after.pose.translation() - before.pose.translation()).norm();
  const double seen = (odo.pose.translation() - before.pose.translation()).norm();
  EXPECT_GT(moved, 0.05);
  EXPECT_LT(seen, 0.1 * moved);
}

// A 70 kg walker that keeps walking at 1.34 m/s into the side of a robot
// standing on its motors: driven by the social force model's driving term
// m (v0 - v) / tau (tau 0.5 s: at most ~190 N) it jolts the robot when it
// walks into it, then cannot move it on, the wheels' lateral friction
// holding twice that; a body that holds its velocity against any force
// (tau = 0, a motorized cart) bulldozes it. The robot's displacement over
// the last 2 s of 4 s of pushing.
double RobotDisplacementByWalker(double drive_relaxation_s) {
  World world(Hall(false), WorldOptions{});
  const int r = pavilion::testing::AddRobot(world, Spec("r", {0, 0, 0}));
  BodySpec walker;
  walker.id = "walker";
  walker.shape.type = BodyShapeType::kCylinder;
  walker.shape.radius_m = 0.22;
  walker.shape.height_m = 1.7;
  walker.mass_kg = 70.0;
  walker.pose = {0.0, -1.2, 0.5 * kPi};
  walker.material = "plastic";
  walker.driven = true;
  walker.drive_relaxation_s = drive_relaxation_s;
  const int w = world.AddBody(walker);
  Advance(&world, r, 0.5, nullptr);
  world.SetPlanarVelocity(w, {0.0, 1.34}, 0.0);  // towards the robot's side, and on
  Advance(&world, r, 2.0, nullptr);
  const core::Pose2 before = world.robot_state(r).pose;
  Advance(&world, r, 2.0, nullptr);
  return (world.robot_state(r).pose.translation() - before.translation()).norm();
}

TEST(RobotWorld, AWalkerWithAPersonsForceDoesNotBulldozeARobot) {
  const double walker_m = RobotDisplacementByWalker(0.5);
  const double cart_m = RobotDisplacementByWalker(0.0);
  RecordProperty("walker_displacement_m", std::to_string(walker_m));
  RecordProperty("cart_displacement_m", std::to_string(cart_m));
  EXPECT_LT(walker_m, 0.01);
  EXPECT_GT(cart_m, 1.0);  // 2 s at 1.34 m/s: the cart carries the robot along
}

TEST(RobotWorld, ChassisContactsAreReportedInTheBaseFrame) {
  World world(Hall(true), WorldOptions{});
  const int r = pavilion::testing::AddRobot(world, Spec("r", {4.0, 0, 0}));
  world.SetWheelSpeeds(r, 4.0, 4.0);
  bool touched = false;
  for (int i = 0; i < 600 && !touched; ++i) {
    world.Step();
    for (const Eigen::Vector2d& p : world.RobotContactPoints(r)) {
      EXPECT_NEAR(p.x(), 0.225, 0.02);  // the front face
      touched = true;
    }
  }
  EXPECT_TRUE(touched);
  World free_world(Hall(false), WorldOptions{});
  const int f = pavilion::testing::AddRobot(free_world, Spec("f", {0, 0, 0}));
  Advance(&free_world, f, 0.5, nullptr);
  EXPECT_TRUE(free_world.RobotContactPoints(f).empty());  // floor and own parts excluded
}

TEST(RobotWorld, RaysSkipTheRobotsOwnPartsAndReportAttachments) {
  World world(Hall(false), WorldOptions{});
  pavilion::testing::WorldRobot a = Spec("a", {0, 0, 0});
  pavilion::testing::WorldRobot b = Spec("b", {3, 0, 0});
  b.model.markers.push_back({"marker", "", {0.0, 0.25}, 0.03, 0.2, 0.5, "retro"});
  const int ra = pavilion::testing::AddRobot(world, a);
  const int rb = pavilion::testing::AddRobot(world, b);
  Advance(&world, ra, 0.2, nullptr);
  const Eigen::Vector3d from(0, 0, 0.4);
  const RayHit hit = world.CastRay(from, {8, 0, 0.4}, world.robot_group(ra));
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.element, world.robot_element(rb));
  EXPECT_NEAR(hit.distance_m, 3 - 0.225, 2e-3);
  const RayHit own = world.CastRay(from, {8, 0, 0.4});  // not ignoring: inside own chassis
  EXPECT_TRUE(own.hit);
  const RayHit marker = world.CastRay(from, {3, 0.25, 0.4}, world.robot_group(ra));
  ASSERT_TRUE(marker.hit);
  EXPECT_EQ(world.elements()[marker.element].id, "b/marker");
  EXPECT_EQ(world.elements()[marker.element].laser, core::LaserResponse::kRetroReflective);
  const RayHit above = world.CastRay({0, 0, 0.9}, {8, 0, 0.9}, world.robot_group(ra));
  EXPECT_FALSE(above.hit);  // over the 0.7 m robot
}

TEST(RobotWorld, SectionHoldsTheFootprintAndAttachments) {
  World world(Hall(false), WorldOptions{});
  pavilion::testing::WorldRobot spec = Spec("r", {2, 1, kPi / 2});
  spec.model.markers.push_back({"marker", "", {0.0, 0.25}, 0.03, 0.2, 0.5, "retro"});
  const int r = pavilion::testing::AddRobot(world, spec);
  const core::PlanarSection section = world.SectionAt(0.4);
  int chassis_segments = 0, markers = 0;
  for (const auto& s : section.segments) chassis_segments += s.element == world.robot_element(r);
  for (const auto& c : section.circles) {
    if (section.elements[c.element].id == "r/marker") {
      ++markers;
      EXPECT_NEAR(c.center_m.x(), 2 - 0.25, 1e-6);
      EXPECT_NEAR(c.center_m.y(), 1.0, 1e-6);
    }
  }
  EXPECT_EQ(chassis_segments, 4);
  EXPECT_EQ(markers, 1);
}

TEST(RobotWorld, InconsistentModelsAreRejectedNamingTheRobot) {
  World world(Hall(false), WorldOptions{});
  pavilion::testing::WorldRobot zero_mass = Spec("heavy", {0, 0, 0});
  zero_mass.model.chassis_mass_kg = 0.0;
  EXPECT_THROW(pavilion::testing::AddRobot(world, zero_mass), std::invalid_argument);
  pavilion::testing::WorldRobot clockwise = Spec("cw", {0, 0, 0});
  std::reverse(clockwise.model.footprint_m.begin(), clockwise.model.footprint_m.end());
  EXPECT_THROW(pavilion::testing::AddRobot(world, clockwise), std::invalid_argument);
  pavilion::testing::WorldRobot swapped = Spec("swapped", {0, 0, 0});
  std::swap(swapped.model.left_wheel, swapped.model.right_wheel);
  try {
    pavilion::testing::AddRobot(world, swapped);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("robot 'swapped'"), std::string::npos);
  }
  pavilion::testing::AddRobot(world, Spec("twice", {0, 0, 0}));
  EXPECT_THROW(pavilion::testing::AddRobot(world, Spec("twice", {3, 0, 0})), std::invalid_argument);
}

// The laser's fast path (baked static mesh, exact shapes) against Bullet's
// rayTest on the physics world's primitives, on random horizontal rays among
// walls, boxes, a cylinder, a door, bodies of every shape and two robots.
TEST(RobotWorld, FastRaysAgreeWithBulletsPrimitiveRayTest) {
  WorldDescription d = Hall(true);
  d.boxes.push_back({"box", {2, 2, 0.4}, {1.0, 0.6, 1.2}, 0.0, "plastic"});
  d.cylinders.push_back({"column", {-2, 3}, 0.4, 2.0, 0.0, "plastic"});
  Door door;
  door.id = "door";
  door.hinge_m = {-3, -2};
  door.width_m = 0.9;
  door.material = "plastic";
  d.doors.push_back(door);
  const auto build = [&](bool baked) {
    WorldOptions options;
    options.baked_static_rays = baked;
    auto world = std::make_unique<World>(d, options);
    BodySpec visitor;
    visitor.id = "visitor";
    visitor.shape.radius_m = 0.25;
    visitor.pose = {1, -2, 0};
    visitor.material = "plastic";
    world->AddBody(visitor);
    BodySpec crate = visitor;
    crate.id = "crate";
    crate.shape.type = BodyShapeType::kBox;
    crate.shape.box_size_m = {0.6, 0.4, 0.8};
    crate.pose = {-1, 1, 0.5};
    world->AddBody(crate);
    BodySpec ball = visitor;
    ball.id = "ball";
    ball.shape.type = BodyShapeType::kSphere;
    ball.shape.radius_m = 0.5;
    ball.pose = {3, -1, 0};
    world->AddBody(ball);
    pavilion::testing::WorldRobot r = Spec("robot", {0, 0, 0.4});
    r.model.markers.push_back({"marker", "", {0.0, 0.25}, 0.03, 0.2, 0.5, "retro"});
    pavilion::testing::AddRobot(*world, r);
    pavilion::testing::AddRobot(*world, Spec("other", {-2, -1, 2.0}));
    for (int i = 0; i < 40; ++i) world->Step();
    return world;
  };
  const auto fast = build(true);
  const auto reference = build(false);
  core::RandomStream rng(11, 12);
  int hits = 0, mismatched = 0;
  const int rays = 5000;
  for (int i = 0; i < rays; ++i) {
    const double z = rng.Uniform(0.05, 1.5);
    const Eigen::Vector3d from(rng.Uniform(-4, 4.8), rng.Uniform(-3, 3), z);
    const double a = rng.Uniform(-kPi, kPi);
    const Eigen::Vector3d to = from + 8.0 * Eigen::Vector3d(std::cos(a), std::sin(a), 0.0);
    const int ignore = i % 2 == 0 ? fast->robot_group(0) : -1;
    const RayHit f = fast->CastRay(from, to, ignore);
    const RayHit r = reference->CastRay(from, to, ignore);
    if (f.hit != r.hit || (f.hit && std::abs(f.distance_m - r.distance_m) > 1e-3)) {
      // Bullet's convex cast on thin boxes (the 4 cm door) can report hits a few
      // centimetres beyond their ends; the exact path does not.
      ++mismatched;
      continue;
    }
    if (!f.hit) continue;
    ++hits;
    EXPECT_EQ(f.element, r.element) << "ray " << i;
    EXPECT_NEAR(f.normal.dot(r.normal), 1.0, 1e-3) << "ray " << i;
  }
  EXPECT_GT(hits, rays / 3);
  EXPECT_LE(mismatched, rays / 200);  // ≥ 99.5 % agree within 1 mm
}

// A robot is where its pose says from the moment it is added: rays find it
// before the first step, and robots added one after the other never share
// broadphase pairs through their parts' construction place at the origin.
TEST(RobotWorld, AddedRobotsAreInTheBroadphaseAtTheirPose) {
  World world(Hall(false), WorldOptions{});
  for (int k = 0; k < 20; ++k) {
    std::string id = "r";  // appended, not `+`: GCC 12 warns falsely (-Wrestrict)
    id += std::to_string(k);
    pavilion::testing::AddRobot(world, Spec(id, {-10.0 + k, 8, 0}));
  }
  const int r = pavilion::testing::AddRobot(world, Spec("target", {3, -6, 0.0}));
  const RayHit hit = world.CastRay({0, -6, 0.2}, {6, -6, 0.2});
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.element, world.robot_element(r));
}

TEST(RobotWorld, SameCommandsGiveBitIdenticalStates) {
  const auto run = [] {
    World world(Hall(true), WorldOptions{});
    const int r = pavilion::testing::AddRobot(world, Spec("r", {0, 0, 0.1}));
    world.SetWheelSpeeds(r, 6.0, 5.0);
    Advance(&world, r, 3.0, nullptr);
    world.ApplyRobotImpulse(r, {10, -30});
    Advance(&world, r, 1.0, nullptr);
    return world.robot_state(r);
  };
  const RobotState a = run(), b = run();
  EXPECT_EQ(a.pose, b.pose);
  EXPECT_EQ(a.left_wheel_rad, b.left_wheel_rad);
  EXPECT_EQ(a.right_wheel_rad, b.right_wheel_rad);
}

}  // namespace
}  // namespace pavilion::sim
