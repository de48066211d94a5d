#include "sim/robot_sensors.h"

#include <cmath>
#include <stdexcept>

namespace pavilion::sim {

void EncoderOptions::Validate() const {
  if (ticks_per_revolution < 1) throw std::invalid_argument("ticks_per_revolution must be >= 1");
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz))
    throw std::invalid_argument("rate_hz must be > 0");
  if (!(k_left_m >= 0.0) || !std::isfinite(k_left_m))
    throw std::invalid_argument("k_left_m must be >= 0");
  if (!(k_right_m >= 0.0) || !std::isfinite(k_right_m))
    throw std::invalid_argument("k_right_m must be >= 0");
}

void SystematicErrors::Validate() const {
  if (!(wheel_radius_ratio > 0.5 && wheel_radius_ratio < 2.0)) {
    throw std::invalid_argument("wheel_radius_ratio must be in (0.5, 2)");
  }
  if (!(wheelbase_factor > 0.5 && wheelbase_factor < 2.0)) {
    throw std::invalid_argument("wheelbase_factor must be in (0.5, 2)");
  }
}

}  // namespace pavilion::sim
