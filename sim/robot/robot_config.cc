#include "sim/robot/robot_config.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace pavilion::sim {

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
