#include "scenarios/config/robot_setup.h"

namespace pavilion::scenarios {

sim::RobotConfig WithWorldMaterials(sim::RobotConfig config, sim::WorldDescription* world) {
  sim::RobotDescription& model = config.description;
  const auto scoped = [&](const std::string& name) {
    if (!model.materials.contains(name)) return name;  // one of the world's
    const std::string world_name = model.model + "/" + name;
    world->materials[world_name] = model.materials.at(name);
    return world_name;
  };
  model.material = scoped(model.material);
  for (sim::MarkerSpec& m : model.markers) m.material = scoped(m.material);
  return config;
}

}  // namespace pavilion::scenarios
