#include "scenarios/events/odometry_bias_event.h"

#include <memory>
#include <stdexcept>
#include <utility>

#include "scenarios/config/options_reader.h"
#include "sim/robot/sim_robot.h"

namespace pavilion::scenarios {
namespace {

constexpr double kMinRadiusScale = 0.8;
constexpr double kMaxRadiusScale = 1.2;
constexpr double kMaxDurationS = 1e7;  // the scenario's own bound on duration_s
// Events end when their time is reached up to this rounding of tick times (s).
constexpr double kDueToleranceS = 1e-9;

}  // namespace

void OdometryBiasOptions::Validate() const {
  if (!(radius_scale >= kMinRadiusScale && radius_scale <= kMaxRadiusScale)) {
    throw std::invalid_argument("radius_scale must be in [0.8, 1.2]");
  }
  if (duration_s && !(*duration_s > 0.0 && *duration_s <= kMaxDurationS)) {
    throw std::invalid_argument("duration_s must be in (0, 1e7] s");
  }
}

const char* WheelName(OdometryBiasOptions::Wheel wheel) {
  switch (wheel) {
    case OdometryBiasOptions::Wheel::kLeft:
      return "left";
    case OdometryBiasOptions::Wheel::kRight:
      return "right";
    case OdometryBiasOptions::Wheel::kBoth:
      break;
  }
  return "both";
}

OdometryBiasEvent::OdometryBiasEvent(std::string robot, const OdometryBiasOptions& options)
    : robot_(std::move(robot)), options_(options) {
  options_.Validate();
}

bool OdometryBiasEvent::SetScale(const EventContext& c, double scale) const {
  const auto it = c.robot_index->find(robot_);
  sim::SimRobot* robot =
      it != c.robot_index->end() && c.sim_robot ? c.sim_robot(it->second) : nullptr;
  if (robot == nullptr) return false;
  if (options_.wheel != OdometryBiasOptions::Wheel::kRight) robot->SetWheelRadiusScale(0, scale);
  if (options_.wheel != OdometryBiasOptions::Wheel::kLeft) robot->SetWheelRadiusScale(1, scale);
  return true;
}

EventFields OdometryBiasEvent::Apply(const EventContext& c) const {
  EventFields fields{{"robot", robot_},
                     {"wheel", WheelName(options_.wheel)},
                     {"radius_scale", options_.radius_scale}};
  if (options_.duration_s) fields["duration_s"] = *options_.duration_s;
  if (!SetScale(c, options_.radius_scale)) {
    fields["error"] = "no such simulated robot";
    return fields;
  }
  if (options_.duration_s) until_s_ = c.world->time_s() + *options_.duration_s;
  return fields;
}

EventFields OdometryBiasEvent::Continue(const EventContext& c) const {
  if (until_s_ < 0.0 || c.world->time_s() < until_s_ - kDueToleranceS) return nullptr;
  until_s_ = -1.0;
  SetScale(c, 1.0);
  return EventFields{{"robot", robot_},
                     {"wheel", WheelName(options_.wheel)},
                     {"radius_scale", 1.0},
                     {"ended", true}};
}

void RegisterOdometryBiasEvent(EventRegistry* registry) {
  registry->Register(
      "odometry_bias",
      [](MapReader& r, const EventTargets& targets) -> std::shared_ptr<const ScenarioEvent> {
        const std::string robot = r.RequiredString("robot").value_or("");
        if (!robot.empty() && !targets.robots.contains(robot)) {
          r.doc()->Error(r.Child("robot"), r.PathOf("robot"), "no robot '" + robot + "'");
        }
        OdometryBiasOptions options;
        const std::string wheel = r.Choice("wheel", {"left", "right", "both"}, "both", true);
        options.wheel = wheel == "left"    ? OdometryBiasOptions::Wheel::kLeft
                        : wheel == "right" ? OdometryBiasOptions::Wheel::kRight
                                           : OdometryBiasOptions::Wheel::kBoth;
        RequireKeys(r, {"radius_scale"});
        const bool valid = ReadOptions(r, &options,
                                       {{"radius_scale", &OdometryBiasOptions::radius_scale},
                                        {"duration_s", &OdometryBiasOptions::duration_s}});
        if (!valid || !targets.robots.contains(robot)) return nullptr;
        return std::make_shared<const OdometryBiasEvent>(robot, options);
      });
}

}  // namespace pavilion::scenarios
