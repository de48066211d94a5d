#include "sim/sensors/robot_sensors.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace pavilion::sim {
namespace {

constexpr double kPi = std::numbers::pi;

EncoderOptions Pygmalion() {
  EncoderOptions o;
  o.ticks_per_revolution = 50000;
  return o;
}

TEST(WheelEncoders, CountTicksOfTheWheelAnglesQuantizedDownwards) {
  WheelEncoders enc(Pygmalion(), 0.09, 0.09, core::RandomStream(1, 2));
  enc.Read(0.0, 10.0, -3.0);  // counters start at zero wherever the wheels are
  const core::EncoderReading r = enc.Read(0.005, 10.0 + 2 * kPi, -3.0 - kPi / 2);
  EXPECT_EQ(r.left_ticks, 50000);
  EXPECT_EQ(r.right_ticks, -12500);
  EXPECT_EQ(r.ticks_per_revolution, 50000);
  EXPECT_EQ(r.stamp_s, 0.005);
  const core::EncoderReading s = enc.Read(0.01, 10.0 + 2 * kPi + 0.99 * 2 * kPi / 50000, -3.0);
  EXPECT_EQ(s.left_ticks, 50000);  // 0.99 of a tick is not counted yet
  EXPECT_EQ(s.right_ticks, 0);
}

// eq. 2.9: each wheel's travel error has variance k·|s| over a travel s,
// however it is cut into readings.
TEST(WheelEncoders, NoiseVarianceGrowsAsKTimesTravel) {
  EncoderOptions o = Pygmalion();
  o.ticks_per_revolution = 1 << 30;  // resolution far below the noise
  o.noise = true;
  o.k_left_m = 5e-6;
  o.k_right_m = 2e-5;
  const double radius = 0.09, travel = 10.0;
  const int draws = 2000, steps = 100;
  double sum_sq[2] = {0, 0};
  for (int d = 0; d < draws; ++d) {
    WheelEncoders enc(o, radius, radius, core::RandomStream(7, d));
    enc.Read(0, 0, 0);
    core::EncoderReading r;
    for (int i = 1; i <= steps; ++i) {
      const double angle = travel / radius * i / steps;
      r = enc.Read(i * 0.005, angle, -angle);  // magnitude matters, not direction
    }
    const double per_tick = 2 * kPi / o.ticks_per_revolution * radius;
    sum_sq[0] += std::pow(r.left_ticks * per_tick - travel, 2);
    sum_sq[1] += std::pow(r.right_ticks * per_tick + travel, 2);
  }
  EXPECT_NEAR(sum_sq[0] / draws, o.k_left_m * travel, 0.1 * o.k_left_m * travel);
  EXPECT_NEAR(sum_sq[1] / draws, o.k_right_m * travel, 0.1 * o.k_right_m * travel);
}

TEST(WheelEncoders, NoiseOffOrSameSeedIsReproducible) {
  EncoderOptions o = Pygmalion();
  o.k_left_m = o.k_right_m = 1e-4;
  WheelEncoders quiet(o, 0.09, 0.09, core::RandomStream(1, 1));
  quiet.Read(0, 0, 0);
  EXPECT_EQ(quiet.Read(1, 2 * kPi, 2 * kPi).left_ticks, 50000);  // noise flag off
  o.noise = true;
  WheelEncoders a(o, 0.09, 0.09, core::RandomStream(3, 4));
  WheelEncoders b(o, 0.09, 0.09, core::RandomStream(3, 4));
  WheelEncoders c(o, 0.09, 0.09, core::RandomStream(3, 5));
  a.Read(0, 0, 0), b.Read(0, 0, 0), c.Read(0, 0, 0);
  const auto ra = a.Read(1, 50, 60), rb = b.Read(1, 50, 60), rc = c.Read(1, 50, 60);
  EXPECT_EQ(ra.left_ticks, rb.left_ticks);
  EXPECT_EQ(ra.right_ticks, rb.right_ticks);
  EXPECT_NE(ra.left_ticks, rc.left_ticks);
}

TEST(WheelEncoders, RejectInvalidOptions) {
  EncoderOptions o;
  o.ticks_per_revolution = 0;
  EXPECT_THROW(WheelEncoders(o, 0.1, 0.1, core::RandomStream(1, 1)), std::invalid_argument);
  EXPECT_THROW(WheelEncoders(EncoderOptions{}, 0.0, 0.1, core::RandomStream(1, 1)),
               std::invalid_argument);
}

TEST(Bumpers, ContactBearingsPressTheirZonesIncludingOneAcrossTheRear) {
  const std::vector<BumperZone> zones = {{"front", -kPi / 4, kPi / 4},
                                         {"left", kPi / 4, 3 * kPi / 4},
                                         {"rear", 3 * kPi / 4, -3 * kPi / 4},  // crosses ±π
                                         {"right", -3 * kPi / 4, -kPi / 4}};
  EXPECT_EQ(PressedBumperZones(zones, {}), 0u);
  EXPECT_EQ(PressedBumperZones(zones, {{0.3, 0.05}}), 1u);
  EXPECT_EQ(PressedBumperZones(zones, {{0.0, 0.3}}), 2u);
  EXPECT_EQ(PressedBumperZones(zones, {{-0.3, 0.01}, {-0.3, -0.01}}), 4u);
  EXPECT_EQ(PressedBumperZones(zones, {{0.1, -0.3}, {0.3, 0.0}}), 9u);
}

}  // namespace
}  // namespace pavilion::sim
