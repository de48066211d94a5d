#include "sim/sensors/bumper_sensor.h"

#include <utility>

namespace pavilion::sim {

BumperSensor::BumperSensor(std::vector<BumperZone> zones, double rate_hz)
    : zones_(std::move(zones)), rate_hz_(rate_hz) {}

void BumperSensor::Sample(const SensorTick& tick, SensorOutputs* out) {
  if (zones_.empty()) return;
  const std::uint32_t pressed =
      PressedBumperZones(zones_, tick.world->RobotContactPoints(tick.robot));
  if (pressed != pressed_) out->bumpers.push_back({tick.end_s, pressed});
  pressed_ = pressed;
}

}  // namespace pavilion::sim
