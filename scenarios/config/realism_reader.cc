#include "scenarios/config/realism_reader.h"

#include <numbers>

#include "scenarios/config/options_reader.h"

namespace pavilion::scenarios {
namespace {
constexpr double kRadPerDeg = std::numbers::pi / 180.0;  // the angles are given in degrees
}  // namespace

void ReadRealism(YamlDocument* doc, MapReader& top, RealismProfile* profile) {
  *profile = RealismProfile{};
  if (!top.Has("realism")) return;
  const YAML::Node node = top.Child("realism");
  if (node.IsScalar()) {
    profile->realistic = top.Choice("realism", {"ideal", "realistic"}, "ideal") == "realistic";
    return;
  }
  MapReader r(doc, node, "realism");
  if (!r.valid()) return;
  profile->realistic = r.Choice("profile", {"ideal", "realistic"}, "ideal", true) == "realistic";
  using P = RealismProfile;
  ReadOptions(r, profile,
              {{"laser_mount_sigma_m", &P::laser_mount_sigma_m},
               {"laser_mount_yaw_sigma_deg", "laser_mount_yaw_sigma_rad",
                &P::laser_mount_yaw_sigma_rad, kRadPerDeg},
               {"laser_angle_offset_sigma_deg", "laser_angle_offset_sigma_rad",
                &P::laser_angle_offset_sigma_rad, kRadPerDeg},
               {"laser_range_sigma_m", &P::laser_range_sigma_m},
               {"laser_surface_bias_sigma_m", &P::laser_surface_bias_sigma_m},
               {"laser_correlated_sigma_m", &P::laser_correlated_sigma_m},
               {"laser_correlation_readings", &P::laser_correlation_readings},
               {"laser_intensity_bias_m", &P::laser_intensity_bias_m},
               {"laser_intensity_sigma_m", &P::laser_intensity_sigma_m},
               {"laser_stamp_jitter_s", &P::laser_stamp_jitter_s},
               {"laser_latency_sigma_s", &P::laser_latency_sigma_s},
               {"wheel_radius_ratio_sigma", &P::wheel_radius_ratio_sigma},
               {"wheelbase_factor_sigma", &P::wheelbase_factor_sigma},
               {"mean_radius_factor_sigma", &P::mean_radius_factor_sigma},
               {"wheel_noise_k_m", &P::wheel_noise_k_m},
               {"turn_slip_k_m", &P::turn_slip_k_m},
               {"accel_slip_k_s2", &P::accel_slip_k_s2},
               {"carpet_fraction", &P::carpet_fraction},
               {"carpet_travel_error", &P::carpet_travel_error},
               {"floor_max_slope_deg", "floor_max_slope_rad", &P::floor_max_slope_rad, kRadPerDeg},
               {"floor_min_wavelength_m", &P::floor_min_wavelength_m},
               {"floor_max_wavelength_m", &P::floor_max_wavelength_m},
               {"wall_offset_sigma_m", &P::wall_offset_sigma_m},
               {"clutter_per_m", &P::clutter_per_m},
               {"door_flip_probability", &P::door_flip_probability}});
  r.Finish();
}

}  // namespace pavilion::scenarios
