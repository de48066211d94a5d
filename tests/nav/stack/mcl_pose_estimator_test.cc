// The Monte Carlo localization baseline behind the robot stack's estimator
// seam: cycles, lost state, laser selection and pausing on synthetic data.
#include "nav/stack/mcl_pose_estimator.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "tests/support/mcl_world.h"

namespace pavilion::nav {
namespace {

constexpr double kDtS = 0.02;      // encoder period (50 Hz)
constexpr int kStepsPerTick = 10;  // one stack tick, one scan: 0.2 s
constexpr double kSpeedMps = 0.5;
constexpr double kWheelScale = 1.03;  // true wheel radius / modelled

// Feeds an estimator a tick at a time: ten encoder readings and one scan.
class Drive {
 public:
  explicit Drive(const core::Pose2& start, std::uint64_t noise_seed = 3)
      : sim_(start, core::EncoderOdometryOptions{}, kWheelScale),
        walls_(testing::LShapedRoomWalls()),
        noise_(noise_seed, 2) {}

  // One tick at `v_mps` straight ahead; the scan named `sensor_id`.
  std::optional<EstimatorCycle> Tick(PoseEstimator& estimator, const std::string& sensor_id) {
    std::vector<core::EncoderReading> encoders;
    if (first_) encoders.push_back(sim_.Reading());
    first_ = false;
    for (int i = 0; i < kStepsPerTick; ++i) encoders.push_back(sim_.Step(kSpeedMps, 0.0, kDtS));
    core::LaserScan scan = testing::CastScan(walls_, sim_.truth(), sim_.stamp_s(), &noise_);
    scan.sensor_id = sensor_id;
    return estimator.Update(encoders, {&scan});
  }
  const core::Pose2& truth() const { return sim_.truth(); }

 private:
  testing::DriveSimulator sim_;
  std::vector<testing::Wall> walls_;
  core::RandomStream noise_;
  bool first_ = true;
};

double PositionError(const core::Pose2& a, const core::Pose2& b) {
  return (a.translation() - b.translation()).norm();
}

// From a known start the adapter reports a cycle per sensor update (the first
// scan, then every 0.3 m), with the beams as observations, and tracks.
TEST(MclPoseEstimatorTest, ReportsCyclesAndTracks) {
  const core::Pose2 start{2.0, 3.0, 0.0};
  MclPoseEstimatorOptions options;
  options.initial_pose = start;
  MclPoseEstimator estimator(testing::LShapedRoomMap(), core::EncoderOdometryOptions{}, options);
  Drive drive(start);
  int cycles = 0;
  for (int tick = 0; tick < 60; ++tick) {  // 6 m
    const std::optional<EstimatorCycle> cycle = drive.Tick(estimator, "front");
    if (!cycle) continue;
    ++cycles;
    EXPECT_EQ(cycle->observations, 60);
    EXPECT_EQ(cycle->predictions, 0);
    EXPECT_EQ(cycle->matched_lines + cycle->matched_beacons + cycle->matched_other, 0);
    if (tick > 10) {
      EXPECT_FALSE(cycle->lost) << "tick " << tick;
    }
  }
  EXPECT_EQ(cycles, 1 + 59 / 3);  // 0.1 m per tick, an update when > 0.25 m
  EXPECT_LT(PositionError(estimator.estimate().pose, drive.truth()), 0.1);
  EXPECT_EQ(estimator.lost_reason(), "none");
}

// A global start is lost ("not_converged") until the particles converge on
// the same synthetic data, then it is within 0.3 m of the truth.
TEST(MclPoseEstimatorTest, GlobalStartConverges) {
  MclPoseEstimatorOptions options;
  options.global_start = true;
  options.mcl.particles = 2000;
  options.mcl.seed = 3;
  MclPoseEstimator estimator(testing::LShapedRoomMap(), core::EncoderOdometryOptions{}, options);
  EXPECT_EQ(estimator.lost_reason(), "not_converged");
  Drive drive({2.0, 3.0, 0.0}, 3);
  bool ever_lost = false;
  std::optional<EstimatorCycle> last;
  for (int tick = 0; tick < 80; ++tick) {
    const std::optional<EstimatorCycle> cycle = drive.Tick(estimator, "front");
    if (!cycle) continue;
    ever_lost = ever_lost || cycle->lost;
    last = cycle;
  }
  EXPECT_TRUE(ever_lost);
  ASSERT_TRUE(last.has_value());
  EXPECT_FALSE(last->lost);
  EXPECT_EQ(estimator.lost_reason(), "none");
  EXPECT_LT(PositionError(estimator.estimate().pose, drive.truth()), 0.3);
}

// Scans of lasers not listed are ignored; while paused no scan is used but
// the odometry still moves the estimate.
TEST(MclPoseEstimatorTest, SelectsLasersAndPauses) {
  const core::Pose2 start{2.0, 3.0, 0.0};
  MclPoseEstimatorOptions options;
  options.initial_pose = start;
  options.lasers = {"front"};
  MclPoseEstimator estimator(testing::LShapedRoomMap(), core::EncoderOdometryOptions{}, options);
  Drive drive(start);
  EXPECT_FALSE(drive.Tick(estimator, "rear").has_value());
  EXPECT_TRUE(drive.Tick(estimator, "front").has_value());
  estimator.SetPaused(true, 0.4);
  const double x_before = estimator.estimate().pose.x_m;
  for (int tick = 0; tick < 5; ++tick) EXPECT_FALSE(drive.Tick(estimator, "front").has_value());
  EXPECT_NEAR(estimator.estimate().pose.x_m - x_before, 0.5 / kWheelScale, 0.05);
  estimator.SetPaused(false, 1.4);
  EXPECT_TRUE(drive.Tick(estimator, "front").has_value());
}

// A covariance that is not positive semi-definite is rejected by name.
TEST(MclPoseEstimatorTest, ValidatesOptions) {
  MclPoseEstimatorOptions options;
  options.initial_covariance(0, 0) = -1.0;
  try {
    options.Validate();
    ADD_FAILURE() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("initial_covariance"), std::string::npos);
  }
  options = {};
  options.mcl.particles = 1;
  EXPECT_THROW(options.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::nav
