#include "nav/reactive/swept_polygon.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>

namespace pavilion::nav {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kTwoPi = 2.0 * std::numbers::pi;
// Beyond this ICR distance (m) the arc is treated as a straight line: over the
// robot's few metres it bends by less than 1e-8 m (sagitta l²/2R).
constexpr double kStraightRadius_m = 1e9;

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

// Inside or on the boundary of a counter-clockwise convex polygon.
bool InsideOrOn(const core::Polygon2& polygon, const Eigen::Vector2d& p) {
  for (std::size_t i = 0, n = polygon.size(); i < n; ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % n];
    if (Cross(b - a, p - a) < 0.0) return false;
  }
  return true;
}

// The point slides along -sign(v)·x: the first edge crossing of that ray.
double StraightTime(const core::Polygon2& polygon, double v_mps, const Eigen::Vector2d& p) {
  const double direction = v_mps > 0.0 ? 1.0 : -1.0;
  double best_m = kInfinity;
  for (std::size_t i = 0, n = polygon.size(); i < n; ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % n];
    if ((a.y() - p.y()) * (b.y() - p.y()) > 0.0 || a.y() == b.y()) continue;
    const double s = (p.y() - a.y()) / (b.y() - a.y());
    const double x = a.x() + s * (b.x() - a.x());
    const double travel_m = (p.x() - x) * direction;
    if (travel_m >= 0.0) best_m = std::min(best_m, travel_m);
  }
  return best_m / std::abs(v_mps);
}

// The point turns about the ICR c at -ω: the first edge crossing of its circle
// in that sense. Roots of |a + s·d - c|² = |p - c|² with the constant term
// written as (a - p)·(a + p - 2c) to keep precision for far centres.
double TurningTime(const core::Polygon2& polygon, const BodyTwist& twist,
                   const Eigen::Vector2d& p) {
  const Eigen::Vector2d c(0.0, twist.v_mps / twist.omega_radps);
  const Eigen::Vector2d from = p - c;
  if (from.squaredNorm() == 0.0) return kInfinity;
  const double sense = twist.omega_radps > 0.0 ? -1.0 : 1.0;
  double best_rad = kInfinity;
  auto consider = [&](const Eigen::Vector2d& q) {
    const Eigen::Vector2d to = q - c;
    double angle_rad = sense * std::atan2(Cross(from, to), from.dot(to));
    if (angle_rad < 0.0) angle_rad += kTwoPi;
    best_rad = std::min(best_rad, angle_rad);
  };
  for (std::size_t i = 0, n = polygon.size(); i < n; ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d d = polygon[(i + 1) % n] - a;
    const double qa = d.squaredNorm();
    const double qb = (a - c).dot(d);
    const double qk = (a - p).dot(a + p - 2.0 * c);
    const double disc = qb * qb - qa * qk;
    if (disc < 0.0) continue;
    const double q = -(qb + std::copysign(std::sqrt(disc), qb));
    const double roots[2] = {q / qa, q != 0.0 ? qk / q : q / qa};
    for (double s : roots) {
      if (s >= 0.0 && s <= 1.0) consider(a + s * d);
    }
  }
  return best_rad / std::abs(twist.omega_radps);
}

}  // namespace

BodyTwist TwistFromWheels(double left_mps, double right_mps, double wheelbase_m) {
  return {0.5 * (left_mps + right_mps), (right_mps - left_mps) / wheelbase_m};
}

bool IsConvexCounterClockwise(const core::Polygon2& polygon) {
  const std::size_t n = polygon.size();
  if (n < 3) return false;
  for (const Eigen::Vector2d& v : polygon) {
    if (!v.allFinite()) return false;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[(i + 1) % n];
    const Eigen::Vector2d& c = polygon[(i + 2) % n];
    if (!(Cross(b - a, c - b) > 0.0)) return false;
  }
  // A strictly convex turn at every vertex with total turning 2π (not 4π, ...).
  return core::SignedArea(polygon) > 0.0 && core::IsSimple(polygon);
}

double Circumradius(const core::Polygon2& polygon) {
  double r_m = 0.0;
  for (const Eigen::Vector2d& v : polygon) r_m = std::max(r_m, v.norm());
  return r_m;
}

core::Polygon2 InflateConvexPolygon(const core::Polygon2& polygon, double offset_m) {
  const std::size_t n = polygon.size();
  std::vector<Eigen::Vector2d> normals(n);
  std::vector<double> offsets(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d d = polygon[(i + 1) % n] - polygon[i];
    normals[i] = Eigen::Vector2d(d.y(), -d.x()).normalized();
    offsets[i] = normals[i].dot(polygon[i]) + offset_m;
  }
  core::Polygon2 grown(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t prev = (i + n - 1) % n;
    Eigen::Matrix2d lines;
    lines.row(0) = normals[prev].transpose();
    lines.row(1) = normals[i].transpose();
    grown[i] = lines.inverse() * Eigen::Vector2d(offsets[prev], offsets[i]);
  }
  return grown;
}

double SignedDistance(const core::Polygon2& polygon, const Eigen::Vector2d& p,
                      Eigen::Vector2d* outward_normal) {
  double edge_max_m = -kInfinity;  // max over edges of the distance outside its line
  double nearest_m = kInfinity;
  Eigen::Vector2d edge_normal = Eigen::Vector2d::UnitX();
  Eigen::Vector2d nearest = p;
  for (std::size_t i = 0, n = polygon.size(); i < n; ++i) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d d = polygon[(i + 1) % n] - a;
    const Eigen::Vector2d normal = Eigen::Vector2d(d.y(), -d.x()).normalized();
    const double outside_m = normal.dot(p - a);
    if (outside_m > edge_max_m) {
      edge_max_m = outside_m;
      edge_normal = normal;
    }
    const double s = std::clamp((p - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    const double distance_m = (p - (a + s * d)).norm();
    if (distance_m < nearest_m) {
      nearest_m = distance_m;
      nearest = a + s * d;
    }
  }
  if (edge_max_m <= 0.0 || nearest_m == 0.0) {
    *outward_normal = edge_normal;
    return edge_max_m <= 0.0 ? edge_max_m : 0.0;
  }
  *outward_normal = (p - nearest) / nearest_m;
  return nearest_m;
}

Eigen::Vector3d PoseAfter(const BodyTwist& twist, double time_s) {
  const double theta_rad = twist.omega_radps * time_s;
  const double travel_m = twist.v_mps * time_s;
  if (theta_rad == 0.0) return {travel_m, 0.0, 0.0};
  const double half = 0.5 * theta_rad;
  const double chord_m = travel_m * std::sin(half) / half;
  return {chord_m * std::cos(half), chord_m * std::sin(half), theta_rad};
}

double ExactTimeToCollision(const core::Polygon2& polygon_in_robot, const BodyTwist& twist,
                            const Eigen::Vector2d& point_in_robot) {
  if (InsideOrOn(polygon_in_robot, point_in_robot)) return 0.0;
  const double v = twist.v_mps;
  const double w = twist.omega_radps;
  if (w == 0.0 || std::abs(v) > kStraightRadius_m * std::abs(w)) {
    return v == 0.0 ? kInfinity : StraightTime(polygon_in_robot, v, point_in_robot);
  }
  return TurningTime(polygon_in_robot, twist, point_in_robot);
}

double ExactArcLengthToCollision(const core::Polygon2& polygon_in_robot, double curvature_per_m,
                                 const Eigen::Vector2d& point_in_robot) {
  return ExactTimeToCollision(polygon_in_robot, {1.0, curvature_per_m}, point_in_robot);
}

double ExactRotationToCollision(const core::Polygon2& polygon_in_robot, bool counter_clockwise,
                                const Eigen::Vector2d& point_in_robot) {
  return ExactTimeToCollision(polygon_in_robot, {0.0, counter_clockwise ? 1.0 : -1.0},
                              point_in_robot);
}

void AppendSweptOutline(const core::Polygon2& polygon, const BodyTwist& twist, double duration_s,
                        double step_m, double spacing_m, const core::Pose2& frame_from_robot,
                        std::vector<Eigen::Vector2d>* points) {
  const double sweep_m =
      (std::abs(twist.v_mps) + std::abs(twist.omega_radps) * Circumradius(polygon)) *
      std::max(0.0, duration_s);
  const int copies = 1 + static_cast<int>(std::ceil(sweep_m / step_m));
  for (int c = 0; c < copies; ++c) {
    const double t_s = copies == 1 ? 0.0 : duration_s * c / (copies - 1);
    const Eigen::Vector3d at = PoseAfter(twist, t_s);
    const core::Pose2 frame_from_copy = frame_from_robot * core::Pose2{at.x(), at.y(), at.z()};
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const Eigen::Vector2d& a = polygon[i];
      const Eigen::Vector2d& b = polygon[(i + 1) % polygon.size()];
      const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / spacing_m)));
      for (int k = 0; k < steps; ++k) {
        points->push_back(frame_from_copy * (a + (b - a) * (static_cast<double>(k) / steps)));
      }
    }
  }
}

}  // namespace pavilion::nav
