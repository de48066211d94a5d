#include "scenarios/realism/robot_realism.h"

#include <string>

#include "core/random/random_stream.h"

namespace pavilion::scenarios {
namespace {

core::RandomStream StreamNamed(std::uint64_t seed, const std::string& name) {
  return core::RandomStream(seed, core::RandomStream::StreamId(name.c_str()));
}

}  // namespace

std::uint64_t SurfaceBiasSeed(std::uint64_t seed) {
  return StreamNamed(seed, "realism/surfaces").NextU64();
}

void DrawRealisticRobot(const RealismProfile& profile, std::uint64_t seed, RobotEntry* robot) {
  if (!profile.realistic) return;
  const RealismProfile& p = profile;
  const std::string prefix = "realism/" + robot->id;
  // The wheels: the file's systematic errors (the build) times the residual
  // the calibration left.
  core::RandomStream wheels = StreamNamed(seed, prefix + "/wheels");
  sim::SystematicErrors& sys = robot->config.systematic;
  sys.wheel_radius_ratio *= 1.0 + wheels.Normal(0.0, p.wheel_radius_ratio_sigma);
  sys.wheelbase_factor *= 1.0 + wheels.Normal(0.0, p.wheelbase_factor_sigma);
  sys.mean_radius_factor *= 1.0 + wheels.Normal(0.0, p.mean_radius_factor_sigma);
  // The wheel-space noise and slip, injected into the encoders.
  sim::EncoderOptions& encoders = robot->config.encoders;
  if (p.wheel_noise_k_m > 0.0) encoders.k_left_m = encoders.k_right_m = p.wheel_noise_k_m;
  encoders.k_turn_m = p.turn_slip_k_m;
  encoders.k_accel_s2 = p.accel_slip_k_s2;
  encoders.noise =
      encoders.noise || p.wheel_noise_k_m > 0.0 || p.turn_slip_k_m > 0.0 || p.accel_slip_k_s2 > 0.0;

  const std::uint64_t surfaces = SurfaceBiasSeed(seed);
  for (sim::LaserMount& mount : robot->config.lasers) {
    core::RandomStream draw = StreamNamed(seed, prefix + "/laser/" + mount.id);
    sim::LaserSystematicErrors& e = mount.options.systematic;
    e.mount_error.x_m = draw.Normal(0.0, p.laser_mount_sigma_m);
    e.mount_error.y_m = draw.Normal(0.0, p.laser_mount_sigma_m);
    e.mount_error.theta_rad = draw.Normal(0.0, p.laser_mount_yaw_sigma_rad) +
                              draw.Normal(0.0, p.laser_angle_offset_sigma_rad);
    mount.options.range_sigma_m = p.laser_range_sigma_m;
    e.surface_bias_sigma_m = p.laser_surface_bias_sigma_m;
    e.surface_seed = surfaces;
    e.correlated_sigma_m = p.laser_correlated_sigma_m;
    e.correlation_readings = p.laser_correlation_readings;
    e.intensity_bias_m = p.laser_intensity_bias_m;
    e.intensity_sigma_m = p.laser_intensity_sigma_m;
    e.stamp_jitter_s = p.laser_stamp_jitter_s;
    e.seed = draw.NextU64();
    // A latency is a stamp later than the readings: a positive bias.
    mount.options.timestamp_bias_s += draw.Normal(0.0, p.laser_latency_sigma_s);
  }
}

}  // namespace pavilion::scenarios
