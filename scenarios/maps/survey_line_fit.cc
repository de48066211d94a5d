#include "scenarios/maps/survey_line_fit.h"

#include <algorithm>
#include <cmath>

#include "core/types/pose2.h"

namespace pavilion::scenarios {

using Vec2 = Eigen::Vector2d;

std::pair<double, double> FitLine(const std::vector<Vec2>& pts, const Vec2& hint) {
  Vec2 c = Vec2::Zero();
  for (const Vec2& p : pts) c += p;
  c /= static_cast<double>(pts.size());
  double sxx = 0, syy = 0, sxy = 0;
  for (const Vec2& p : pts) {
    const Vec2 d = p - c;
    sxx += d.x() * d.x();
    syy += d.y() * d.y();
    sxy += d.x() * d.y();
  }
  const double dir = 0.5 * std::atan2(2.0 * sxy, sxx - syy);  // of largest spread
  Vec2 n(-std::sin(dir), std::cos(dir));
  if (n.dot(hint) < 0.0) n = -n;
  return {std::atan2(n.y(), n.x()), n.dot(c)};
}

Eigen::Matrix2d FitCovariance(const std::vector<Vec2>& pts, const Vec2& hint, double sigma) {
  const std::size_t n = pts.size();
  Eigen::MatrixXd J(2, 2 * n);
  constexpr double kStep = 1e-6;
  std::vector<Vec2> q = pts;
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < 2; ++k) {
      q[i](k) = pts[i](k) + kStep;
      const auto plus = FitLine(q, hint);
      q[i](k) = pts[i](k) - kStep;
      const auto minus = FitLine(q, hint);
      q[i](k) = pts[i](k);
      J(0, 2 * i + k) = core::NormalizeAngle(plus.first - minus.first) / (2.0 * kStep);
      J(1, 2 * i + k) = (plus.second - minus.second) / (2.0 * kStep);
    }
  }
  return sigma * sigma * (J * J.transpose());
}

void ShiftWall(const Vec2& normal, const Vec2& along, double e_first, double e_last,
               std::vector<Vec2>* corners) {
  if (corners->empty()) return;
  double lo = along.dot(corners->front()), hi = lo;
  for (const Vec2& c : *corners) {
    lo = std::min(lo, along.dot(c));
    hi = std::max(hi, along.dot(c));
  }
  const double span = hi - lo;
  for (Vec2& c : *corners) {
    const double t = span > 0.0 ? (along.dot(c) - lo) / span : 0.5;
    c += (e_first + t * (e_last - e_first)) * normal;
  }
}

Eigen::Matrix2d WallEndCovariance(const std::vector<Vec2>& corners, const Vec2& normal,
                                  const Vec2& along, double sigma) {
  constexpr double kStep = 1e-6;
  Eigen::Matrix2d J;
  for (int end = 0; end < 2; ++end) {
    std::vector<Vec2> plus = corners, minus = corners;
    ShiftWall(normal, along, end == 0 ? kStep : 0.0, end == 1 ? kStep : 0.0, &plus);
    ShiftWall(normal, along, end == 0 ? -kStep : 0.0, end == 1 ? -kStep : 0.0, &minus);
    const auto p = FitLine(plus, normal), m = FitLine(minus, normal);
    J(0, end) = core::NormalizeAngle(p.first - m.first) / (2.0 * kStep);
    J(1, end) = (p.second - m.second) / (2.0 * kStep);
  }
  return sigma * sigma * (J * J.transpose());
}

}  // namespace pavilion::scenarios
