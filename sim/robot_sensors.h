#pragma once

#include <string>
#include <vector>

namespace pavilion::sim {

// Wheel encoders: quantized cumulative ticks of each wheel, read at a fixed rate.
struct EncoderOptions {
  int ticks_per_revolution = 50000;  // pulses per wheel revolution (Pygmalion: 50,000), >= 1
  double rate_hz = 200.0;            // the thesis' odometry task ran every 5 ms (§4.4.3), > 0
  // Random wheel-space noise of the §2.3 model: the variance of a wheel's
  // travel error grows by k·|Δs| (Chong & Kleeman), k in metres, >= 0.
  double k_left_m = 0.0;
  double k_right_m = 0.0;
  bool noise = false;  // apply the k_L, k_R noise

  void Validate() const;  // throws std::invalid_argument naming the field
};

// Systematic differences between the physical robot and the nominal model its
// odometry uses (the robot's true wheels are built with these applied).
struct SystematicErrors {
  double wheel_radius_ratio = 1.0;  // true right radius / true left radius, around 1
  double wheelbase_factor = 1.0;    // true wheelbase / nominal wheelbase, around 1

  void Validate() const;
};

// A tactile bumper zone: contacts whose bearing from the robot's centre lies
// in [from_rad, to_rad] (counter-clockwise, robot frame) press it.
struct BumperZone {
  std::string name;
  double from_rad = 0.0;
  double to_rad = 0.0;
};

}  // namespace pavilion::sim
