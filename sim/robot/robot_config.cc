#include "sim/robot/robot_config.h"

#include <cmath>
#include <stdexcept>

namespace pavilion::sim {

void OdometryCalibration::Validate() const {
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v))
      throw std::invalid_argument(std::string(name) + " must be > 0");
  };
  auto non_negative = [](double v, const char* name) {
    if (!(v >= 0.0) || !std::isfinite(v)) {
      throw std::invalid_argument(std::string(name) + " must be >= 0");
    }
  };
  positive(left_wheel_radius_m, "left_wheel_radius_m");
  positive(right_wheel_radius_m, "right_wheel_radius_m");
  positive(wheelbase_m, "wheelbase_m");
  non_negative(k_left_m, "k_left_m");
  non_negative(k_right_m, "k_right_m");
  non_negative(k_turn_m, "k_turn_m");
}

}  // namespace pavilion::sim
