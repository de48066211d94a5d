#pragma once

// Wheel travels from encoder counts with the robot's calibrated odometry
// parameters (thesis §2.3): the input u = [s_r, s_l] of eqs. 2.5-2.13.

#include <optional>

#include "core/odometry/diff_drive.h"
#include "core/types/sensor_data.h"

namespace pavilion::core {

// The calibrated odometry of a differential-drive robot: the values the
// robot's `odometry:` block holds (robots/<name>/robot.yaml, read in
// scenarios/). Defaults: Robox's nominal geometry (r = 0.09 m, b = 0.50 m) and
// the thesis' k_L = k_R = 5e-6 m (§2.3).
struct EncoderOdometryOptions {
  double left_wheel_radius_m = 0.09;   // calibrated r_L, m; (0, 10]
  double right_wheel_radius_m = 0.09;  // calibrated r_R, m; (0, 10]
  double wheelbase_m = 0.5;            // calibrated b, m; (0, 10]
  double k_left_m = 5e-6;              // k_L of eq. 2.9, m; [0, 1]
  double k_right_m = 5e-6;             // k_R of eq. 2.9, m; [0, 1]
  double k_turn_m = 0.0;               // turn slip (WheelNoise), m; [0, 1]

  WheelNoise noise() const { return {k_left_m, k_right_m, k_turn_m}; }
  void Validate() const;  // throws std::invalid_argument naming the field
};

// The wheel travels s_l, s_r (eq. 2.5) between two cumulative encoder readings:
// counts times 2 pi r / ticks per revolution. Throws std::invalid_argument when
// a reading's ticks_per_revolution is not positive or the two differ.
WheelTravel WheelTravelFromEncoders(const EncoderReading& previous, const EncoderReading& current,
                                    const EncoderOdometryOptions& options);

// Dead reckoning from cumulative encoder readings with the calibrated odometry
// model (eqs. 2.5-2.8): what a robot believes without any other sensor. The
// first reading only sets the reference counts.
class DeadReckoning {
 public:
  DeadReckoning(const EncoderOdometryOptions& options, const Pose2& start)
      : options_(options), pose_(start) {}
  void Update(const EncoderReading& reading);
  const Pose2& pose() const { return pose_; }

 private:
  EncoderOdometryOptions options_;
  Pose2 pose_;
  std::optional<EncoderReading> last_;
};

}  // namespace pavilion::core
