#include "sim/robot/robot_description.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "core/geometry/polygon.h"

namespace pavilion::sim {
namespace {

// Two outlines' corners closer than this are the same corner (m): the
// footprint and the slabs come from the same hull computation.
constexpr double kSameCornerM = 1e-9;

}  // namespace

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
  for (const WheelSpec* w : {&left_wheel, &right_wheel}) {
    const double hx = w->radius_m, hy = 0.5 * w->width_m;
    for (const auto& [sx, sy] : {std::pair{1, 1}, {-1, 1}, {-1, -1}, {1, -1}}) {
      points.push_back(w->position_m + Eigen::Vector2d(sx * hx, sy * hy));
    }
  }
  for (const CasterSpec& c : casters) add_disc(c.position_m, c.radius_m);
  return core::ConvexHull(std::move(points));
}

std::vector<ChassisPrism> RobotDescription::ChassisPrisms() const {
  const std::vector<ChassisPrism> whole{
      {footprint_m, chassis_base_z_m, chassis_base_z_m + chassis_height_m}};
  if (chassis_prisms.empty()) return whole;
  std::vector<Eigen::Vector2d> corners;
  for (const ChassisPrism& p : chassis_prisms) {
    corners.insert(corners.end(), p.outline_m.begin(), p.outline_m.end());
  }
  const core::Polygon2 hull = core::ConvexHull(std::move(corners));
  if (hull.size() != footprint_m.size()) return whole;
  for (const Eigen::Vector2d& f : footprint_m) {
    bool found = false;
    for (const Eigen::Vector2d& h : hull) found = found || (h - f).norm() <= kSameCornerM;
    if (!found) return whole;
  }
  return chassis_prisms;
}

}  // namespace pavilion::sim
