#include "scenarios/events/sensor_fault_event.h"

#include <algorithm>
#include <memory>

namespace pavilion::scenarios {
namespace {

const char* ModeName(sim::LaserFault::Mode mode) {
  switch (mode) {
    case sim::LaserFault::Mode::kBlackout:
      return "blackout";
    case sim::LaserFault::Mode::kNoise:
      return "noise";
    case sim::LaserFault::Mode::kStuck:
      return "stuck";
    case sim::LaserFault::Mode::kNone:
      break;
  }
  return "none";
}

}  // namespace

EventFields SensorFaultEvent::Apply(const EventContext& c) const {
  sim::LaserFault fault;
  fault.mode = mode_;
  // Scans stamped from the event's tick on (times up to a rounding of it).
  fault.from_s = c.world->time_s() - 1e-9;
  fault.until_s = c.world->time_s() + duration_s_;
  fault.extra_sigma_m = sigma_m_;
  fault.seed = c.streams->Get(robot_ + "/sensor_fault").NextU64();
  const bool done = c.set_laser_fault && c.set_laser_fault(robot_, sensor_, fault);
  EventFields fields{{"robot", robot_},
                     {"sensor", sensor_.empty() ? "all" : sensor_},
                     {"mode", ModeName(mode_)},
                     {"duration_s", duration_s_}};
  if (mode_ == sim::LaserFault::Mode::kNoise) fields["sigma_m"] = sigma_m_;
  if (!done) fields["error"] = "no such laser";
  return fields;
}

void RegisterSensorFaultEvent(EventRegistry* registry) {
  registry->Register(
      "sensor_fault",
      [](MapReader& r, const EventTargets& targets) -> std::shared_ptr<const ScenarioEvent> {
        const std::string robot = r.RequiredString("robot").value_or("");
        if (!robot.empty() && !targets.robots.contains(robot)) {
          r.doc()->Error(r.Child("robot"), r.PathOf("robot"), "no robot '" + robot + "'");
        }
        const std::string sensor = r.String("sensor", "");
        if (!sensor.empty() && targets.robots.contains(robot)) {
          const auto it = targets.lasers.find(robot);
          const bool known =
              it != targets.lasers.end() &&
              std::find(it->second.begin(), it->second.end(), sensor) != it->second.end();
          if (!known) {
            r.doc()->Error(r.Child("sensor"), r.PathOf("sensor"),
                           "robot '" + robot + "' has no laser '" + sensor + "'");
          }
        }
        const std::string mode_name =
            r.Choice("mode", {"blackout", "noise", "stuck"}, "blackout", true);
        const sim::LaserFault::Mode mode = mode_name == "noise" ? sim::LaserFault::Mode::kNoise
                                           : mode_name == "stuck"
                                               ? sim::LaserFault::Mode::kStuck
                                               : sim::LaserFault::Mode::kBlackout;
        const double duration_s = r.Number("duration_s", 1.0, 1e-3, 1e6);
        double sigma_m = 0.0;
        if (mode == sim::LaserFault::Mode::kNoise) {
          sigma_m = r.Number("sigma_m", 0.05, 1e-6, 10.0);
        }
        return std::make_shared<const SensorFaultEvent>(robot, sensor, mode, duration_s, sigma_m);
      });
}

}  // namespace pavilion::scenarios
