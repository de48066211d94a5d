#include "sim/robot/robot_config.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace pavilion::sim {

void OdometryCalibration::Validate() const {
  constexpr double kMaxLengthM = 10.0;  // beyond any robot: a unit mistake
  constexpr double kMaxK = 1.0;         // §2.3 k (m); the thesis found 5e-6
  auto length = [](double v, const char* name) {
    if (!(v > 0.0 && v <= kMaxLengthM)) {
      throw std::invalid_argument(std::string("OdometryCalibration.") + name +
                                  " must be in (0, 10] m");
    }
  };
  auto noise = [](double v, const char* name) {
    if (!(v >= 0.0 && v <= kMaxK)) {
      throw std::invalid_argument(std::string("OdometryCalibration.") + name +
                                  " must be in [0, 1] m");
    }
  };
  length(left_wheel_radius_m, "left_wheel_radius_m");
  length(right_wheel_radius_m, "right_wheel_radius_m");
  length(wheelbase_m, "wheelbase_m");
  noise(k_left_m, "k_left_m");
  noise(k_right_m, "k_right_m");
  noise(k_turn_m, "k_turn_m");
}

void CameraMount::Validate() const {
  constexpr int kMaxSidePx = 100000;
  constexpr double kMaxRateHz = 1000.0;
  if (width_px < 1 || width_px > kMaxSidePx) {
    throw std::invalid_argument("CameraMount.width_px must be in [1, 100000]");
  }
  if (height_px < 1 || height_px > kMaxSidePx) {
    throw std::invalid_argument("CameraMount.height_px must be in [1, 100000]");
  }
  if (!(hfov_rad > 0.0 && hfov_rad < std::numbers::pi)) {
    throw std::invalid_argument("CameraMount.hfov_rad must be in (0, π) rad (a pinhole camera)");
  }
  if (!(rate_hz > 0.0 && rate_hz <= kMaxRateHz)) {
    throw std::invalid_argument("CameraMount.rate_hz must be in (0, 1000] Hz");
  }
}

}  // namespace pavilion::sim
