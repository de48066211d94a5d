#include "scenarios/maps/closed_doors.h"

#include <algorithm>
#include <cmath>

#include "core/geometry/segment2.h"

namespace pavilion::scenarios {

std::vector<std::string> RemoveEdgesThroughClosedDoors(const std::vector<sim::Door>& doors,
                                                       core::RobotMap* map) {
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> panels;
  for (const sim::Door& d : doors) {
    if (d.open) continue;
    const Eigen::Vector2d along(std::cos(d.closed_yaw_rad), std::sin(d.closed_yaw_rad));
    panels.emplace_back(d.hinge_m, d.hinge_m + d.width_m * along);
  }
  const auto position = [&](const std::string& id) {
    for (const core::MapNode& n : map->nodes) {
      if (n.id == id) return n.pose.translation();
    }
    return Eigen::Vector2d(Eigen::Vector2d::Zero());
  };
  std::vector<std::string> removed;
  std::erase_if(map->edges, [&](const core::MapEdge& e) {
    const Eigen::Vector2d a = position(e.from);
    const Eigen::Vector2d b = position(e.to);
    for (const auto& [p, q] : panels) {
      if (core::SegmentsCross(a, b, p, q)) {
        removed.push_back(e.from + "-" + e.to);
        return true;
      }
    }
    return false;
  });
  return removed;
}

}  // namespace pavilion::scenarios
