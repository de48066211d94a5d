#include "sim/crowd/social_force.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "core/random/random_stream.h"

namespace pavilion::sim::crowd {
namespace {

// Weidmann (1993): v(ρ) = v0 (1 - exp(-γ (1/ρ - 1/ρ_max))), v0 = 1.34 m/s,
// γ = 1.913 /m², ρ_max = 5.4 /m².
double WeidmannSpeed(double density) {
  return 1.34 * (1.0 - std::exp(-1.913 * (1.0 / density - 1.0 / 5.4)));
}

struct CorridorResult {
  double mean_speed_mps = 0.0;
  double max_overlap_m = 0.0;
};

// People walking along a 20 m x 4 m corridor whose ends meet, at a density:
// the mean walking speed over `measure_s` after a `warmup_s`.
CorridorResult WalkCorridor(double density, std::uint64_t seed, double warmup_s = 30.0,
                            double measure_s = 30.0) {
  constexpr double kLength = 20.0, kWidth = 4.0, kDt = 0.005;
  SocialForceModel model{SocialForceOptions{}};
  model.SetWalls({{{0, 0}, {kLength, 0}, 0}, {{kLength, kWidth}, {0, kWidth}, 1}}, {});
  model.SetPeriodicX(0.0, kLength);
  core::RandomStream random(seed, 7);
  const int n = static_cast<int>(std::lround(density * kLength * kWidth));
  // A jittered lattice over the floor.
  const int rows = std::max(1, static_cast<int>(std::lround(std::sqrt(n * kWidth / kLength))));
  const int cols = (n + rows - 1) / rows;
  for (int k = 0; k < n; ++k) {
    Agent a;
    a.radius_m = random.Uniform(0.20, 0.25);
    const double x = (k % cols + 0.5 + random.Uniform(-0.1, 0.1)) * kLength / cols;
    const double y = 0.3 + (k / cols + 0.5 + random.Uniform(-0.2, 0.2)) * (kWidth - 0.6) / rows;
    a.position_m = {x, y};
    a.free_speed_mps = std::clamp(random.Normal(1.34, 0.26), 0.5, 2.2);
    a.desired_velocity_mps = {a.free_speed_mps, 0.0};
    a.active = true;
    model.agents().push_back(a);
  }
  CorridorResult result;
  double speed_sum = 0.0;
  long samples = 0;
  const int warmup = static_cast<int>(warmup_s / kDt),
            total = warmup + static_cast<int>(measure_s / kDt);
  for (int step = 0; step < total; ++step) {
    model.Step(kDt, nullptr);
    if (step < warmup) continue;
    result.max_overlap_m = std::max(result.max_overlap_m, model.max_overlap_m());
    if (step % 20 != 0) continue;
    for (const Agent& a : model.agents()) speed_sum += a.velocity_mps.x();
    samples += static_cast<long>(model.agents().size());
  }
  result.mean_speed_mps = speed_sum / static_cast<double>(samples);
  return result;
}

// The fundamental diagram: mean speeds within ±25 % of Weidmann's curve at
// 0.5, 1 and 2 persons/m², and below 0.5 m/s at 3 /m² (issue acceptance).
TEST(SocialForceTest, FundamentalDiagramFollowsWeidmann) {
  constexpr int kSeeds = 3;
  for (double density : {0.5, 1.0, 2.0, 3.0}) {
    double speed = 0.0, overlap = 0.0;
    for (int seed = 1; seed <= kSeeds; ++seed) {
      const CorridorResult r = WalkCorridor(density, seed);
      speed += r.mean_speed_mps / kSeeds;
      overlap = std::max(overlap, r.max_overlap_m);
    }
    const double expected = WeidmannSpeed(density);
    std::printf("| %.1f | %.2f | %.2f | %+.0f %% | %.3f |\n", density, speed, expected,
                100.0 * (speed / expected - 1.0), overlap);
    if (density < 2.5) {
      EXPECT_NEAR(speed, expected, 0.25 * expected) << "density " << density;
      // Bodies compress by at most 5 cm in walking crowds (the jam at 3 /m²
      // squeezes harder: reported, not bounded).
      EXPECT_LE(overlap, 0.05) << "density " << density;
    } else {
      EXPECT_LT(speed, 0.5) << "density " << density;
    }
  }
}

// A square robot footprint of half-width h centred at (x, 0).
RobotObstacle SquareRobot(double x, double h) {
  RobotObstacle r;
  r.hull_m = {{x - h, -h}, {x + h, -h}, {x + h, h}, {x - h, h}};
  r.center_m = {x, 0.0};
  return r;
}

// A person squeezed between two robots is pinned for both: each meets the
// full body force (Newton's third law through the person), equal and
// opposite, above what a free person can push with. Judged robot by robot,
// the first robot felt only the bounded push and the second the whole spring.
TEST(SocialForceTest, APersonSqueezedBetweenTwoRobotsPinsBoth) {
  SocialForceOptions options;
  SocialForceModel model{options};
  constexpr double kHalf = 0.3;
  Agent a;
  a.radius_m = 0.22;
  a.active = true;
  model.agents().push_back(a);  // at the origin, standing
  // Each robot's face 0.19 m from the person's centre: 3 cm into the body.
  model.SetRobots({SquareRobot(-(0.19 + kHalf), kHalf), SquareRobot(0.19 + kHalf, kHalf)});
  std::vector<RobotContactForce> forces;
  model.Step(0.001, &forces);
  ASSERT_EQ(forces.size(), 2u);
  const RobotContactForce& left = forces[0].robot == 0 ? forces[0] : forces[1];
  const RobotContactForce& right = forces[0].robot == 0 ? forces[1] : forces[0];
  EXPECT_TRUE(left.pinned);
  EXPECT_TRUE(right.pinned);
  EXPECT_LT(left.force_n.x(), -options.max_push_force_n);  // pushed away from the person
  EXPECT_GT(right.force_n.x(), options.max_push_force_n);
  EXPECT_NEAR(left.force_n.x(), -right.force_n.x(), 1e-6 * right.force_n.x());

  // A person touching one robot only is free: the push is bounded.
  SocialForceModel alone{options};
  alone.agents().push_back(a);
  alone.SetRobots({SquareRobot(0.19 + kHalf, kHalf)});
  std::vector<RobotContactForce> one;
  alone.Step(0.001, &one);
  ASSERT_EQ(one.size(), 1u);
  EXPECT_FALSE(one[0].pinned);
  EXPECT_NEAR(one[0].force_n.norm(), options.max_push_force_n, 1e-6);
}

// A person walking head-on into a wall at 1 m/s, with nothing but the body
// contact acting (no wish, no long-range wall force): the speed at which it
// leaves the wall over the speed at which it met it.
double WallRebound(double restitution) {
  SocialForceOptions options;
  options.contact_restitution = restitution;
  options.wall_strength_n = 0.0;
  options.relaxation_s = 10.0;  // its wish (to stand) barely brakes it
  SocialForceModel model{options};
  model.SetWalls({{{0.0, -5.0}, {0.0, 5.0}, 0}}, {});  // x = 0, facing -x
  Agent a;
  a.position_m = {-0.3, 0.0};
  a.velocity_mps = {1.0, 0.0};
  a.active = true;
  model.agents().push_back(a);
  double approach = 0.0;
  for (int step = 0; step < 400; ++step) {
    const Agent& now = model.agents()[0];
    const bool touching = now.position_m.x() + now.radius_m > 0.0;
    if (!touching && now.velocity_mps.x() > 0.0) approach = now.velocity_mps.x();
    if (!touching && now.velocity_mps.x() < 0.0) return -now.velocity_mps.x() / approach;
    model.Step(0.001, nullptr);
  }
  // Still against the wall after 0.4 s (some 8 contact times): how fast it
  // is leaving.
  return std::max(0.0, -model.agents()[0].velocity_mps.x()) / approach;
}

// contact_restitution is what a head-on contact gives back: 1 is HFV00's
// spring, elastic; the default 0.2 leaves the wall at a fifth of the speed.
// Lifting the damped force where the spring alone would still push (a contact
// only pushes) lets a body leave a little faster than the linear damper's e.
TEST(SocialForceTest, AContactGivesBackItsRestitutionOfTheApproachSpeed) {
  EXPECT_NEAR(WallRebound(1.0), 1.0, 0.03);
  EXPECT_NEAR(WallRebound(0.2), 0.2, 0.05);
  EXPECT_NEAR(WallRebound(0.5), 0.5, 0.05);
  EXPECT_NEAR(WallRebound(0.0), 0.0, 0.02);
  SocialForceOptions bad;
  bad.contact_restitution = 1.5;
  EXPECT_THROW(bad.Validate(), std::invalid_argument);
}

// A robot driving at 0.5 m/s into a standing person damps the contact by its
// own motion (the surface's velocity): the person leaves the robot's face
// at (1 + e) times the robot's speed, as off an unyielding mass, and the robot
// meets a force above the spring's alone while it closes in.
TEST(SocialForceTest, ARobotDrivingIntoAPersonIsMetByTheDampedContact) {
  for (const double e : {1.0, 0.2}) {
    SocialForceOptions options;
    options.contact_restitution = e;
    options.robot_strength_n = 0.0;
    options.relaxation_s = 10.0;
    SocialForceModel model{options};
    Agent a;
    a.active = true;
    model.agents().push_back(a);  // at the origin, standing
    constexpr double kHalf = 0.3, kSpeed = 0.5, kDt = 0.001;
    double face = -0.23;  // the robot's front face, 1 cm short of the person
    double first_push = 0.0;
    for (int step = 0; step < 300; ++step) {
      RobotObstacle robot = SquareRobot(face - kHalf, kHalf);
      robot.velocity_mps = {kSpeed, 0.0};
      model.SetRobots({robot});
      std::vector<RobotContactForce> forces;
      model.Step(kDt, &forces);
      if (first_push == 0.0 && !forces.empty()) first_push = -forces[0].force_n.x();
      face += kSpeed * kDt;
    }
    EXPECT_NEAR(model.agents()[0].velocity_mps.x(), (1.0 + e) * kSpeed, 0.05 * kSpeed) << e;
    // The first contact step: the damper's 2 ζ √(k m) v is the whole push
    // (the overlap is still under a millimetre), bounded by 300 N.
    if (e < 1.0) {
      EXPECT_GT(first_push, 100.0) << e;
    } else {
      EXPECT_LT(first_push, 100.0) << e;
    }
  }
}

// A robot 3 cm into a person (3.6 kN of body force) meets the person's push
// (300 N) plus what holds the person against it: a wall the person presses
// 3 cm into passes the whole force on, one the person brushes by 1 mm (120 N)
// little more than the push.
TEST(SocialForceTest, APersonPassesOnWhatHoldsIt) {
  SocialForceOptions options;
  options.wall_strength_n = 0.0;
  constexpr double kHalf = 0.3;
  const auto robot_force = [&](double wall_overlap_m) {
    SocialForceModel model{options};
    Agent a;
    a.radius_m = 0.22;
    a.active = true;
    model.agents().push_back(a);  // at the origin, standing
    const double wall_x = a.radius_m - wall_overlap_m;
    model.SetWalls({{{wall_x, 5.0}, {wall_x, -5.0}, 0}}, {});  // facing -x
    model.SetRobots({SquareRobot(-(0.19 + kHalf), kHalf)});    // its face 3 cm in
    std::vector<RobotContactForce> forces;
    model.Step(0.001, &forces);
    EXPECT_EQ(forces.size(), 1u);
    return forces.empty() ? RobotContactForce{} : forces[0];
  };
  const double k = options.body_stiffness_npm;
  const RobotContactForce pressed = robot_force(0.03);
  EXPECT_TRUE(pressed.pinned);
  EXPECT_NEAR(-pressed.force_n.x(), k * 0.03, 1e-6 * k);
  const RobotContactForce brushing = robot_force(0.001);
  EXPECT_TRUE(brushing.pinned);
  EXPECT_NEAR(-brushing.force_n.x(), options.max_push_force_n + k * 0.001, 1e-6 * k);
  const RobotContactForce free = robot_force(-0.01);  // the wall 1 cm off
  EXPECT_FALSE(free.pinned);
  EXPECT_NEAR(free.force_n.norm(), options.max_push_force_n, 1e-6);
}

}  // namespace
}  // namespace pavilion::sim::crowd
