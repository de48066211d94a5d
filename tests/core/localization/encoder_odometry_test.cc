// Wheel travels from encoder counts with calibrated radii (thesis eq. 2.5).
#include "core/localization/encoder_odometry.h"

#include <gtest/gtest.h>

#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace pavilion::core {
namespace {

// A full revolution of each wheel is 2 pi r of travel with that wheel's own
// calibrated radius; counts may go backwards.
TEST(EncoderOdometryTest, TicksBecomeWheelTravel) {
  EncoderOdometryOptions options;
  options.left_wheel_radius_m = 0.09;
  options.right_wheel_radius_m = 0.091;
  const EncoderReading a{0.0, 1000, -500, 25000};
  const EncoderReading b{0.005, 1000 + 25000, -500 - 12500, 25000};
  const WheelTravel t = WheelTravelFromEncoders(a, b, options);
  EXPECT_NEAR(t.left_m, 2.0 * std::numbers::pi * 0.09, 1e-12);
  EXPECT_NEAR(t.right_m, -std::numbers::pi * 0.091, 1e-12);
}

// A bad or changing ticks_per_revolution is rejected.
TEST(EncoderOdometryTest, RejectsBadResolution) {
  const EncoderOdometryOptions options;
  EXPECT_THROW(WheelTravelFromEncoders({0, 0, 0, 0}, {1, 10, 10, 0}, options),
               std::invalid_argument);
  EXPECT_THROW(WheelTravelFromEncoders({0, 0, 0, 100}, {1, 10, 10, 200}, options),
               std::invalid_argument);
}

// Every field is validated and named in the error.
TEST(EncoderOdometryTest, ValidatesEveryField) {
  const auto expect_field = [](EncoderOdometryOptions o, const std::string& field) {
    try {
      o.Validate();
      ADD_FAILURE() << "no throw for " << field;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
  };
  EncoderOdometryOptions o;
  EXPECT_NO_THROW(o.Validate());
  o.left_wheel_radius_m = 0.0;
  expect_field(o, "left_wheel_radius_m");
  o = {};
  o.right_wheel_radius_m = -1.0;
  expect_field(o, "right_wheel_radius_m");
  o = {};
  o.wheelbase_m = std::numeric_limits<double>::quiet_NaN();
  expect_field(o, "wheelbase_m");
  o = {};
  o.k_left_m = -1e-6;
  expect_field(o, "k_left_m");
  o = {};
  o.k_right_m = std::numeric_limits<double>::infinity();
  expect_field(o, "k_right_m");
}

}  // namespace
}  // namespace pavilion::core
