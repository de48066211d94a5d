#pragma once

// A robot as the world-level tests build one: the model, the physical
// robot's systematic errors and where it goes (World::AddRobot's arguments in
// one aggregate, so tests can vary one field at a time).
#include <string>

#include "sim/world/world.h"

namespace pavilion::testing {

struct WorldRobot {
  std::string id;
  sim::RobotDescription model;
  sim::SystematicErrors systematic;
  core::Pose2 pose;
  sim::WheelModel wheel_model = sim::WheelModel::kArticulated;
};

inline int AddRobot(sim::World& world, const WorldRobot& r) {
  return world.AddRobot(r.model, r.systematic, sim::RobotPlacement{r.id, r.pose, r.wheel_model});
}

}  // namespace pavilion::testing
