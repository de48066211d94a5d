#pragma once

// sensor_fault: a robot's laser blacks out, grows noisy, or sticks, for a while.

#include <string>

#include "scenarios/events/event.h"
#include "scenarios/events/event_registry.h"

namespace pavilion::scenarios {

class SensorFaultEvent : public ScenarioEvent {
 public:
  SensorFaultEvent(std::string robot, std::string sensor, sim::LaserFault::Mode mode,
                   double duration_s, double sigma_m)
      : robot_(std::move(robot)),
        sensor_(std::move(sensor)),
        mode_(mode),
        duration_s_(duration_s),
        sigma_m_(sigma_m) {}
  std::string type() const override { return "sensor_fault"; }
  EventFields Apply(const EventContext& context) const override;

 private:
  std::string robot_;
  std::string sensor_;  // empty: every laser of the robot
  sim::LaserFault::Mode mode_;
  double duration_s_;
  double sigma_m_;
};

// Registers sensor_fault: {robot: id, sensor: laser id (default: every laser),
// mode: blackout | noise | stuck, duration_s: > 0, sigma_m: > 0 (noise)}.
// The noise draws from the stream "<robot>/sensor_fault" of the scenario seed.
void RegisterSensorFaultEvent(EventRegistry* registry);

}  // namespace pavilion::scenarios
