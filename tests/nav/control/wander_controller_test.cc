// The hall benchmark's wander controller, rule by rule (nav/control/wander_controller.h).
#include "nav/control/wander_controller.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace pavilion::nav {
namespace {

constexpr int kBeams = 361;  // the benchmark's laser
constexpr double kFarM = 5.0;
constexpr std::uint64_t kSeed = 7;
constexpr std::uint64_t kStream = 11;

// A scan with every reading at `range_m`, in bearing order, right to left.
std::vector<core::LaserReading> Scan(double range_m = kFarM, int beams = kBeams) {
  std::vector<core::LaserReading> readings(beams);
  for (int i = 0; i < beams; ++i) {
    readings[i].range_m = range_m;
    readings[i].valid = true;
  }
  return readings;
}

std::vector<core::LaserReading> ScanWith(int i, double range_m) {
  auto readings = Scan();
  readings[i].range_m = range_m;
  return readings;
}

WanderController Make() { return WanderController({}, core::RandomStream(kSeed, kStream)); }

// Nothing near: cruise at 0.4 m/s straight ahead, no manoeuvre.
TEST(WanderControllerTest, CruisesWhenNothingIsNear) {
  WanderController w = Make();
  const VelocityCommand c = w.Update(Scan());
  EXPECT_DOUBLE_EQ(c.linear_mps, 0.4);
  EXPECT_DOUBLE_EQ(c.angular_radps, 0.0);
  EXPECT_EQ(w.avoid_scans_left(), 0);
}

// Obstruction: a reading below 1 m strictly inside the front third (n/3 < i <
// n - n/3 with integer division: 121..240 of 361) slows to 0.05 m/s and turns;
// the same reading just outside it (120, 241) does not.
TEST(WanderControllerTest, ObstructionOnlyInTheFrontThird) {
  for (int i : {121, 180, 240}) {
    WanderController w = Make();
    const VelocityCommand c = w.Update(ScanWith(i, 0.99));
    EXPECT_DOUBLE_EQ(c.linear_mps, 0.05) << "reading " << i;
    EXPECT_DOUBLE_EQ(std::abs(c.angular_radps), 0.5) << "reading " << i;
  }
  for (int i : {0, 120, 241, 360}) {
    WanderController w = Make();
    const VelocityCommand c = w.Update(ScanWith(i, 0.99));
    EXPECT_DOUBLE_EQ(c.linear_mps, 0.4) << "reading " << i;
    EXPECT_DOUBLE_EQ(c.angular_radps, 0.0) << "reading " << i;
  }
  // At exactly 1 m nothing obstructs ("below 1.0 m").
  WanderController w = Make();
  EXPECT_DOUBLE_EQ(w.Update(ScanWith(180, 1.0)).linear_mps, 0.4);
}

// Stop: a reading below 0.3 m anywhere, even outside the front third, stops the
// robot (speed 0) while it turns away.
TEST(WanderControllerTest, StopsForAnyReadingBelowThirtyCentimetres) {
  for (int i : {0, 60, 180, 300, 360}) {
    WanderController w = Make();
    const VelocityCommand c = w.Update(ScanWith(i, 0.29));
    EXPECT_DOUBLE_EQ(c.linear_mps, 0.0) << "reading " << i;
    EXPECT_DOUBLE_EQ(std::abs(c.angular_radps), 0.5) << "reading " << i;
  }
  WanderController w = Make();
  EXPECT_DOUBLE_EQ(w.Update(ScanWith(0, 0.3)).linear_mps, 0.4);  // not below
}

// A manoeuvre turns away from the nearer side: right (-0.5 rad/s) when the
// smallest reading with i > n/2 (left) is below the others', else left
// (+0.5), ties included; reading n/2 itself counts as right.
TEST(WanderControllerTest, TurnsAwayFromTheNearerSide) {
  auto left_near = ScanWith(200, 0.5);
  left_near[150].range_m = 0.8;
  EXPECT_DOUBLE_EQ(Make().Update(left_near).angular_radps, -0.5);
  auto right_near = ScanWith(200, 0.8);
  right_near[150].range_m = 0.5;
  EXPECT_DOUBLE_EQ(Make().Update(right_near).angular_radps, 0.5);
  auto tie = ScanWith(200, 0.5);
  tie[150].range_m = 0.5;
  EXPECT_DOUBLE_EQ(Make().Update(tie).angular_radps, 0.5);
  // Reading 181 is the first on the left, 180 the last on the right.
  EXPECT_DOUBLE_EQ(Make().Update(ScanWith(181, 0.5)).angular_radps, -0.5);
  EXPECT_DOUBLE_EQ(Make().Update(ScanWith(180, 0.5)).angular_radps, 0.5);
}

// Once started, a manoeuvre keeps its turn for its whole drawn length — even
// when the obstacle moves to the other side or disappears — and the robot
// cruises on the scan after it ends.
TEST(WanderControllerTest, KeepsTheTurnForTheWholeManoeuvre) {
  WanderController w = Make();
  // The length is the stream's first draw from [10, 19].
  core::RandomStream reference(kSeed, kStream);
  const int length = static_cast<int>(reference.UniformInt(10, 19));
  const VelocityCommand first = w.Update(ScanWith(200, 0.5));  // left: turn right
  ASSERT_DOUBLE_EQ(first.angular_radps, -0.5);
  EXPECT_EQ(w.avoid_scans_left(), length - 1);
  // Next scan: the obstacle is on the right now; the turn is kept.
  VelocityCommand c = w.Update(ScanWith(150, 0.5));
  EXPECT_DOUBLE_EQ(c.angular_radps, -0.5);
  EXPECT_DOUBLE_EQ(c.linear_mps, 0.05);
  // Free space for the rest of the manoeuvre: still avoiding at 0.05 m/s.
  for (int k = 2; k < length; ++k) {
    c = w.Update(Scan());
    EXPECT_DOUBLE_EQ(c.angular_radps, -0.5) << "scan " << k;
    EXPECT_DOUBLE_EQ(c.linear_mps, 0.05) << "scan " << k;
  }
  EXPECT_EQ(w.avoid_scans_left(), 0);
  c = w.Update(Scan());
  EXPECT_DOUBLE_EQ(c.linear_mps, 0.4);
  EXPECT_DOUBLE_EQ(c.angular_radps, 0.0);
}

// During a manoeuvre the speed follows each scan: 0 while something is below
// 0.3 m, 0.05 m/s otherwise.
TEST(WanderControllerTest, SpeedFollowsEachScanDuringAManoeuvre) {
  WanderController w = Make();
  EXPECT_DOUBLE_EQ(w.Update(ScanWith(180, 0.2)).linear_mps, 0.0);
  EXPECT_DOUBLE_EQ(w.Update(Scan()).linear_mps, 0.05);
  EXPECT_DOUBLE_EQ(w.Update(ScanWith(10, 0.1)).linear_mps, 0.0);
  EXPECT_DOUBLE_EQ(w.Update(Scan()).linear_mps, 0.05);
}

// An obstruction still there when a manoeuvre ends starts a new one: a fresh
// length from the stream and the side chosen anew.
TEST(WanderControllerTest, StartsANewManoeuvreWhileStillObstructed) {
  WanderController w = Make();
  core::RandomStream reference(kSeed, kStream);
  const int first = static_cast<int>(reference.UniformInt(10, 19));
  const int second = static_cast<int>(reference.UniformInt(10, 19));
  for (int k = 0; k < first; ++k)
    EXPECT_DOUBLE_EQ(w.Update(ScanWith(200, 0.5)).angular_radps, -0.5);
  EXPECT_EQ(w.avoid_scans_left(), 0);
  EXPECT_DOUBLE_EQ(w.Update(ScanWith(150, 0.5)).angular_radps, 0.5);  // now right is nearer
  EXPECT_EQ(w.avoid_scans_left(), second - 1);
}

// Manoeuvre lengths are uniform over 10..19 scans: every length occurs, and a
// chi-square test over the ten values passes (9 dof, p > 0.001: < 27.88).
TEST(WanderControllerTest, ManoeuvreLengthsAreUniformFromTenToNineteenScans) {
  WanderController w = Make();
  std::array<int, 10> counts{};
  constexpr int kManoeuvres = 5000;
  for (int m = 0; m < kManoeuvres; ++m) {
    w.Update(ScanWith(180, 0.5));  // starts one
    const int length = w.avoid_scans_left() + 1;
    ASSERT_GE(length, 10);
    ASSERT_LE(length, 19);
    ++counts[length - 10];
    while (w.avoid_scans_left() > 0) w.Update(Scan());
    w.Update(Scan());  // cruise: the next obstruction starts a new manoeuvre
  }
  const double expected = kManoeuvres / 10.0;
  double chi2 = 0.0;
  for (int c : counts) {
    EXPECT_GT(c, 0);
    chi2 += (c - expected) * (c - expected) / expected;
  }
  EXPECT_LT(chi2, 27.88);
}

// The same seed and stream give the same commands; the draws are the only
// randomness.
TEST(WanderControllerTest, SameStreamSameCommands) {
  WanderController a = Make(), b = Make();
  for (int k = 0; k < 200; ++k) {
    const auto scan = (k % 7 < 3) ? ScanWith(170 + k % 20, 0.6) : Scan();
    const VelocityCommand ca = a.Update(scan), cb = b.Update(scan);
    EXPECT_EQ(ca.linear_mps, cb.linear_mps);
    EXPECT_EQ(ca.angular_radps, cb.angular_radps);
  }
}

// Readings without a return are free space, whatever range they carry; an
// empty scan keeps the last command.
TEST(WanderControllerTest, NoReturnIsFreeSpaceAndEmptyScansKeepTheCommand) {
  WanderController w = Make();
  auto readings = ScanWith(180, 0.1);
  readings[180].valid = false;
  EXPECT_DOUBLE_EQ(w.Update(readings).linear_mps, 0.4);
  w.Update(ScanWith(180, 0.5));
  const VelocityCommand before = w.command();
  const VelocityCommand after = w.Update({});
  EXPECT_EQ(after.linear_mps, before.linear_mps);
  EXPECT_EQ(after.angular_radps, before.angular_radps);
}

// Options are validated, naming the field.
TEST(WanderControllerTest, RejectsInvalidOptions) {
  const auto message = [](WanderOptions o) {
    try {
      o.Validate();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  WanderOptions o;
  EXPECT_EQ(message(o), "");
  o.stop_distance_m = 2.0;
  EXPECT_NE(message(o).find("stop_distance_m"), std::string::npos);
  o = {};
  o.max_avoid_scans = 5;
  EXPECT_NE(message(o).find("max_avoid_scans"), std::string::npos);
  o = {};
  o.avoid_turn_rate_radps = 0.0;
  EXPECT_NE(message(o).find("avoid_turn_rate_radps"), std::string::npos);
  o = {};
  o.cruise_speed_mps = std::nan("");
  EXPECT_NE(message(o).find("cruise_speed_mps"), std::string::npos);
  o = {};
  o.min_avoid_scans = 0;
  EXPECT_THROW(WanderController(o, core::RandomStream(1, 1)), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::nav
