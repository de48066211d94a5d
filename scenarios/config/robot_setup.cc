#include "scenarios/config/robot_setup.h"

namespace pavilion::scenarios {

sim::SimRobotSetup MakeSimRobotSetup(const std::string& id, const sim::RobotConfig& config,
                                     const core::Pose2& pose, sim::WorldDescription* world) {
  const sim::RobotDescription& model = config.description;
  auto material = [&](const std::string& name) {
    if (!model.materials.contains(name)) return name;  // one of the world's
    const std::string scoped = model.model + "/" + name;
    world->materials[scoped] = model.materials.at(name);
    return scoped;
  };
  sim::SimRobotSetup setup;
  setup.spec.id = id;
  setup.spec.model = model;
  setup.spec.model.material = material(model.material);
  setup.spec.systematic = config.systematic;
  setup.spec.pose = pose;
  for (const sim::MarkerSpec& m : model.markers) {
    setup.spec.attachments.push_back(
        {m.id, m.position_m, m.radius_m, m.base_z_m, m.height_m, material(m.material)});
  }
  setup.encoders = config.encoders;
  for (const sim::LaserMount& laser : config.lasers) {
    setup.lasers.push_back({laser.id, laser.options, laser.robot_from_sensor, laser.z_m});
  }
  setup.bumpers = config.bumpers;
  return setup;
}

}  // namespace pavilion::scenarios
