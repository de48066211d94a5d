#include "sim/world/wall_geometry.h"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace pavilion::sim {
namespace {

Eigen::Vector2d LeftNormal(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d d = (b - a).normalized();
  return {-d.y(), d.x()};
}

// Offset of vertex i to the left side of the polyline (the right side is its
// negation), mitred between the neighbouring segments' offset lines. Also
// returns the mitre ratio (offset length / half thickness).
Eigen::Vector2d LeftOffset(const Wall& wall, std::size_t i, double* ratio) {
  const auto& p = wall.points_m;
  const std::size_t n = p.size();
  const double half = 0.5 * wall.thickness_m;
  const bool has_prev = wall.closed || i > 0;
  const bool has_next = wall.closed || i + 1 < n;
  const std::size_t prev = (i + n - 1) % n;
  const std::size_t next = (i + 1) % n;
  if (!has_prev) {
    *ratio = 1.0;
    return half * LeftNormal(p[i], p[next]);
  }
  if (!has_next) {
    *ratio = 1.0;
    return half * LeftNormal(p[prev], p[i]);
  }
  const Eigen::Vector2d n_in = LeftNormal(p[prev], p[i]);
  const Eigen::Vector2d n_out = LeftNormal(p[i], p[next]);
  const Eigen::Vector2d bisector = n_in + n_out;
  const double norm = bisector.norm();
  if (norm < 1e-9) {  // the wall turns back on itself
    *ratio = 1e9;
    return half * n_in;
  }
  const Eigen::Vector2d m = bisector / norm;
  const double cos_half = m.dot(n_in);
  *ratio = 1.0 / cos_half;
  return (half / cos_half) * m;
}

}  // namespace

std::vector<Quad> WallFootprint(const Wall& wall) {
  const auto& p = wall.points_m;
  const std::size_t n = p.size();
  std::vector<Eigen::Vector2d> left(n), right(n);
  for (std::size_t i = 0; i < n; ++i) {
    double ratio;
    const Eigen::Vector2d off = LeftOffset(wall, i, &ratio);
    left[i] = p[i] + off;
    right[i] = p[i] - off;
  }
  std::vector<Quad> quads;
  const std::size_t segments = wall.closed ? n : n - 1;
  for (std::size_t i = 0; i < segments; ++i) {
    const std::size_t j = (i + 1) % n;
    quads.push_back({right[i], right[j], left[j], left[i]});
  }
  return quads;
}

std::vector<std::array<Eigen::Vector2d, 2>> WallOutline(const Wall& wall) {
  const std::vector<Quad> quads = WallFootprint(wall);
  std::vector<std::array<Eigen::Vector2d, 2>> outline;
  for (const Quad& q : quads) outline.push_back({q[0], q[1]});  // right side, forward
  for (auto it = quads.rbegin(); it != quads.rend(); ++it) {
    outline.push_back({(*it)[2], (*it)[3]});  // left side, backward
  }
  if (!wall.closed && !quads.empty()) {
    outline.push_back({quads.back()[1], quads.back()[2]});    // end cap
    outline.push_back({quads.front()[3], quads.front()[0]});  // start cap
  }
  return outline;
}

double MaxMitreRatio(const Wall& wall) {
  double worst = 1.0;
  for (std::size_t i = 0; i < wall.points_m.size(); ++i) {
    double ratio;
    LeftOffset(wall, i, &ratio);
    worst = std::max(worst, ratio);
  }
  return worst;
}

Quad BoxFootprint(const Box& box) {
  const double c = std::cos(box.pose.theta_rad);
  const double s = std::sin(box.pose.theta_rad);
  const double hx = 0.5 * box.size_m.x();
  const double hy = 0.5 * box.size_m.y();
  Quad q;
  const double corners[4][2] = {{-hx, -hy}, {hx, -hy}, {hx, hy}, {-hx, hy}};
  for (int k = 0; k < 4; ++k) {
    q[k] = {box.pose.x_m + c * corners[k][0] - s * corners[k][1],
            box.pose.y_m + s * corners[k][0] + c * corners[k][1]};
  }
  return q;
}

}  // namespace pavilion::sim
