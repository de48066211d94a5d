// Slip and floor patches in the wheel encoders (sim::EncoderOptions, issue 20):
// each has the statistics it claims, and turning one on leaves every other
// draw as it was.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "sim/sensors/encoder_sensor.h"
#include "sim/sensors/robot_sensors.h"

namespace pavilion::sim {
namespace {

constexpr double kRadiusM = 0.075;
constexpr int kTicks = 50000;
constexpr double kDtS = 0.005;

// Travel (m) the counts of a reading stand for, per wheel.
double Travel(std::int64_t ticks) {
  return static_cast<double>(ticks) / kTicks * 2.0 * std::numbers::pi * kRadiusM;
}

EncoderOptions Options() {
  EncoderOptions o;
  o.ticks_per_revolution = kTicks;
  o.noise = true;
  return o;
}

// Drives a profile of (left, right) wheel speeds (m/s), one reading per 5 ms,
// and returns the final measured travel minus the true one, per wheel.
std::pair<double, double> FinalError(const EncoderOptions& options, std::uint64_t seed,
                                     const std::vector<std::pair<double, double>>& speeds) {
  WheelEncoders enc(options, kRadiusM, kRadiusM, core::RandomStream(seed, 1));
  double left = 0.0, right = 0.0;
  core::EncoderReading r = enc.Read(0.0, 0.0, 0.0);
  for (std::size_t k = 0; k < speeds.size(); ++k) {
    left += speeds[k].first * kDtS / kRadiusM;
    right += speeds[k].second * kDtS / kRadiusM;
    r = enc.Read((k + 1) * kDtS, left, right);
  }
  return {Travel(r.left_ticks) - left * kRadiusM, Travel(r.right_ticks) - right * kRadiusM};
}

// Turn slip: the wheels' travel difference has variance k_turn·|Δs_r − Δs_l|,
// split as −d/2, +d/2 (their sum untouched).
TEST(EncoderSlipTest, TurnSlipHasItsVariance) {
  EncoderOptions o = Options();
  o.k_turn_m = 1e-4;
  // Turning on the spot: right +0.2 m/s, left −0.2 m/s for 5 s: |Δs_r − Δs_l| = 2 m.
  const std::vector<std::pair<double, double>> spin(1000, {-0.2, 0.2});
  double sum2 = 0.0, sum_sum2 = 0.0;
  const int runs = 400;
  for (int seed = 1; seed <= runs; ++seed) {
    const auto [el, er] = FinalError(o, seed, spin);
    sum2 += (er - el) * (er - el);
    sum_sum2 += (er + el) * (er + el);
  }
  const double expected = 1e-4 * 2.0;                   // Var(d)
  EXPECT_NEAR(sum2 / runs, expected, 0.15 * expected);  // 400 runs: 7 % standard error
  // The sum moves only by the tick quantization (1e-5 m per wheel).
  EXPECT_LT(std::sqrt(sum_sum2 / runs), 3e-5);
}

// Acceleration slip: variance k_accel·|a|·|Δs| per wheel and reading; none
// at constant speed.
TEST(EncoderSlipTest, AccelerationSlipGrowsWithAcceleration) {
  EncoderOptions o = Options();
  o.k_accel_s2 = 1e-4;
  std::vector<std::pair<double, double>> cruise(1000, {0.4, 0.4});
  std::vector<std::pair<double, double>> ramp;
  for (int k = 0; k < 1000; ++k) ramp.push_back({0.1 * (k + 1) * kDtS, 0.1 * (k + 1) * kDtS});
  double cruise2 = 0.0, ramp2 = 0.0;
  const int runs = 400;
  for (int seed = 1; seed <= runs; ++seed) {
    const double c = FinalError(o, seed, cruise).first;
    const double r = FinalError(o, seed, ramp).first;
    cruise2 += c * c;
    ramp2 += r * r;
  }
  // The ramp: a = 0.1 m/s², travel 1.25 m: variance 1e-4 · 0.1 · 1.25.
  const double expected = 1e-4 * 0.1 * 1.25;
  EXPECT_NEAR(ramp2 / runs, expected, 0.2 * expected);
  // The cruise: one reading of acceleration at the start (0 -> 0.4 m/s in 5 ms).
  const double start = 1e-4 * (0.4 / kDtS) * (0.4 * kDtS);
  EXPECT_NEAR(cruise2 / runs, start, 0.25 * start);
}

// A floor patch: the counts grow by (1 + error) while the wheel is on it.
TEST(EncoderSlipTest, CarpetScalesTheCountsWhereTheWheelStands) {
  EncoderOptions o = Options();
  o.noise = false;
  o.patches.push_back({"carpet", {{1.0, -5.0}, {3.0, -5.0}, {3.0, 5.0}, {1.0, 5.0}}, 0.01});
  EncoderSensor sensor("robot", o, kRadiusM, kRadiusM, core::RandomStream(1, 1), 200.0,
                       Eigen::Vector2d(0.0, 0.19), Eigen::Vector2d(0.0, -0.19));
  SensorTick tick;
  SensorOutputs out;
  // Drive straight along x at 0.5 m/s from x = 0 to 4 m.
  const double step_m = 0.5 * kDtS;
  for (int k = 0; k < 1600; ++k) {
    tick.start_s = k * kDtS;
    tick.end_s = (k + 1) * kDtS;
    tick.before.pose = core::Pose2{k * step_m, 0.0, 0.0};
    tick.after.pose = core::Pose2{(k + 1) * step_m, 0.0, 0.0};
    tick.before.left_wheel_rad = tick.before.right_wheel_rad = k * step_m / kRadiusM;
    tick.after.left_wheel_rad = tick.after.right_wheel_rad = (k + 1) * step_m / kRadiusM;
    sensor.Sample(tick, &out);
  }
  const core::EncoderReading& last = out.encoders.back();
  // 4 m true, less the first step (the counters start at the first reading),
  // 2 m of it on the carpet: 0.02 m more counted, to a tick.
  EXPECT_NEAR(Travel(last.left_ticks), 4.0 - step_m + 0.01 * 2.0, 2e-5);
  EXPECT_NEAR(Travel(last.right_ticks), Travel(last.left_ticks), 1e-5);
}

// Slip off (zero coefficients) draws nothing: the k noise stays as it was.
TEST(EncoderSlipTest, SlipOffChangesNothing) {
  EncoderOptions k_only = Options();
  k_only.k_left_m = k_only.k_right_m = 5e-6;
  EncoderOptions with_zero_slip = k_only;
  with_zero_slip.k_turn_m = 0.0;
  with_zero_slip.k_accel_s2 = 0.0;
  std::vector<std::pair<double, double>> drive(500, {0.3, 0.35});
  const auto a = FinalError(k_only, 7, drive);
  const auto b = FinalError(with_zero_slip, 7, drive);
  EXPECT_EQ(a, b);
  EncoderOptions bad = Options();
  bad.k_accel_s2 = -1.0;
  EXPECT_THROW(bad.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::sim
