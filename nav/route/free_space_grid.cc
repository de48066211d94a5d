#include "nav/route/free_space_grid.h"

#include <algorithm>
#include <cmath>
#include <deque>

#include "core/geometry/segment2.h"

namespace pavilion::nav {

using Vec2 = Eigen::Vector2d;

FreeSpaceGrid::FreeSpaceGrid(const Vec2& lo, const Vec2& hi, const core::ObstacleSet& obstacles,
                             double cap_m, double cell_m)
    : lo_(lo), cell_m_(cell_m) {
  nx_ = std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x()) / cell_m_)));
  ny_ = std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y()) / cell_m_)));
  clearance_.assign(static_cast<std::size_t>(nx_) * ny_, static_cast<float>(cap_m));
  reachable_.assign(clearance_.size(), 0);
  for (const auto& s : obstacles.segments) {
    const core::Box2 box = core::SegmentBox(s.a_m, s.b_m);
    Lower(box.lo, box.hi, cap_m,
          [&](const Vec2& p) { return core::PointSegmentDistance(p, s.a_m, s.b_m); });
  }
  for (const auto& c : obstacles.circles) {
    core::Box2 box;
    box.Add(c.center_m.array() - c.radius_m);
    box.Add(c.center_m.array() + c.radius_m);
    Lower(box.lo, box.hi, cap_m,
          [&](const Vec2& p) { return std::max(0.0, (p - c.center_m).norm() - c.radius_m); });
  }
}

template <typename Distance>
void FreeSpaceGrid::Lower(const Vec2& box_lo, const Vec2& box_hi, double cap_m, Distance distance) {
  const CellBox r = CellRange(box_lo, box_hi, cap_m);
  for (int y = r.y0; y <= r.y1; ++y) {
    for (int x = r.x0; x <= r.x1; ++x) {
      float& c = clearance_[Index(x, y)];
      c = std::min(c, static_cast<float>(distance(Center(x, y))));
    }
  }
}

bool FreeSpaceGrid::CellOf(const Vec2& p, std::size_t* index) const {
  const int x = static_cast<int>(std::floor((p.x() - lo_.x()) / cell_m_));
  const int y = static_cast<int>(std::floor((p.y() - lo_.y()) / cell_m_));
  if (x < 0 || y < 0 || x >= nx_ || y >= ny_) return false;
  *index = Index(x, y);
  return true;
}

void FreeSpaceGrid::Flood(const std::vector<std::size_t>& seeds, double radius_m) {
  std::deque<std::size_t> queue;
  for (std::size_t s : seeds) {
    if (clearance_[s] >= radius_m && !reachable_[s]) {
      reachable_[s] = 1;
      queue.push_back(s);
    }
  }
  while (!queue.empty()) {
    const std::size_t i = queue.front();
    queue.pop_front();
    const int x = static_cast<int>(i % nx_), y = static_cast<int>(i / nx_);
    const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
    for (int k = 0; k < 4; ++k) {
      const int u = x + dx[k], v = y + dy[k];
      if (u < 0 || v < 0 || u >= nx_ || v >= ny_) continue;
      const std::size_t j = Index(u, v);
      if (reachable_[j] || clearance_[j] < radius_m) continue;
      reachable_[j] = 1;
      queue.push_back(j);
    }
  }
}

FreeSpaceGrid::CellBox FreeSpaceGrid::CellRange(const Vec2& box_lo, const Vec2& box_hi,
                                                double margin) const {
  CellBox r;
  r.x0 = std::max(0, static_cast<int>(std::floor((box_lo.x() - margin - lo_.x()) / cell_m_)));
  r.y0 = std::max(0, static_cast<int>(std::floor((box_lo.y() - margin - lo_.y()) / cell_m_)));
  r.x1 = std::min(nx_ - 1, static_cast<int>(std::floor((box_hi.x() + margin - lo_.x()) / cell_m_)));
  r.y1 = std::min(ny_ - 1, static_cast<int>(std::floor((box_hi.y() + margin - lo_.y()) / cell_m_)));
  return r;
}

}  // namespace pavilion::nav
