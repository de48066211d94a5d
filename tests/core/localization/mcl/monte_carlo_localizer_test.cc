// Monte Carlo localization (Probabilistic Robotics §8.3, table 8.3) on an
// L-shaped room: tracking, global localization, recovery after a kidnap, and
// reproducibility. Scans are ray cast against the map's own segments; the true
// wheels are 3 % larger than the odometry model, so dead reckoning drifts.
#include "core/localization/mcl/monte_carlo_localizer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include "tests/support/mcl_world.h"

namespace pavilion::core {
namespace {

using testing::DriveSimulator;

constexpr double kDtS = 0.02;      // encoder period (50 Hz)
constexpr int kStepsPerScan = 10;  // a scan every 0.2 s (5 Hz)
constexpr double kSpeedMps = 0.5;
constexpr double kTurnRadps = 1.0;
constexpr double kWheelScale = 1.03;  // true wheel radius / modelled
constexpr double kTenDegreesRad = 10.0 * std::numbers::pi / 180.0;

double PositionError(const Pose2& a, const Pose2& b) {
  return (a.translation() - b.translation()).norm();
}
double HeadingError(const Pose2& a, const Pose2& b) {
  return std::abs(NormalizeAngle(a.theta_rad - b.theta_rad));
}

// Drives the simulated robot and feeds the localizer its encoders and scans.
class Harness {
 public:
  Harness(const MonteCarloOptions& options, const Pose2& start, std::uint64_t noise_seed = 5)
      : mcl(testing::LShapedRoomMap(), EncoderOdometryOptions{}, options),
        sim(start, EncoderOdometryOptions{}, kWheelScale),
        dead_reckoning(EncoderOdometryOptions{}, start),
        walls_(testing::LShapedRoomWalls()),
        noise_(noise_seed, 2) {
    mcl.AddEncoders(sim.Reading());
    dead_reckoning.Update(sim.Reading());
  }

  // Drives `duration_s` at (v, w); `on_update` is called after every sensor update.
  template <typename OnUpdate>
  void Drive(double v_mps, double w_radps, double duration_s, OnUpdate on_update) {
    const int steps = static_cast<int>(std::lround(duration_s / kDtS));
    for (int i = 0; i < steps; ++i) {
      const EncoderReading reading = sim.Step(v_mps, w_radps, kDtS);
      mcl.AddEncoders(reading);
      dead_reckoning.Update(reading);
      if (++step_ % kStepsPerScan != 0) continue;
      if (mcl.AddScan(testing::CastScan(walls_, sim.truth(), sim.stamp_s(), &noise_))) on_update();
    }
  }
  void Drive(double v_mps, double w_radps, double duration_s) {
    Drive(v_mps, w_radps, duration_s, [] {});
  }
  void Straight(double distance_m) { Drive(kSpeedMps, 0.0, distance_m / kSpeedMps); }
  void Turn(double angle_rad) {
    Drive(0.0, std::copysign(kTurnRadps, angle_rad), std::abs(angle_rad) / kTurnRadps);
  }
  // The scan at the current truth, fed once (the first scan always updates).
  void ScanNow() { mcl.AddScan(testing::CastScan(walls_, sim.truth(), sim.stamp_s(), &noise_)); }

  MonteCarloLocalizer mcl;
  DriveSimulator sim;
  DeadReckoning dead_reckoning;

 private:
  std::vector<testing::Wall> walls_;
  RandomStream noise_;
  long step_ = 0;
};

PoseWithCovariance Known(const Pose2& pose) {
  PoseWithCovariance start;
  start.pose = pose;
  start.covariance = Eigen::Vector3d(0.05 * 0.05, 0.05 * 0.05, 0.03 * 0.03).asDiagonal();
  return start;
}

// From a known pose the filter tracks an 8 m drive within 0.1 m while dead
// reckoning with 3 % too small wheels drifts by more than twice that.
TEST(MonteCarloLocalizerTest, TracksFromAKnownPose) {
  const Pose2 start{2.0, 3.0, 0.0};
  Harness h(MonteCarloOptions{}, start);
  h.mcl.Initialize(Known(start));
  h.ScanNow();
  double worst_m = 0.0;
  h.Drive(kSpeedMps, 0.0, 8.0 / kSpeedMps, [&] {
    worst_m = std::max(worst_m, PositionError(h.mcl.estimate().pose, h.sim.truth()));
    EXPECT_LT(HeadingError(h.mcl.estimate().pose, h.sim.truth()), 0.05);
  });
  EXPECT_GE(h.mcl.updates(), 20);
  EXPECT_LT(worst_m, 0.1);
  EXPECT_TRUE(h.mcl.converged());
  EXPECT_GT(PositionError(h.dead_reckoning.pose(), h.sim.truth()), 0.2);
}

// Drives 8 m from (2, 3) heading +x after a global start with 2000 particles
// (seeded `seed`, range noise seeded too). *converged_at: the first update at
// which the estimate is within 0.3 m and 10 deg of the truth and converged, -1
// if none.
std::unique_ptr<Harness> GlobalStart(std::uint64_t seed, long* converged_at) {
  MonteCarloOptions options;
  options.particles = 2000;
  options.seed = seed;
  auto h = std::make_unique<Harness>(options, Pose2{2.0, 3.0, 0.0}, seed);
  h->mcl.InitializeGlobal();
  EXPECT_FALSE(h->mcl.converged());
  *converged_at = -1;
  h->Drive(kSpeedMps, 0.0, 8.0 / kSpeedMps, [&] {
    const bool near = PositionError(h->mcl.estimate().pose, h->sim.truth()) < 0.3 &&
                      HeadingError(h->mcl.estimate().pose, h->sim.truth()) < kTenDegreesRad;
    if (*converged_at < 0 && near && h->mcl.converged()) *converged_at = h->mcl.updates();
  });
  return h;
}

// Started uniformly over the free space, the filter converges to the truth
// (0.3 m, 10 deg) within 20 updates for seed 3 and is still there at the end.
TEST(MonteCarloLocalizerTest, GlobalStartConverges) {
  long converged_at = -1;
  const std::unique_ptr<Harness> h = GlobalStart(3, &converged_at);
  ASSERT_GT(converged_at, 0) << "never converged";
  EXPECT_LE(converged_at, 20);
  EXPECT_LT(PositionError(h->mcl.estimate().pose, h->sim.truth()), 0.3);
  EXPECT_TRUE(h->mcl.converged());
}

// One uniform draw may collapse on a wrong pose (the 60-beam likelihood is
// sharp and w_slow starts cold, so no recovery comes within 8 m): of seeds
// 1-10, at least 7 converge within the drive (8 did when this was written).
TEST(MonteCarloLocalizerTest, GlobalStartConvergesForMostSeeds) {
  int converged = 0;
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    long converged_at = -1;
    GlobalStart(seed, &converged_at);
    converged += converged_at > 0 ? 1 : 0;
  }
  EXPECT_GE(converged, 7);
}

// Laps along the long part of the room, from x = 2.5 to x = 10 and back, until
// the filter made at least `updates` sensor updates.
void Laps(Harness& h, long updates) {
  while (h.mcl.updates() < updates) {
    h.Straight(7.5);
    h.Turn(std::numbers::pi);
    h.Straight(7.5);
    h.Turn(-std::numbers::pi);
  }
}

// After a kidnap (truth moved, odometry not told) the short-term likelihood
// average falls below the long-term one, random particles come in, and the
// filter re-converges on the new pose.
TEST(MonteCarloLocalizerTest, RecoversFromAKidnap) {
  const Pose2 start{2.5, 3.0, 0.0};
  Harness h(MonteCarloOptions{}, start);
  h.mcl.Initialize(Known(start));
  h.ScanNow();
  Laps(h, 400);  // w_slow warms up over ~1 / alpha_slow updates
  ASSERT_LT(PositionError(h.mcl.estimate().pose, h.sim.truth()), 0.1);
  const double ratio_before = h.mcl.w_fast() / h.mcl.w_slow();
  EXPECT_GT(ratio_before, 1.0);
  const long kidnapped_at = h.mcl.updates();
  h.sim.Teleport({3.0, 8.0, -0.5 * std::numbers::pi});
  double lowest_ratio = ratio_before;
  long recovered_at = -1;
  const auto watch = [&] {
    lowest_ratio = std::min(lowest_ratio, h.mcl.w_fast() / h.mcl.w_slow());
    const bool near = PositionError(h.mcl.estimate().pose, h.sim.truth()) < 0.3 &&
                      HeadingError(h.mcl.estimate().pose, h.sim.truth()) < kTenDegreesRad;
    if (recovered_at < 0 && near && h.mcl.converged()) recovered_at = h.mcl.updates();
  };
  h.Drive(kSpeedMps, 0.0, 5.0 / kSpeedMps, watch);  // down the arm to (3, 3)
  h.Drive(0.0, kTurnRadps, 0.5 * std::numbers::pi / kTurnRadps, watch);
  for (int lap = 0; lap < 3 && recovered_at < 0; ++lap) {
    h.Drive(kSpeedMps, 0.0, 6.0 / kSpeedMps, watch);
    h.Drive(0.0, kTurnRadps, std::numbers::pi / kTurnRadps, watch);
    h.Drive(kSpeedMps, 0.0, 6.0 / kSpeedMps, watch);
    h.Drive(0.0, -kTurnRadps, std::numbers::pi / kTurnRadps, watch);
  }
  EXPECT_LT(lowest_ratio, 0.5);
  ASSERT_GT(recovered_at, 0) << "never re-converged";
  EXPECT_LE(recovered_at - kidnapped_at, 80);
  EXPECT_LT(PositionError(h.mcl.estimate().pose, h.sim.truth()), 0.3);
}

// Same seed: the same particles, byte for byte; another seed: others.
TEST(MonteCarloLocalizerTest, IsDeterministicPerSeed) {
  const auto run = [](std::uint64_t seed) {
    MonteCarloOptions options;
    options.seed = seed;
    Harness h(options, {2.0, 3.0, 0.0});
    h.mcl.InitializeGlobal();
    h.Straight(2.0);
    return h.mcl.particles();
  };
  const std::vector<Particle> a = run(11), b = run(11), c = run(12);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(Particle)), 0);
  ASSERT_EQ(a.size(), c.size());
  EXPECT_NE(std::memcmp(a.data(), c.data(), a.size() * sizeof(Particle)), 0);
}

// No sensor update before the robot moved update_min_d / update_min_a, except
// the first scan; each update scores `beams` beams.
TEST(MonteCarloLocalizerTest, UpdatesOnlyAfterMotion) {
  const Pose2 start{2.0, 3.0, 0.0};
  Harness h(MonteCarloOptions{}, start);
  h.mcl.Initialize(Known(start));
  h.ScanNow();
  EXPECT_EQ(h.mcl.updates(), 1);
  EXPECT_EQ(h.mcl.last_beams(), 60);
  h.ScanNow();
  EXPECT_EQ(h.mcl.updates(), 1);
  h.Straight(0.2);  // two scans, 0.2 m < 0.25 m
  EXPECT_EQ(h.mcl.updates(), 1);
  h.Straight(0.1);
  EXPECT_EQ(h.mcl.updates(), 2);
  h.Turn(0.5);  // scans 0.2 and 0.4 rad in: one turn past update_min_a
  EXPECT_EQ(h.mcl.updates(), 3);
}

// Every option is validated and named in the error.
TEST(MonteCarloLocalizerTest, ValidatesOptions) {
  const auto expect_field = [](MonteCarloOptions o, const std::string& field) {
    try {
      o.Validate();
      ADD_FAILURE() << field << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  MonteCarloOptions o;
  o.particles = 5;
  expect_field(o, "particles");
  o = {};
  o.beams = 0;
  expect_field(o, "beams");
  o = {};
  o.sigma_hit_m = 0.0;
  expect_field(o, "sigma_hit_m");
  o = {};
  o.alpha_fast = 0.0005;
  expect_field(o, "alpha_fast");
  o = {};
  o.resample_interval = 0;
  expect_field(o, "resample_interval");
  o = {};
  o.field.max_distance_m = -1.0;
  expect_field(o, "max_distance_m");
}

}  // namespace
}  // namespace pavilion::core
