#include "scenarios/output/canvas.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pavilion::scenarios {

using Vec2 = Eigen::Vector2d;

void Canvas::LinePx(const Vec2& a, const Vec2& b, const Rgb& c, double width_px) {
  const double len = (b - a).norm();
  const int steps = std::max(1, static_cast<int>(std::ceil(len * 2.0)));
  const double h = 0.5 * width_px;
  for (int i = 0; i <= steps; ++i) {
    const Vec2 p = a + (b - a) * (static_cast<double>(i) / steps);
    for (int y = static_cast<int>(std::floor(p.y() - h + 0.5));
         y <= static_cast<int>(std::floor(p.y() + h - 0.5)); ++y) {
      for (int x = static_cast<int>(std::floor(p.x() - h + 0.5));
           x <= static_cast<int>(std::floor(p.x() + h - 0.5)); ++x) {
        Put(x, y, c);
      }
    }
  }
}

void Canvas::DiscPx(const Vec2& q, double r, const Rgb& c) {
  for (int y = static_cast<int>(std::floor(q.y() - r)); y <= static_cast<int>(q.y() + r); ++y) {
    for (int x = static_cast<int>(std::floor(q.x() - r)); x <= static_cast<int>(q.x() + r); ++x) {
      const double dx = x + 0.5 - q.x(), dy = y + 0.5 - q.y();
      if (dx * dx + dy * dy <= r * r) Put(x, y, c);
    }
  }
}

void Canvas::RingPx(const Vec2& q, double r, const Rgb& c, double width_px) {
  const int n = std::max(16, static_cast<int>(r * 2.0));
  for (int i = 0; i < n; ++i) {
    const double t0 = 2.0 * std::numbers::pi * i / n, t1 = 2.0 * std::numbers::pi * (i + 1) / n;
    LinePx(q + r * Vec2(std::cos(t0), std::sin(t0)), q + r * Vec2(std::cos(t1), std::sin(t1)), c,
           width_px);
  }
}

void Canvas::SquarePx(const Vec2& q, double half, const Rgb& c) {
  for (int y = static_cast<int>(std::floor(q.y() - half));
       y <= static_cast<int>(std::floor(q.y() + half)); ++y) {
    for (int x = static_cast<int>(std::floor(q.x() - half));
         x <= static_cast<int>(std::floor(q.x() + half)); ++x) {
      Put(x, y, c);
    }
  }
}

void Canvas::DiamondPx(const Vec2& q, double half, const Rgb& fill, const Rgb& outline) {
  for (int y = static_cast<int>(std::floor(q.y() - half));
       y <= static_cast<int>(std::floor(q.y() + half)); ++y) {
    for (int x = static_cast<int>(std::floor(q.x() - half));
         x <= static_cast<int>(std::floor(q.x() + half)); ++x) {
      const double m = std::abs(x + 0.5 - q.x()) + std::abs(y + 0.5 - q.y());
      if (m <= half) Put(x, y, m > half - 1.5 ? outline : fill);
    }
  }
}

}  // namespace pavilion::scenarios
