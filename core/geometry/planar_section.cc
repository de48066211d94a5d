#include "core/geometry/planar_section.h"

#include <algorithm>
#include <utility>

namespace pavilion::core {

const char* ToString(LaserResponse response) {
  switch (response) {
    case LaserResponse::kNormal:
      return "normal";
    case LaserResponse::kRetroReflective:
      return "retro_reflective";
    case LaserResponse::kDark:
      return "dark";
    case LaserResponse::kSpecular:
      return "specular";
    case LaserResponse::kTransparent:
      return "transparent";
  }
  return "unknown";
}

int PlanarSection::AddElement(SectionElement element) {
  elements.push_back(std::move(element));
  return static_cast<int>(elements.size()) - 1;
}

double PlanarSection::TotalSegmentLength() const {
  double total = 0.0;
  for (const auto& s : segments) total += (s.b_m - s.a_m).norm();
  return total;
}

bool PlanarSection::Bounds(Eigen::Vector2d* min_m, Eigen::Vector2d* max_m) const {
  if (segments.empty() && circles.empty()) return false;
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e300);
  Eigen::Vector2d hi = -lo;
  for (const auto& s : segments) {
    lo = lo.cwiseMin(s.a_m).cwiseMin(s.b_m);
    hi = hi.cwiseMax(s.a_m).cwiseMax(s.b_m);
  }
  for (const auto& c : circles) {
    lo = lo.cwiseMin((c.center_m.array() - c.radius_m).matrix());
    hi = hi.cwiseMax((c.center_m.array() + c.radius_m).matrix());
  }
  *min_m = lo;
  *max_m = hi;
  return true;
}

}  // namespace pavilion::core
