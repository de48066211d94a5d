#include "scenarios/datasets/carmen_log.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>

#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

using pavilion::testing::Contains;
using pavilion::testing::LineOf;
using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

// The shipped real logs, beside the repository (../shared/data/carmen).
std::string CarmenPath(const std::string& name) {
  return pavilion::testing::CarmenDataDir() + "/" + name + "-corrected.log.gz";
}

// What the data set's README states per log, plus the counts of the files and
// the angular step chosen with DecideCarmenAngleStep (docs/carmen_logs.md).
struct Expected {
  int scans;
  int readings;
  int unknown_intervals;
  CarmenAngleStep step;
};
const std::map<std::string, Expected>& ExpectedLogs() {
  static const std::map<std::string, Expected> logs = {
      {"intel", {910, 180, 0, CarmenAngleStep::kFovOverN}},
      {"aces", {440, 180, 0, CarmenAngleStep::kFovOverNMinus1}},
      {"csail", {406, 361, 0, CarmenAngleStep::kFovOverNMinus1}},
      {"freiburg-101", {292, 360, 0, CarmenAngleStep::kFovOverN}},
      {"orebro", {237, 181, 219, CarmenAngleStep::kFovOverNMinus1}},
      {"infinite-corridor", {1941, 180, 0, CarmenAngleStep::kFovOverN}},
  };
  return logs;
}

// Parses the six logs once for the whole suite.
class CarmenLogsTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    logs_ = new std::map<std::string, CarmenLog>();
    for (const auto& [name, expected] : ExpectedLogs()) {
      const auto start = std::chrono::steady_clock::now();
      (*logs_)[name] = ReadCarmenLog(CarmenPath(name));
      const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
      std::cout << name << ": parsed in " << elapsed.count() << " s\n";
    }
  }
  static void TearDownTestSuite() {
    delete logs_;
    logs_ = nullptr;
  }
  static const CarmenLog& Log(const std::string& name) { return logs_->at(name); }

 private:
  static std::map<std::string, CarmenLog>* logs_;
};
std::map<std::string, CarmenLog>* CarmenLogsTest::logs_ = nullptr;

// Every log parses with its scan count and the README's n on every scan;
// bearings run from -90° counter-clockwise; no-returns are invalid.
TEST_F(CarmenLogsTest, ParsesEveryLogWithItsReadingCount) {
  for (const auto& [name, expected] : ExpectedLogs()) {
    SCOPED_TRACE(name);
    const CarmenLog& log = Log(name);
    ASSERT_EQ(static_cast<int>(log.scans.size()), expected.scans);
    int invalid = 0;
    for (const CarmenScan& s : log.scans) {
      ASSERT_EQ(static_cast<int>(s.scan.readings.size()), expected.readings) << "line " << s.line;
      EXPECT_DOUBLE_EQ(s.scan.readings.front().bearing_rad, -std::numbers::pi / 2.0);
      EXPECT_DOUBLE_EQ(
          s.scan.readings.back().bearing_rad,
          -std::numbers::pi / 2.0 + (expected.readings - 1) * std::numbers::pi / expected.readings);
      for (const core::LaserReading& r : s.scan.readings) {
        if (!r.valid) {
          ++invalid;
          EXPECT_EQ(r.range_m, s.scan.max_range_m);
        } else {
          EXPECT_GT(r.range_m, 0.0);
          EXPECT_LT(r.range_m, 30.0);
        }
      }
    }
    // Real logs have some no-returns, but most readings hit something.
    EXPECT_GT(invalid, 0);
    EXPECT_LT(invalid, expected.scans * expected.readings / 2);
  }
}

// The README's intel example: between the scans at 309.5 s and 313.1 s the
// wheels turned -0.105 rad where the corrected poses turned -0.055 rad.
TEST_F(CarmenLogsTest, IntelOdometryMatchesTheReadmeExample) {
  const CarmenLog& log = Log("intel");
  std::size_t k = 0;
  while (k < log.scans.size() && std::abs(log.scans[k].stamp_s - 313.1) > 0.05) ++k;
  ASSERT_LT(k, log.scans.size());
  ASSERT_GT(k, 0u);
  const CarmenScan& previous = log.scans[k - 1];
  const CarmenScan& current = log.scans[k];
  EXPECT_NEAR(previous.stamp_s, 309.5, 0.05);
  ASSERT_TRUE(current.odometry_known);
  EXPECT_NEAR(current.previous_from_current_odom.theta_rad, -0.105, 0.002);
  const core::Pose2 reference = previous.world_from_laser.Inverse() * current.world_from_laser;
  EXPECT_NEAR(reference.theta_rad, -0.055, 0.002);
  // Forward motion of about a metre in both (the robot drove along its x axis).
  EXPECT_NEAR(current.previous_from_current_odom.x_m, 1.02, 0.05);
  EXPECT_NEAR(reference.x_m, 1.03, 0.05);
}

// Missing wheel odometry is flagged unknown, never reported as standing still:
// orebro lacks it for 219 of its 236 intervals, the other logs have it throughout.
TEST_F(CarmenLogsTest, MissingOdometryIsUnknown) {
  for (const auto& [name, expected] : ExpectedLogs()) {
    SCOPED_TRACE(name);
    const CarmenLog& log = Log(name);
    EXPECT_FALSE(log.scans.front().odometry_known);
    EXPECT_EQ(log.UnknownOdometryIntervals(), expected.unknown_intervals);
    for (const CarmenScan& s : log.scans) {
      if (!s.odometry_known) {
        EXPECT_EQ(s.previous_from_current_odom, core::Pose2{});
      }
    }
  }
}

// The per-log angular step recorded in docs/carmen_logs.md is the one that
// makes long straight walls straightest.
TEST_F(CarmenLogsTest, AngleStepDecisionPerLog) {
  for (const auto& [name, expected] : ExpectedLogs()) {
    SCOPED_TRACE(name);
    const CarmenAngleStepDecision d = DecideCarmenAngleStep(Log(name));
    std::cout << name << ": runs " << d.runs << " points " << d.points << " rms 180/n "
              << d.rms_fov_over_n_m * 1000.0 << " mm, 180/(n-1) "
              << d.rms_fov_over_n_minus_1_m * 1000.0 << " mm, median step fraction "
              << d.median_step_fraction << " paired z " << d.paired_z << "\n";
    EXPECT_GT(d.runs, 100);
    EXPECT_EQ(d.step, expected.step);
  }
}

// A log of straight walls rendered with a known step: the criterion recovers
// that step, for both conventions.
TEST(CarmenAngleStepTest, RecoversTheStepOfSyntheticWalls) {
  for (const CarmenAngleStep truth :
       {CarmenAngleStep::kFovOverN, CarmenAngleStep::kFovOverNMinus1}) {
    CarmenLog log;
    constexpr int kReadings = 180;
    for (int k = 0; k < 20; ++k) {
      // Robot in a 6 m wide corridor, rotated a little more each scan.
      const double heading = 0.05 * k;
      CarmenScan s;
      s.scan.max_range_m = 30.0;
      for (int i = 0; i < kReadings; ++i) {
        const double bearing = CarmenBearingRad(i, kReadings, truth);
        const double phi = bearing + heading;  // beam direction in the corridor frame
        const double s_phi = std::sin(phi);
        core::LaserReading r;
        r.range_m = std::abs(s_phi) > 1e-3 ? 3.0 / std::abs(s_phi) : 31.0;
        r.valid = r.range_m < 20.0;
        if (!r.valid) r.range_m = 30.0;
        r.bearing_rad = CarmenBearingRad(i, kReadings, CarmenAngleStep::kFovOverN);
        s.scan.readings.push_back(r);
      }
      log.scans.push_back(s);
    }
    const CarmenAngleStepDecision d = DecideCarmenAngleStep(log);
    EXPECT_EQ(d.step, truth);
    EXPECT_NEAR(d.median_step_fraction, truth == CarmenAngleStep::kFovOverN ? 0.0 : 1.0, 0.05);
  }
}

// Plain-text logs parse; PARAM, NEFF, RLASER and comments are skipped; the
// odometry increment is the anchor-to-last motion in the anchor's frame.
TEST(CarmenLogTest, ReadsPlainTextAndSkipsOtherMessages) {
  const std::string text =
      "# message formats defined: PARAM ODOM FLASER\n"
      "PARAM robot_use_laser on nohost 0\n"
      "ODOM 9 9 9 0 0 0 0 pippo 0\n"
      "FLASER 4 1.0 2.0 50.0 0.0 1 2 0.5 1 2 0.5 10.0 host 10.0\n"
      "ODOM 1 2 0.5 0 0 0 0 pippo 0\n"
      "RLASER 2 1 1 0 0 0 0 0 0 11.0 host 11.0\n"
      "ODOM 1 3 0.6 0 0 0 10.5 pippo 10.5\n"
      "NEFF 60\n"
      "ODOM 1 4 0.7 0 0 0 10.9 pippo 10.9\n"
      "FLASER 4 1.0 2.0 3.0 4.0 1 4 0.7 1 4 0.7 11.0 host 11.0\n"
      "ODOM 1 4 0.7 0 0 0 0 pippo 0\n"
      "FLASER 4 1.0 2.0 3.0 4.0 1 4 0.7 1 4 0.7 12.0 host 12.0\n";
  const std::string path = WriteFile(TestDir(), "tiny.log", text);
  CarmenOptions options;
  options.angle_step = CarmenAngleStep::kFovOverNMinus1;
  const CarmenLog log = ReadCarmenLog(path, options);
  ASSERT_EQ(log.scans.size(), 3u);
  EXPECT_EQ(log.scans[0].line, 4);
  EXPECT_FALSE(log.scans[0].odometry_known);
  EXPECT_TRUE(log.scans[0].scan.readings[1].valid);
  EXPECT_FALSE(log.scans[0].scan.readings[2].valid);  // 50 m >= max_range_m
  EXPECT_FALSE(log.scans[0].scan.readings[3].valid);  // 0 m: no return
  EXPECT_DOUBLE_EQ(log.scans[0].scan.readings[3].bearing_rad, std::numbers::pi / 2.0);
  EXPECT_DOUBLE_EQ(log.scans[0].stamp_s, 10.0);
  EXPECT_EQ(log.scans[0].world_from_laser, (core::Pose2{1, 2, 0.5}));
  // Anchor (1, 2, 0.5) to last (1, 4, 0.7): 2 m along world y, in the anchor frame.
  ASSERT_TRUE(log.scans[1].odometry_known);
  const core::Pose2& d = log.scans[1].previous_from_current_odom;
  EXPECT_NEAR(d.x_m, 2.0 * std::sin(0.5), 1e-12);
  EXPECT_NEAR(d.y_m, 2.0 * std::cos(0.5), 1e-12);
  EXPECT_NEAR(d.theta_rad, 0.2, 1e-12);
  // Only the anchor between the last two scans: unknown, not zero motion.
  EXPECT_FALSE(log.scans[2].odometry_known);
  EXPECT_EQ(log.UnknownOdometryIntervals(), 1);
}

// A malformed line throws one line naming the file and the line number.
TEST(CarmenLogTest, MalformedLinesNameFileAndLine) {
  const std::string good = "FLASER 3 1 2 3 0 0 0 0 0 0 1.0 host 1.0\n";
  const std::map<std::string, std::string> cases = {
      {"non-numeric range", "FLASER 3 1 x 3 0 0 0 0 0 0 2.0 host 2.0\n"},
      {"too few ranges", "FLASER 3 1 2 0 0 0 0 0 0 2.0 host 2.0\n"},
      {"bad count", "FLASER -3 1 2 3 0 0 0 0 0 0 2.0 host 2.0\n"},
      {"short odom", "ODOM 1 2\n"},
      {"nan odom", "ODOM 1 nan 0 0 0 0 1.5 pippo 1.5\n"},
  };
  for (const auto& [what, bad] : cases) {
    SCOPED_TRACE(what);
    const std::string text = "PARAM a b nohost 0\n" + good + "ODOM 0 0 0 0 0 0 0 h 0\n" + bad;
    const std::string path = WriteFile(TestDir(), "bad.log", text);
    try {
      ReadCarmenLog(path);
      ADD_FAILURE() << "no error for " << what;
    } catch (const std::runtime_error& e) {
      const std::string message = e.what();
      EXPECT_TRUE(Contains(message, path + ":" + std::to_string(LineOf(text, bad))));
      EXPECT_EQ(message.find('\n'), std::string::npos);
    }
  }
  EXPECT_THROW(ReadCarmenLog((TestDir() / "missing.log.gz").string()), std::runtime_error);
  CarmenOptions options;
  options.max_range_m = 0.0;
  EXPECT_THROW(ReadCarmenLog(WriteFile(TestDir(), "ok.log", good), options), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::scenarios
