#include "sim/raycast/ray_shapes.h"

#include <cmath>
#include <limits>

namespace pavilion::sim {
namespace {

// Cyrus–Beck clipping of the ray's parameter interval by one half-space
// n·p <= c; tracks the entering plane's normal.
bool Clip(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const Eigen::Vector3d& n, double c,
          double* t_in, double* t_out, Eigen::Vector3d* n_in) {
  const double denom = n.dot(d);
  const double dist = c - n.dot(o);  // >= 0 inside
  if (denom == 0.0) return dist >= 0.0;
  const double t = dist / denom;
  if (denom < 0.0) {  // entering
    if (t > *t_in) {
      *t_in = t;
      *n_in = n;
    }
  } else if (t < *t_out) {
    *t_out = t;
  }
  return *t_in <= *t_out;
}

std::optional<RayShapeHit> Finish(double t_in, double t_out, const Eigen::Vector3d& n,
                                  double t_max) {
  if (t_in <= 0.0 || t_in > t_max || t_in > t_out) return std::nullopt;  // inside or missed
  return RayShapeHit{t_in, n.normalized()};
}

}  // namespace

std::optional<RayShapeHit> RaySphere(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                     double radius, double t_max) {
  const double a = d.squaredNorm();
  const double b = o.dot(d);
  const double c = o.squaredNorm() - radius * radius;
  if (c <= 0.0 || a == 0.0) return std::nullopt;  // inside
  const double disc = b * b - a * c;
  if (disc < 0.0) return std::nullopt;
  const double t = (-b - std::sqrt(disc)) / a;
  if (t <= 0.0 || t > t_max) return std::nullopt;
  return RayShapeHit{t, (o + t * d).normalized()};
}

std::optional<RayShapeHit> RayBox(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                  const Eigen::Vector3d& half, double t_max) {
  double t_in = -std::numeric_limits<double>::infinity();
  double t_out = std::numeric_limits<double>::infinity();
  Eigen::Vector3d n_in = Eigen::Vector3d::Zero();
  for (int axis = 0; axis < 3; ++axis) {
    Eigen::Vector3d n = Eigen::Vector3d::Zero();
    n[axis] = 1.0;
    if (!Clip(o, d, n, half[axis], &t_in, &t_out, &n_in)) return std::nullopt;
    if (!Clip(o, d, -n, half[axis], &t_in, &t_out, &n_in)) return std::nullopt;
  }
  return Finish(t_in, t_out, n_in, t_max);
}

std::optional<RayShapeHit> RayCylinderZ(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                        double radius, double half_height, double t_max) {
  double t_in = -std::numeric_limits<double>::infinity();
  double t_out = std::numeric_limits<double>::infinity();
  Eigen::Vector3d n_in = Eigen::Vector3d::Zero();
  // The caps' slab.
  if (!Clip(o, d, Eigen::Vector3d::UnitZ(), half_height, &t_in, &t_out, &n_in)) return std::nullopt;
  if (!Clip(o, d, -Eigen::Vector3d::UnitZ(), half_height, &t_in, &t_out, &n_in)) {
    return std::nullopt;
  }
  // The infinite cylinder x² + y² <= r².
  const double a = d.x() * d.x() + d.y() * d.y();
  const double b = o.x() * d.x() + o.y() * d.y();
  const double c = o.x() * o.x() + o.y() * o.y() - radius * radius;
  if (a == 0.0) {
    if (c > 0.0) return std::nullopt;  // parallel to the axis, outside
  } else {
    const double disc = b * b - a * c;
    if (disc < 0.0) return std::nullopt;
    const double root = std::sqrt(disc);
    const double t0 = (-b - root) / a;
    const double t1 = (-b + root) / a;
    if (t0 > t_in) {
      t_in = t0;
      n_in = {o.x() + t0 * d.x(), o.y() + t0 * d.y(), 0.0};
    }
    t_out = std::min(t_out, t1);
  }
  return Finish(t_in, t_out, n_in, t_max);
}

std::optional<RayShapeHit> RayPrismZ(const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                                     const std::vector<Eigen::Vector2d>& polygon, double z0,
                                     double z1, double t_max) {
  double t_in = -std::numeric_limits<double>::infinity();
  double t_out = std::numeric_limits<double>::infinity();
  Eigen::Vector3d n_in = Eigen::Vector3d::Zero();
  if (!Clip(o, d, Eigen::Vector3d::UnitZ(), z1, &t_in, &t_out, &n_in)) return std::nullopt;
  if (!Clip(o, d, -Eigen::Vector3d::UnitZ(), -z0, &t_in, &t_out, &n_in)) return std::nullopt;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
    const Eigen::Vector3d n(b.y() - a.y(), a.x() - b.x(), 0.0);  // outward for CCW
    if (!Clip(o, d, n, n.x() * a.x() + n.y() * a.y(), &t_in, &t_out, &n_in)) return std::nullopt;
  }
  return Finish(t_in, t_out, n_in, t_max);
}

}  // namespace pavilion::sim
