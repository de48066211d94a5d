#pragma once

// A seam for code outside the runner (tests, tools, future recorders) that
// wants to see a run as it goes without changing the runner: the sensor
// outputs of every robot after each tick, in robot order.

#include "scenarios/config/scenario.h"
#include "sim/robot/sim_robot.h"

namespace pavilion::scenarios {

class RunObserver {
 public:
  virtual ~RunObserver() = default;
  // Called once per robot and tick, after the robot stacks ran, in robot order.
  virtual void OnRobotOutputs(const RobotEntry& robot, const sim::SensorOutputs& outputs,
                              double now_s) = 0;
};

}  // namespace pavilion::scenarios
