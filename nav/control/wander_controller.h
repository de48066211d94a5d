#pragma once

// The "wander" controller of the hall benchmark (docs/benchmarks.md): the
// obstacle-avoiding random walk that Stage and mvsim run in their own
// benchmarks (Stage's examples/ctrl/wander.cc), reproduced rule for rule so
// that the three simulators run the same workload. It reacts to each new scan
// of one laser and holds its command until the next.
//
// On each scan (readings i = 0..n-1, right to left):
// - obstruction: a reading with n/3 < i < n - n/3 (integer division) below
//   obstruction_distance_m; stop: any reading below stop_distance_m;
//   min_left / min_right: the smallest reading with i > n/2 / the others;
// - on obstruction, stop or a running avoid manoeuvre: forward speed
//   avoid_speed_mps (0 on stop). A manoeuvre starts when none is running: its
//   length is drawn uniformly from [min_avoid_scans, max_avoid_scans] scans
//   and it turns at avoid_turn_rate_radps away from the nearer side (right,
//   negative, if min_left < min_right, else left); the turn is kept until the
//   manoeuvre has lasted its length, counting this scan;
// - otherwise: cruise_speed_mps straight ahead, and no manoeuvre is running.
//
// Pure: no simulator types; the readings and the random stream are the only
// inputs, so the controller runs the same on recorded scans.

#include <span>

#include "core/random/random_stream.h"
#include "core/types/sensor_data.h"
#include "nav/control/path_follower.h"

namespace pavilion::nav {

// Defaults: the peers' wander (Stage's wander.cc: cruisespeed, avoidspeed,
// avoidturn, minfrontdistance, stopdist, avoidduration 10 -> 10..19 scans).
struct WanderOptions {
  double cruise_speed_mps = 0.4;       // speed with nothing ahead, m/s, [0, 10]
  double avoid_speed_mps = 0.05;       // speed while avoiding, m/s, [0, 10]
  double avoid_turn_rate_radps = 0.5;  // turn rate while avoiding, rad/s, (0, 10]
  double obstruction_distance_m =
      1.0;                       // a closer reading in the front third obstructs, m, (0, 1000]
  double stop_distance_m = 0.3;  // a closer reading anywhere stops, m, [0, obstruction_distance_m]
  int min_avoid_scans = 10;      // shortest manoeuvre, scans, [1, 1000000]
  int max_avoid_scans = 19;      // longest manoeuvre, scans, [min_avoid_scans, 1000000]

  void Validate() const;  // throws std::invalid_argument naming the field
};

class WanderController {
 public:
  // `stream` draws the manoeuvre lengths (one draw per manoeuvre). Throws
  // std::invalid_argument for invalid options.
  WanderController(const WanderOptions& options, core::RandomStream stream);

  // The command until the next scan. `readings` in bearing order, right to left
  // (core::LaserScan::readings); a reading without a return (!valid) counts as
  // free space. An empty scan keeps the previous command.
  VelocityCommand Update(std::span<const core::LaserReading> readings);

  const WanderOptions& options() const { return options_; }
  // Scans left in the running avoid manoeuvre (0: cruising).
  int avoid_scans_left() const { return avoid_scans_left_; }
  const VelocityCommand& command() const { return command_; }

 private:
  WanderOptions options_;
  core::RandomStream stream_;
  int avoid_scans_left_ = 0;
  double avoid_turn_radps_ = 0.0;
  VelocityCommand command_;
};

}  // namespace pavilion::nav
