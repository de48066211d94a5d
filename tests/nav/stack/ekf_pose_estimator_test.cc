// The EKF estimator's cycles: a tick of the rate gate is one cycle with every
// laser's scan of it, whether the lasers' stamps agree or differ by their
// latencies (Table 4.2 counts matched lines per 2 Hz cycle), and a laser that
// stops delivering does not stop the cycles.
#include "nav/stack/ekf_pose_estimator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "nav/stack/global_pose_estimator.h"
#include "tests/support/mcl_world.h"

namespace pavilion::nav {
namespace {

constexpr double kDtS = 0.01;      // encoder period (100 Hz)
constexpr int kStepsPerCall = 5;   // one stack tick: 50 ms
constexpr double kSpeedMps = 0.2;  // straight along the room's long part
constexpr double kRunS = 10.0;

struct Rows {
  int cycles = 0;
  int matched_lines = 0;
  double LinesPerCycle() const { return cycles > 0 ? double(matched_lines) / cycles : 0.0; }
};

// Drives 10 s through the L-shaped room with a front and a rear scanner. The
// front scans at every stack tick; the rear twice a second, `rear_lag_s`
// after the front's due instants (a whole number of ticks), until `rear_until_s`;
// or, `rear_every_tick`, at every tick as the front.
constexpr double kRateHz = 2.0;
const core::Pose2 kStart{2.0, 3.0, 0.0};

Rows Drive(PoseEstimator& estimator, double rear_lag_s, double rear_until_s = kRunS,
           bool rear_every_tick = false) {
  testing::DriveSimulator sim(kStart, core::EncoderOdometryOptions{}, 1.0);
  const std::vector<testing::Wall> walls = testing::LShapedRoomWalls();
  core::RandomStream noise(5, 1);
  constexpr double kTickS = kStepsPerCall * kDtS;
  const long lag_ticks = std::lround(rear_lag_s / kTickS);
  const long ticks_per_cycle = std::lround(1.0 / (kRateHz * kTickS));
  Rows rows;
  std::vector<core::EncoderReading> encoders{sim.Reading()};
  for (long tick = 0; sim.stamp_s() < kRunS; ++tick) {
    for (int i = 0; i < kStepsPerCall; ++i) encoders.push_back(sim.Step(kSpeedMps, 0.0, kDtS));
    // Each scan cast from where the robot is at its stamp (the tick's end).
    std::vector<core::LaserScan> scans{
        testing::CastScan(walls, sim.truth(), sim.stamp_s(), &noise)};
    if (tick >= lag_ticks && (rear_every_tick || (tick - lag_ticks) % ticks_per_cycle == 0) &&
        sim.stamp_s() < rear_until_s) {
      core::Pose2 rear_pose = sim.truth();
      rear_pose.theta_rad += std::numbers::pi;  // CastScan's mount: 0.2 m ahead, facing forward
      scans.push_back(testing::CastScan(walls, rear_pose, sim.stamp_s(), &noise));
      scans.back().sensor_id = "rear";
      scans.back().robot_from_sensor = {-0.2, 0.0, std::numbers::pi};
    }
    std::vector<const core::LaserScan*> pointers;
    for (const core::LaserScan& s : scans) pointers.push_back(&s);
    const std::optional<EstimatorCycle> cycle = estimator.Update(encoders, pointers);
    encoders.clear();
    if (!cycle) continue;
    ++rows.cycles;
    rows.matched_lines += cycle->matched_lines;
  }
  EXPECT_LT((estimator.estimate().pose.translation() - sim.truth().translation()).norm(), 0.02);
  return rows;
}

Rows Drive(double rear_lag_s, double rear_until_s = kRunS) {
  EkfPoseEstimatorOptions options;
  options.lasers = {"front", "rear"};
  options.rate_hz = kRateHz;
  options.initial_pose = kStart;
  EkfPoseEstimator estimator(testing::LShapedRoomMap(), options);
  return Drive(estimator, rear_lag_s, rear_until_s);
}

TEST(EkfPoseEstimatorTest, LasersWithTheSameStampsMakeOneCyclePerTick) {
  const Rows rows = Drive(0.0);
  EXPECT_NEAR(rows.cycles, 2.0 * kRunS, 1.0);  // 2 Hz
  // Both scanners see walls: more lines than either alone.
  EXPECT_GT(rows.LinesPerCycle(), 3.0);
}

TEST(EkfPoseEstimatorTest, ALaggingLaserStillMakesOneCyclePerTick) {
  const Rows same = Drive(0.0);
  const Rows lagging = Drive(0.1);                // the rear's scans 100 ms after the front's
  EXPECT_NEAR(lagging.cycles, 2.0 * kRunS, 1.0);  // 2 Hz, not a row per scan
  // Each cycle still holds both scanners' lines.
  EXPECT_NEAR(lagging.LinesPerCycle(), same.LinesPerCycle(), 0.3);
}

TEST(EkfPoseEstimatorTest, ALaserThatStopsDoesNotStopTheCycles) {
  const Rows both = Drive(0.1);
  const Rows rear_stops = Drive(0.1, 5.0);  // the rear delivers for 5 s only
  // One tick waits for the rear's scan that does not come, then the front alone.
  EXPECT_NEAR(rear_stops.cycles, both.cycles, 1.0);
  EXPECT_LT(rear_stops.matched_lines, both.matched_lines);
}

// The global estimator, localized, reports a cycle with both lasers' scans of
// a tick as the EKF estimator does: it reported the last scan's pairings
// alone, and the front laser's went uncounted (expo_day's matched lines per
// cycle and missions without a match).
TEST(GlobalPoseEstimatorTest, ACycleCountsEveryLasersPairings) {
  GlobalPoseEstimatorOptions options;
  options.lasers = {"front", "rear"};
  options.rate_hz = kRateHz;
  options.initial = core::PoseWithCovariance{
      kStart, Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal().toDenseMatrix()};
  GlobalPoseEstimator global(testing::LShapedRoomMap(), options);
  // Both scanners deliver at every tick, as a robot's lasers at their own
  // rates do: the rate gate admits both in the same tick.
  const Rows rows = Drive(global, 0.0, kRunS, true);
  EkfPoseEstimatorOptions ekf_options;
  ekf_options.lasers = options.lasers;
  ekf_options.rate_hz = kRateHz;
  ekf_options.initial_pose = kStart;
  EkfPoseEstimator estimator(testing::LShapedRoomMap(), ekf_options);
  const Rows ekf = Drive(estimator, 0.0, kRunS, true);
  EXPECT_NEAR(rows.cycles, ekf.cycles, 1.0);
  EXPECT_NEAR(rows.LinesPerCycle(), ekf.LinesPerCycle(), 0.3);
  EXPECT_GT(rows.LinesPerCycle(), 3.0);
}

}  // namespace
}  // namespace pavilion::nav
