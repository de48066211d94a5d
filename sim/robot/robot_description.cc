#include "sim/robot/robot_description.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "core/geometry/polygon.h"

namespace pavilion::sim {

const MountSpec& RobotDescription::Mount(const std::string& link) const {
  for (const MountSpec& m : mounts) {
    if (m.link == link) return m;
  }
  throw std::out_of_range("robot '" + model + "': no mount link '" + link + "'");
}

std::vector<Eigen::Vector2d> RobotDescription::OutlineWithWheels() const {
  constexpr int kDiscVertices = 16;
  std::vector<Eigen::Vector2d> points = footprint_m;
  const auto add_disc = [&](const Eigen::Vector2d& c, double r) {
    // The 16-gon around the disc (its vertices at r / cos(pi / 16)) holds it.
    const double outer = r / std::cos(std::numbers::pi / kDiscVertices);
    for (int k = 0; k < kDiscVertices; ++k) {
      const double a = 2.0 * std::numbers::pi * k / kDiscVertices;
      points.push_back(c + outer * Eigen::Vector2d(std::cos(a), std::sin(a)));
    }
  };
  add_disc(left_wheel.position_m, left_wheel.radius_m);
  add_disc(right_wheel.position_m, right_wheel.radius_m);
  for (const CasterSpec& c : casters) add_disc(c.position_m, c.radius_m);
  return core::ConvexHull(std::move(points));
}

}  // namespace pavilion::sim
