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

// A Pygmalion-like model: 45 cm square, 70 cm tall, wheels r = 9 cm, b = 0.4 m.
inline sim::RobotDescription PygmalionLikeModel(const std::string& material) {
  sim::RobotDescription m;
  m.model = "test";
  m.footprint_m = {{-0.225, -0.225}, {0.225, -0.225}, {0.225, 0.225}, {-0.225, 0.225}};
  m.chassis_base_z_m = 0.04;
  m.chassis_height_m = 0.66;
  m.chassis_mass_kg = 50.0;
  m.left_wheel = {"left", 0.09, 0.03, 1.5, {0.0, 0.2}};
  m.right_wheel = {"right", 0.09, 0.03, 1.5, {0.0, -0.2}};
  m.casters = {{"caster_front", {0.17, 0.0}, 0.03}, {"caster_rear", {-0.17, 0.0}, 0.03}};
  m.max_wheel_torque_nm = 15.0;
  m.max_wheel_speed_radps = 15.0;
  m.max_wheel_accel_radps2 = 10.0;
  m.material = material;
  return m;
}

inline int AddRobot(sim::World& world, const WorldRobot& r) {
  return world.AddRobot(r.model, r.systematic, sim::RobotPlacement{r.id, r.pose, r.wheel_model});
}

}  // namespace pavilion::testing
