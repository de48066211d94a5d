#include "sim/robot/robot_description.h"

#include <stdexcept>

namespace pavilion::sim {

const MountSpec& RobotDescription::Mount(const std::string& link) const {
  for (const MountSpec& m : mounts) {
    if (m.link == link) return m;
  }
  throw std::out_of_range("robot '" + model + "': no mount link '" + link + "'");
}

}  // namespace pavilion::sim
