#include "sim/crowd/social_force.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

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

}  // namespace
}  // namespace pavilion::sim::crowd
