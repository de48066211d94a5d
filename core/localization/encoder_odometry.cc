#include "core/localization/encoder_odometry.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace pavilion::core {
namespace {

void Require(bool ok, const char* field, const char* expected) {
  if (!ok) throw std::invalid_argument(std::string(field) + " must be " + expected);
}

}  // namespace

void EncoderOdometryOptions::Validate() const {
  Require(std::isfinite(left_wheel_radius_m) && left_wheel_radius_m > 0.0, "left_wheel_radius_m",
          "a finite value > 0");
  Require(std::isfinite(right_wheel_radius_m) && right_wheel_radius_m > 0.0, "right_wheel_radius_m",
          "a finite value > 0");
  Require(std::isfinite(wheelbase_m) && wheelbase_m > 0.0, "wheelbase_m", "a finite value > 0");
  Require(std::isfinite(k_left_m) && k_left_m >= 0.0, "k_left_m", "a finite value >= 0");
  Require(std::isfinite(k_right_m) && k_right_m >= 0.0, "k_right_m", "a finite value >= 0");
  Require(std::isfinite(k_turn_m) && k_turn_m >= 0.0, "k_turn_m", "a finite value >= 0");
}

WheelTravel WheelTravelFromEncoders(const EncoderReading& previous, const EncoderReading& current,
                                    const EncoderOdometryOptions& options) {
  if (current.ticks_per_revolution <= 0 ||
      current.ticks_per_revolution != previous.ticks_per_revolution) {
    throw std::invalid_argument(
        "EncoderReading.ticks_per_revolution must be > 0 and the same in consecutive readings");
  }
  const double radians_per_tick = 2.0 * std::numbers::pi / current.ticks_per_revolution;
  return {static_cast<double>(current.left_ticks - previous.left_ticks) * radians_per_tick *
              options.left_wheel_radius_m,
          static_cast<double>(current.right_ticks - previous.right_ticks) * radians_per_tick *
              options.right_wheel_radius_m};
}

void DeadReckoning::Update(const EncoderReading& reading) {
  if (last_) {
    pose_ = DiffDriveStep(pose_, WheelTravelFromEncoders(*last_, reading, options_),
                          options_.wheelbase_m);
  }
  last_ = reading;
}

}  // namespace pavilion::core
