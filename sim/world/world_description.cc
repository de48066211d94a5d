#include "sim/world/world_description.h"

#include <cmath>
#include <stdexcept>

namespace pavilion::sim {

Box Door::AsBox() const {
  const double yaw = open ? open_yaw_rad : closed_yaw_rad;
  const Eigen::Vector2d dir(std::cos(yaw), std::sin(yaw));
  const Eigen::Vector2d centre = hinge_m + 0.5 * width_m * dir;
  Box box;
  box.id = id;
  box.pose = {centre.x(), centre.y(), yaw};
  box.size_m = {width_m, thickness_m, height_m};
  box.material = material;
  return box;
}

const Material& WorldDescription::MaterialNamed(const std::string& name) const {
  auto it = materials.find(name);
  if (it == materials.end()) {
    throw std::out_of_range("world '" + this->name + "': unknown material '" + name + "'");
  }
  return it->second;
}

}  // namespace pavilion::sim
