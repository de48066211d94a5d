#pragma once

// odometry_bias (issue 17): a drive wheel's true radius changes from a time on
// (a flat tyre, a carpet's pile), while the robot's calibrated odometry model
// stays as it was: its dead reckoning drifts systematically and its estimator
// must cope. sim::SimRobot::SetWheelRadiusScale says how both wheel models
// make the change real.

#include <optional>
#include <string>

#include "scenarios/events/event.h"
#include "scenarios/events/event_registry.h"

namespace pavilion::scenarios {

struct OdometryBiasOptions {
  enum class Wheel { kLeft, kRight, kBoth };
  Wheel wheel = Wheel::kBoth;
  // The true radius over the one it was built with, [0.8, 1.2] (chosen: a
  // flat tyre or a thick carpet changes it by a few percent).
  double radius_scale = 1.0;
  // After this long the radius returns to the built one, s, (0, 1e7]; none:
  // for the rest of the run.
  std::optional<double> duration_s;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// "left", "right" or "both".
const char* WheelName(OdometryBiasOptions::Wheel wheel);

class OdometryBiasEvent : public ScenarioEvent {
 public:
  // Throws std::invalid_argument for invalid options.
  OdometryBiasEvent(std::string robot, const OdometryBiasOptions& options);
  std::string type() const override { return "odometry_bias"; }
  // Changes the wheels' true radius now; the record holds robot, wheel,
  // radius_scale (and duration_s when given).
  EventFields Apply(const EventContext& context) const override;
  bool ongoing() const override { return options_.duration_s.has_value(); }
  // With a duration: at its end, the radius returns to the built one (a
  // second record with radius_scale 1 and `ended`).
  EventFields Continue(const EventContext& context) const override;

  const std::string& robot() const { return robot_; }
  const OdometryBiasOptions& options() const { return options_; }

 private:
  // Sets the scale of the event's wheels; false when the run has no such robot.
  bool SetScale(const EventContext& context, double scale) const;

  std::string robot_;
  OdometryBiasOptions options_;
  mutable double until_s_ = -1.0;  // when the running bias ends, s; -1: none running
};

// Registers odometry_bias: {robot: id, wheel: left | right | both,
// radius_scale: [0.8, 1.2], duration_s: > 0 (default: the rest of the run)}.
void RegisterOdometryBiasEvent(EventRegistry* registry);

}  // namespace pavilion::scenarios
