#pragma once

#include <string>

#include "core/random/random_stream.h"
#include "core/types/pose2.h"
#include "sim/sensors/laser_scanner.h"
#include "sim/sensors/sensor.h"

namespace pavilion::sim {

// A laser scanner on a robot as a Sensor (id "laser/<scanner id>"): sampled
// every tick, it casts the readings due in the tick from poses interpolated
// between the tick's two states, and delivers each finished sweep into
// SensorOutputs::scans. Sweeps start every 1/scan_rate_hz from t = 0. With a
// planar caster in the tick, a sweep's readings of the tick fall back to
// Bullet when the robot's tilt at either end exceeds the caster's
// max_tilt_rad or a body the plane does not cut exactly is within range.
class LaserSensor final : public Sensor {
 public:
  // Throws std::invalid_argument for invalid options.
  LaserSensor(std::string scanner_id, const LaserScannerOptions& options,
              const core::Pose2& robot_from_sensor, double mount_height_m,
              core::RandomStream stream, double physics_rate_hz);

  const std::string& id() const override { return id_; }
  double sample_rate_hz() const override { return physics_rate_hz_; }
  void Sample(const SensorTick& tick, SensorOutputs* out) override;
  // Casts in a tick when a sweep is under way or starts before its end.
  bool Heavy(std::int64_t tick, double end_s) const override {
    (void)tick;
    return sweeping_ || next_sweep_s_ < end_s;
  }

  const LaserScanner& scanner() const { return laser_; }
  LaserScanner& mutable_scanner() { return laser_; }

 private:
  std::string id_;
  LaserScanner laser_;
  double physics_rate_hz_;
  double next_sweep_s_ = 0.0;  // start of the next sweep
  bool sweeping_ = false;
  bool fell_back_ = false;  // this sweep used the Bullet fallback
};

}  // namespace pavilion::sim
