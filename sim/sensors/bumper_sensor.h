#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim/sensors/robot_sensors.h"
#include "sim/sensors/sensor.h"

namespace pavilion::sim {

// A robot's tactile bumper zones as a Sensor (id "bumpers"): polled at its
// rate, it reports into SensorOutputs::bumpers only when the set of pressed
// zones changed (World::RobotContactPoints). Without zones it reports nothing.
class BumperSensor final : public Sensor {
 public:
  BumperSensor(std::vector<BumperZone> zones, double rate_hz);

  const std::string& id() const override { return id_; }
  double sample_rate_hz() const override { return rate_hz_; }
  void Sample(const SensorTick& tick, SensorOutputs* out) override;

 private:
  std::string id_ = "bumpers";
  std::vector<BumperZone> zones_;
  double rate_hz_;
  std::uint32_t pressed_ = 0;
};

}  // namespace pavilion::sim
