#include "scenarios/events/free_space.h"

#include <algorithm>
#include <cmath>
#include <deque>
#include <numbers>

#include "core/geometry/segment2.h"

namespace pavilion::scenarios {
namespace {

// Fractions of the chassis' span checked (chosen: its underside, middle and
// top, where low objects, exhibits and table tops meet it).
constexpr double kCheckFractions[] = {0.05, 0.5, 0.95};
// Rays of the enclosure test and how many may see out (chosen: a hall's
// entrance or exit subtends less than two of eight directions from inside).
constexpr int kEnclosedRays = 8;
constexpr int kOpenRaysAllowed = 2;
// The spread either side of a robot's heading over which its straight run on
// its wheels is checked (chosen: the turn of its last command while it is set
// down and has not yet noticed).
constexpr double kWheelRunSpreadRad = 15.0 * std::numbers::pi / 180.0;
// Cells around the start searched for a free one when the start's own is not
// (a robot close to a wall), per side.
constexpr int kStartSearchCells = 3;

// Whether a ray from `p` along +x crosses the segment a-b (half-open in y, so
// a vertex shared by two segments counts once).
bool CrossesRightward(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                      const Eigen::Vector2d& b) {
  if ((a.y() > p.y()) == (b.y() > p.y())) return false;
  const double x = a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
  return x > p.x();
}

DiscObstacle CheckSection(const core::PlanarSection& s, const Eigen::Vector2d& c, double r,
                          int ignore_group) {
  const auto ignored = [&](int element) {
    return element < 0 || element >= static_cast<int>(s.elements.size()) ||
           (ignore_group >= 0 && s.elements[element].group == ignore_group);
  };
  std::vector<int> crossings(s.elements.size(), 0);
  for (const core::SectionSegment& seg : s.segments) {
    if (ignored(seg.element)) continue;
    if (core::PointSegmentDistance(c, seg.a_m, seg.b_m) < r) {
      return {false, s.elements[seg.element].id};
    }
    if (CrossesRightward(c, seg.a_m, seg.b_m)) ++crossings[seg.element];
  }
  for (const core::SectionCircle& circle : s.circles) {
    if (ignored(circle.element)) continue;
    if ((circle.center_m - c).norm() < r + circle.radius_m) {
      return {false, s.elements[circle.element].id};
    }
  }
  for (std::size_t e = 0; e < crossings.size(); ++e) {
    if (crossings[e] % 2 == 1) return {false, s.elements[e].id};
  }
  return {};
}

// Whether the segment `from_m`-`to_m` meets a segment or circle of the section.
bool RayMeets(const core::PlanarSection& section, const Eigen::Vector2d& from_m,
              const Eigen::Vector2d& to_m) {
  for (const core::SectionSegment& s : section.segments) {
    if (std::isfinite(core::RaySegmentHit(from_m, to_m, s.a_m, s.b_m))) return true;
  }
  for (const core::SectionCircle& c : section.circles) {
    for (double t : core::LineCircleHits(from_m, to_m, c.center_m, c.radius_m)) {
      if (t >= 0.0 && t <= 1.0) return true;
    }
  }
  return false;
}

}  // namespace

DiscObstacle CheckDisc(const std::vector<core::PlanarSection>& sections, const sim::Floor& floor,
                       const Eigen::Vector2d& center_m, double radius_m, int ignore_group) {
  const Eigen::Vector2d margin(radius_m, radius_m);
  if ((center_m - margin).cwiseMin(floor.min_m) != floor.min_m ||
      (center_m + margin).cwiseMax(floor.max_m) != floor.max_m) {
    return {false, kFloorEdge};
  }
  for (const core::PlanarSection& s : sections) {
    DiscObstacle hit = CheckSection(s, center_m, radius_m, ignore_group);
    if (!hit.free) return hit;
  }
  return {};
}

bool Enclosed(const core::PlanarSection& section, const sim::Floor& floor,
              const Eigen::Vector2d& p_m) {
  const double reach_m = (floor.max_m - floor.min_m).norm();
  int open = 0;
  for (int k = 0; k < kEnclosedRays; ++k) {
    const double angle = 2.0 * std::numbers::pi * k / kEnclosedRays;
    const Eigen::Vector2d end = p_m + reach_m * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    if (!RayMeets(section, p_m, end) && ++open > kOpenRaysAllowed) return false;
  }
  return true;
}

bool WheelsRunInside(const core::PlanarSection& section, const sim::Floor& floor,
                     const core::Pose2& pose) {
  const double reach_m = (floor.max_m - floor.min_m).norm();
  for (double way : {0.0, std::numbers::pi}) {
    for (double spread : {-kWheelRunSpreadRad, 0.0, kWheelRunSpreadRad}) {
      const double angle = pose.theta_rad + way + spread;
      const Eigen::Vector2d end =
          pose.translation() + reach_m * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      if (!RayMeets(section, pose.translation(), end)) return false;
    }
  }
  return true;
}

std::vector<double> ChassisCheckHeights(double bottom_m, double top_m) {
  std::vector<double> heights;
  for (double f : kCheckFractions) heights.push_back(bottom_m + f * (top_m - bottom_m));
  return heights;
}

}  // namespace pavilion::scenarios

namespace pavilion::scenarios {

ReachableCells::ReachableCells(const std::vector<core::PlanarSection>& sections,
                               const sim::Floor& floor, double radius_m, double cell_m,
                               const Eigen::Vector2d& from_m, int ignore_group)
    : origin_m_(floor.min_m), cell_m_(cell_m) {
  const Eigen::Vector2d size = floor.max_m - floor.min_m;
  columns_ = std::max(1, static_cast<int>(std::ceil(size.x() / cell_m)));
  rows_ = std::max(1, static_cast<int>(std::ceil(size.y() / cell_m)));
  reached_cells_.assign(static_cast<std::size_t>(columns_) * rows_, 0);
  // 0 unknown, 1 reached, 2 blocked.
  const auto free = [&](int cx, int cy) {
    const Eigen::Vector2d c = origin_m_ + cell_m_ * Eigen::Vector2d(cx + 0.5, cy + 0.5);
    return CheckDisc(sections, floor, c, radius_m, ignore_group).free;
  };
  const int start = CellOf(from_m);
  if (start < 0) return;
  std::deque<int> open;
  const int sx = start % columns_, sy = start / columns_;
  for (int d = 0; d <= kStartSearchCells && open.empty(); ++d) {
    for (int cy = sy - d; cy <= sy + d && open.empty(); ++cy) {
      for (int cx = sx - d; cx <= sx + d && open.empty(); ++cx) {
        if (cx < 0 || cy < 0 || cx >= columns_ || cy >= rows_) continue;
        if (free(cx, cy)) open.push_back(cy * columns_ + cx);
      }
    }
  }
  if (open.empty()) return;
  reached_cells_[open.front()] = 1;
  while (!open.empty()) {
    const int cell = open.front();
    open.pop_front();
    ++reached_;
    const int cx = cell % columns_, cy = cell / columns_;
    const int next[4][2] = {{cx + 1, cy}, {cx - 1, cy}, {cx, cy + 1}, {cx, cy - 1}};
    for (const auto& n : next) {
      if (n[0] < 0 || n[1] < 0 || n[0] >= columns_ || n[1] >= rows_) continue;
      char& mark = reached_cells_[n[1] * columns_ + n[0]];
      if (mark != 0) continue;
      mark = free(n[0], n[1]) ? 1 : 2;
      if (mark == 1) open.push_back(n[1] * columns_ + n[0]);
    }
  }
}

int ReachableCells::CellOf(const Eigen::Vector2d& p_m) const {
  const Eigen::Vector2d q = (p_m - origin_m_) / cell_m_;
  const int cx = static_cast<int>(std::floor(q.x())), cy = static_cast<int>(std::floor(q.y()));
  if (cx < 0 || cy < 0 || cx >= columns_ || cy >= rows_) return -1;
  return cy * columns_ + cx;
}

bool ReachableCells::Contains(const Eigen::Vector2d& p_m) const {
  const int cell = CellOf(p_m);
  return cell >= 0 && reached_cells_[cell] == 1;
}

}  // namespace pavilion::scenarios
