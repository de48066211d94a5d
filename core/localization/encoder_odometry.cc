#include "core/localization/encoder_odometry.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace pavilion::core {

void EncoderOdometryOptions::Validate() const {
  constexpr double kMaxLengthM = 10.0;  // beyond any robot: a unit mistake
  constexpr double kMaxK = 1.0;         // §2.3 k (m); the thesis found 5e-6
  const auto length = [](double v, const char* name) {
    if (!(v > 0.0 && v <= kMaxLengthM)) {
      throw std::invalid_argument(std::string(name) + " must be in (0, 10] m");
    }
  };
  const auto noise = [](double v, const char* name) {
    if (!(v >= 0.0 && v <= kMaxK)) {
      throw std::invalid_argument(std::string(name) + " must be in [0, 1] m");
    }
  };
  length(left_wheel_radius_m, "left_wheel_radius_m");
  length(right_wheel_radius_m, "right_wheel_radius_m");
  length(wheelbase_m, "wheelbase_m");
  noise(k_left_m, "k_left_m");
  noise(k_right_m, "k_right_m");
  noise(k_turn_m, "k_turn_m");
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
