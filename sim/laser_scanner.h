#pragma once

#include <cstdint>
#include <string>

#include "core/random/random_stream.h"
#include "core/types/pose2.h"
#include "core/types/sensor_data.h"
#include "sim/world.h"

namespace pavilion::sim {

// Parameters of a simulated 2D laser scanner. Defaults are the SICK LMS 200 as
// the thesis configured it (§2.2.2: 180°, 0.5°, 8 m, σ_ρ = 1 cm).
struct LaserScannerOptions {
  std::string profile = "sick_lms200";             // sick_lms200 | acuity_accurange | custom
  double fov_rad = 3.14159265358979323846;         // angular range covered, (0, 2π]
  int beams = 361;                                 // readings per scan, >= 2
  double first_bearing_rad = -1.5707963267948966;  // bearing of the first reading
  double max_range_m = 8.0;                        // readings beyond are "no return", > 0
  double scan_rate_hz = 10.0;                      // scans delivered per second, > 0
  double sweep_s =
      0.0267;  // first to last reading (LMS 200: 75 Hz mirror, two interlaced turns), >= 0
  double timestamp_bias_s = 0.0;      // constant error added to the stamp (§2.2.1.5)
  double range_sigma_m = 0.01;        // range noise σ on normal surfaces, >= 0
  double range_resolution_m = 0.001;  // quantization of reported ranges, >= 0 (0: none)

  // Acuity AccuRange amplitude model (§2.2.1.3): amplitude ∝ reflectivity·cos(incidence)/r²,
  // σ = range_sigma_m above min_amplitude, low_amplitude_sigma_m below.
  bool amplitude_model = false;
  double min_amplitude = 0.05;         // relative amplitude threshold s_min, [0, 1]
  double low_amplitude_sigma_m = 0.1;  // σ of readings below s_min, >= 0
  double outlier_probability = 0.0;    // chance of a uniform random range, [0, 1]

  // Surface effects (thesis §2.2.1.6).
  double dark_dropout_probability = 0.3;    // `dark` surfaces: chance of no return, [0, 1]
  double dark_sigma_factor = 5.0;           // ... and range σ multiplied by this, >= 1
  double specular_max_incidence_rad = 1.0;  // `specular`: no return beyond this incidence, [0, π/2]
  double beam_divergence_rad = 0.0087;      // footprint width for mixed pixels, >= 0
  double mixed_pixel_min_gap_m = 0.05;      // depth jump that can produce a mixed pixel, > 0

  bool noise = true;    // range noise, outliers and random dropouts
  bool effects = true;  // dark/specular dropouts and mixed pixels

  // Throws std::invalid_argument naming the field.
  void Validate() const;
  // Named profiles: "sick_lms200", "acuity_accurange". Throws for unknown names.
  static LaserScannerOptions Profile(const std::string& name);
};

// A laser scanner mounted on a robot, casting Bullet rays in its beam plane.
// A sweep spans several physics ticks: the runner calls Cast() every tick
// with the robot pose at the start and end of the tick, and each reading is
// cast in the tick its time falls in, from the pose interpolated to its time
// (so a moving robot gets the distorted scans of §2.2.1.4).
class LaserScanner {
 public:
  // `stream` draws every random number of this sensor.
  LaserScanner(std::string id, LaserScannerOptions options, core::Pose2 robot_from_sensor,
               double mount_height_m, core::RandomStream stream);

  const std::string& id() const { return id_; }
  const LaserScannerOptions& options() const { return options_; }

  // Starts a new sweep whose first reading is taken at `start_s`.
  void BeginSweep(double start_s);
  // Casts the readings whose times lie in [t0_s, t1_s), the robot moving
  // linearly from world_from_robot_t0 to world_from_robot_t1. Rays ignore
  // the elements of `ignore_group` (the robot's own body).
  void Cast(const World& world, double t0_s, const core::Pose2& world_from_robot_t0, double t1_s,
            const core::Pose2& world_from_robot_t1, int ignore_group);
  // True when every reading of the current sweep has been cast.
  bool SweepComplete() const;
  // The finished scan and its ground truth; valid after SweepComplete().
  const core::LaserScan& scan() const { return scan_; }
  const core::LaserScanTruth& truth() const { return truth_; }

  // Casts a whole scan at once from a fixed robot pose (the `pavilion scan` command).
  core::LaserScan ScanFrom(const World& world, const core::Pose2& world_from_robot, double stamp_s,
                           int ignore_group, core::LaserScanTruth* truth);

 private:
  std::string id_;
  LaserScannerOptions options_;
  core::Pose2 robot_from_sensor_;
  double mount_height_m_;
  core::RandomStream stream_;
  double sweep_start_s_ = 0.0;
  int next_reading_ = 0;
  core::LaserScan scan_;
  core::LaserScanTruth truth_;
};

}  // namespace pavilion::sim
