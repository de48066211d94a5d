#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/geometry/polygon.h"
#include "core/random/random_stream.h"
#include "core/types/sensor_data.h"

namespace pavilion::sim {

// Wheel encoders: quantized cumulative ticks of each wheel, read at a fixed rate.
// A floor region whose surface changes how far the wheels turn per metre.
struct FloorPatch {
  std::string id;
  core::Polygon2 area_m;            // world frame
  double travel_scale_error = 0.0;  // extra wheel turn per metre, (-0.1, 0.1)
};

struct EncoderOptions {
  int ticks_per_revolution = 50000;  // pulses per wheel revolution (Pygmalion: 50,000), >= 1
  double rate_hz = 200.0;  // the thesis' odometry task ran every 5 ms (§4.4.3), Hz, (0, 1e5]
  // Random wheel-space noise of the §2.3 model: the variance of a wheel's
  // travel error grows by k·|Δs| (Chong & Kleeman), k in metres, [0, 1].
  double k_left_m = 0.0;
  double k_right_m = 0.0;
  bool noise = false;  // apply the k_L, k_R noise (and the slip below)

  // Slip the encoders do not see (issue 20, `realism: realistic`), with `noise`:
  // - turn slip: a travel difference d with Var(d) = k_turn·|Δs_r − Δs_l|
  //   moves the wheels by −d/2 and +d/2 (core::WheelNoise's k_turn), m, [0, 1];
  // - acceleration slip: a wheel's travel error variance grows by
  //   k_accel·|a|·|Δs| with a its acceleration (traction needs slip), s², [0, 1].
  double k_turn_m = 0.0;
  double k_accel_s2 = 0.0;
  // Floor patches with other rolling behaviour (carpet): while a wheel's
  // contact lies in one, the wheel turns (1 + travel_scale_error) times as
  // far per metre (its pile compresses under the tyre), which the encoders
  // count and the odometry takes for distance.
  std::vector<FloorPatch> patches;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// Systematic differences between the physical robot and the nominal model its
// odometry uses (the robot's true wheels are built with these applied).
struct SystematicErrors {
  double wheel_radius_ratio = 1.0;  // true right radius / true left radius, [0.9, 1.1]
  double wheelbase_factor = 1.0;    // true wheelbase / nominal wheelbase, [0.9, 1.1]
  double mean_radius_factor = 1.0;  // true mean wheel radius / nominal, [0.9, 1.1]

  void Validate() const;  // throws std::invalid_argument naming the field
};

// A tactile bumper zone: contacts whose bearing from the robot's centre lies
// in [from_rad, to_rad] (counter-clockwise, robot frame) press it.
struct BumperZone {
  std::string name;
  double from_rad = 0.0;
  double to_rad = 0.0;
};

// Wheel encoders of one robot. Each reading adds the wheel-space noise of the
// §2.3 model to the travel since the previous reading (variance k·|Δs|, eq.
// 2.9, drawn from the encoders' own stream) and reports the cumulative counts
// a quadrature counter would hold: floor(angle / 2π · ticks per revolution).
class WheelEncoders {
 public:
  // `left_radius_m`/`right_radius_m` convert angles to travel for the noise model
  // (nominal radii: the noise is specified per metre of wheel travel).
  WheelEncoders(EncoderOptions options, double left_radius_m, double right_radius_m,
                core::RandomStream stream);

  const EncoderOptions& options() const { return options_; }
  // Reads the encoders at `stamp_s` given the true wheel angles (rad, unwrapped).
  // `left_scale`, `right_scale`: how many times as far each wheel turned as
  // its travel asks since the last reading (1 but on a floor patch).
  core::EncoderReading Read(double stamp_s, double left_wheel_rad, double right_wheel_rad,
                            double left_scale = 1.0, double right_scale = 1.0);

 private:
  // Turn and acceleration slip (EncoderOptions) added to the wheels' deltas.
  void AddSlip(double stamp_s, const double travel_m[2], double delta[2]);

  EncoderOptions options_;
  double radius_m_[2];
  core::RandomStream stream_;
  double last_true_rad_[2] = {0, 0};
  double measured_rad_[2] = {0, 0};
  double last_speed_mps_[2] = {0, 0};  // each wheel's speed over the previous reading
  double last_stamp_s_ = 0.0;
  bool started_ = false;
};

// The bumper zones pressed by contact points (base frame): bit i for zone i.
std::uint32_t PressedBumperZones(const std::vector<BumperZone>& zones,
                                 const std::vector<Eigen::Vector2d>& contact_points_m);

}  // namespace pavilion::sim
