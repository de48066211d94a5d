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
  for (const double k : {radial_k1, radial_k2, radial_k3, radial_k4}) {
    if (!(std::abs(k) <= 10.0)) {
      throw std::invalid_argument("CameraMount.radial_k1..radial_k4 must be finite, |k| <= 10");
    }
  }
  if (!(calibration_sigma_px >= 0.0 && calibration_sigma_px <= 100.0)) {
    throw std::invalid_argument("CameraMount.calibration_sigma_px must be in [0, 100] px");
  }
  if (!(noise_grey >= 0.0 && noise_grey <= 100.0)) {
    throw std::invalid_argument("CameraMount.noise_grey must be in [0, 100]");
  }
  if (!(grabber_delay_s >= 0.0 && grabber_delay_s <= 1.0)) {
    throw std::invalid_argument("CameraMount.grabber_delay_s must be in [0, 1] s");
  }
  if (!(grabber_delay_sigma_s >= 0.0 && grabber_delay_sigma_s <= 0.1)) {
    throw std::invalid_argument("CameraMount.grabber_delay_sigma_s must be in [0, 0.1] s");
  }
  // The lens must be invertible over the image (DistortPoint throws otherwise).
  const core::CameraIntrinsics camera = Intrinsics();
  camera.Validate();
  try {
    core::DistortPoint(camera, Eigen::Vector2d(0.0, 0.0));
  } catch (const std::invalid_argument&) {
    throw std::invalid_argument(
        "CameraMount.radial_k1..radial_k4 fold the image: the lens model is not invertible at "
        "its corners");
  }
}

core::CameraIntrinsics CameraMount::Intrinsics() const {
  core::CameraIntrinsics c =
      core::CameraIntrinsics::FromHorizontalFov(width_px, height_px, hfov_rad);
  c.radial = {radial_k1, radial_k2, radial_k3, radial_k4};
  return c;
}

}  // namespace pavilion::sim
