// Lost detection by repeated gate failures when the scan can or cannot show
// the map (LocalizerOptions::max_short_ratio_for_failure): visitors standing
// round a robot hide its walls, and the lines of their bodies pair with
// nothing, yet the robot is where it believes; a kidnapped robot's readings
// run through the walls its estimate predicts.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/localization/localizer.h"
#include "core/random/random_stream.h"
#include "tests/support/mcl_world.h"

namespace pavilion::core {
namespace {

using pavilion::testing::Wall;

constexpr double kCycleS = 0.1;  // one scan per 10 Hz cycle
constexpr double kStepS = 0.005;

EncoderOdometryOptions Wheels() { return {0.09, 0.09, 0.5, 5e-6, 5e-6}; }

// Five pairs of visitors, shoulder to shoulder, on a half circle of 1.3 m
// round the laser: their fronts (0.8 m a pair, a few centimetres apart)
// hide nearly all of the room's walls from a robot that faces them.
std::vector<Wall> CrowdAround(const Pose2& robot) {
  std::vector<Wall> bodies;
  const Pose2 laser = robot * Pose2{0.2, 0.0, 0.0};
  for (int k = -2; k <= 2; ++k) {
    const double bearing = laser.theta_rad + k * 0.62;
    const Eigen::Vector2d centre =
        laser.translation() + 1.3 * Eigen::Vector2d(std::cos(bearing), std::sin(bearing));
    const Eigen::Vector2d along(-std::sin(bearing), std::cos(bearing));
    bodies.emplace_back(centre - 0.4 * along, centre + 0.4 * along);
  }
  return bodies;
}

struct LostRun {
  LocalizationState state = LocalizationState::kTracking;
  LostReason reason = LostReason::kNone;
  long hidden_failures = 0;
  int cycles_without_pairing = 0;
};

// The robot stands at `estimate` for `cycles` scans taken from `truth`
// among the room's walls plus `others` (unmapped).
LostRun Stand(const Pose2& estimate, const Pose2& truth, const std::vector<Wall>& others,
              double max_short_ratio, int cycles) {
  LocalizerOptions options;
  options.odometry = Wheels();
  options.max_short_ratio_for_failure = max_short_ratio;
  Localizer localizer(pavilion::testing::LShapedRoomMap(), options);
  pavilion::testing::DriveSimulator drive(truth, options.odometry, 1.0);
  localizer.AddEncoders(drive.Reading());
  localizer.Initialize(estimate, Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal());
  std::vector<Wall> walls = pavilion::testing::LShapedRoomWalls();
  walls.insert(walls.end(), others.begin(), others.end());
  RandomStream noise(7, 1);
  LostRun run;
  for (int cycle = 0; cycle < cycles; ++cycle) {
    EncoderReading reading = drive.Reading();
    for (int k = 0; k < static_cast<int>(kCycleS / kStepS); ++k) reading = drive.Step(0, 0, kStepS);
    localizer.AddEncoders(reading);
    EXPECT_EQ(localizer.AddScan(pavilion::testing::CastScan(walls, truth, reading.stamp_s, &noise)),
              ObservationStatus::kIntegrated);
    run.cycles_without_pairing += localizer.last_cycle().matches.empty() ? 1 : 0;
  }
  run.state = localizer.status().state;
  run.reason = localizer.status().reason;
  run.hidden_failures = localizer.counters().hidden_failures;
  return run;
}

const Pose2 kRobot{3.0, 3.0, 0.0};  // in the long part, facing its east wall

TEST(LostDetection, ACrowdHidingTheWallsIsNotALoss) {
  const int cycles = 3 * LocalizerOptions{}.lost_failed_cycles;
  const LostRun run = Stand(kRobot, kRobot, CrowdAround(kRobot), 0.5, cycles);
  // Nothing paired (the bodies' lines are no wall's), yet the robot stays
  // localized: every failure was hidden.
  EXPECT_EQ(run.cycles_without_pairing, cycles);
  EXPECT_EQ(run.state, LocalizationState::kTracking);
  EXPECT_EQ(run.hidden_failures, cycles);
}

TEST(LostDetection, TheThesisRuleCountsTheCrowdAsALoss) {
  const LostRun run =
      Stand(kRobot, kRobot, CrowdAround(kRobot), 1.0, 3 * LocalizerOptions{}.lost_failed_cycles);
  EXPECT_EQ(run.state, LocalizationState::kLost);
  EXPECT_EQ(run.reason, LostReason::kRepeatedGateFailures);
  EXPECT_EQ(run.hidden_failures, 0);
}

TEST(LostDetection, AKidnappedRobotIsStillDeclaredLost) {
  // Carried 4 m east into the long part and turned: its readings run
  // through the walls its estimate predicts.
  const int needed = LocalizerOptions{}.lost_failed_cycles;
  const Pose2 truth{7.5, 2.2, 0.7};
  const LostRun before = Stand(kRobot, truth, {}, 0.5, needed - 1);
  EXPECT_EQ(before.state, LocalizationState::kTracking);
  const LostRun run = Stand(kRobot, truth, {}, 0.5, needed);
  EXPECT_EQ(run.cycles_without_pairing, needed);
  EXPECT_EQ(run.state, LocalizationState::kLost);
  EXPECT_EQ(run.reason, LostReason::kRepeatedGateFailures);
  EXPECT_EQ(run.hidden_failures, 0);
}

TEST(LostDetection, ValidatesTheRatio) {
  LocalizerOptions options;
  options.max_short_ratio_for_failure = 1.5;
  EXPECT_THROW(options.Validate(), std::invalid_argument);
  options.max_short_ratio_for_failure = -0.1;
  EXPECT_THROW(options.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::core
