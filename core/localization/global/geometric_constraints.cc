#include "core/localization/global/geometric_constraints.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pavilion::core {
namespace {

double Wrap(double angle_rad) { return NormalizeAngle(angle_rad); }

// The two-step decision of Figs. 5.7-5.8 for an equality: D^2 < gate.
bool Equal(double difference, double variance, double gate) {
  if (!(variance > 0.0)) return difference == 0.0;
  return difference * difference / variance < gate;
}

double Squared(double x) { return x * x; }

// Signed distance of a point from a line, eq. 5.30, and its variance (eqs.
// 5.34-5.35), the line and point uncorrelated.
void PointLineDistance(const Line& line, const Point2Uncertain& point, double* d,
                       double* variance) {
  const double c = std::cos(line.alpha_rad);
  const double s = std::sin(line.alpha_rad);
  const double x = point.position_m.x();
  const double y = point.position_m.y();
  *d = x * c + y * s - line.r_m;
  const Eigen::Vector2d j_point(c, s);                   // eq. 5.33
  const Eigen::Vector2d j_line(y * c - x * s, -1.0);     // eq. 5.32
  *variance = j_point.dot(point.covariance * j_point) +  // eq. 5.34
              j_line.dot(line.covariance * j_line);      // eq. 5.35
}

// Cartesian distance of two points, eq. 5.39, and its variance (eq. 5.43).
void PointPointDistance(const Point2Uncertain& a, const Point2Uncertain& b, double* d,
                        double* variance) {
  const Eigen::Vector2d delta = b.position_m - a.position_m;
  *d = delta.norm();
  if (*d <= 0.0) {
    *variance = a.covariance.trace() + b.covariance.trace();
    return;
  }
  const Eigen::Vector2d u = delta / *d;  // eqs. 5.40-5.41
  *variance = u.dot((a.covariance + b.covariance) * u);
}

// Separation of two (anti)parallel lines: r_i - r_j cos(alpha_i - alpha_j),
// frame invariant for them, and its variance.
void Separation(const Line& i, const Line& j, double* s, double* variance) {
  const double cos_delta = std::cos(i.alpha_rad - j.alpha_rad);
  *s = i.r_m - j.r_m * cos_delta;
  *variance = i.covariance(1, 1) + Squared(cos_delta) * j.covariance(1, 1);
}

}  // namespace

void SegmentLength(const Point2Uncertain& first, const Point2Uncertain& second, double* length_m,
                   double* variance_m2) {
  PointPointDistance(first, second, length_m, variance_m2);
}

ConstraintFeature MapConstraintFeature(const RobotMap& map, MapFeatureType type, int index) {
  ConstraintFeature f;
  const auto i = static_cast<std::size_t>(index);
  switch (type) {
    case MapFeatureType::kLine:
      f.line = map.lines.at(i).line;
      break;
    case MapFeatureType::kSegment: {
      const MapSegment& s = map.segments.at(i);
      f.line = s.line;
      f.finite = true;
      SegmentLength(s.first_endpoint, s.second_endpoint, &f.length_m, &f.length_variance_m2);
      break;
    }
    case MapFeatureType::kMultiSegmentLine: {
      const MapMultiSegmentLine& m = map.multi_segment_lines.at(i);
      f.line = m.line;
      f.finite = !m.segments.empty();
      for (const auto& [a, b] : m.segments) {
        double length = 0.0;
        double variance = 0.0;
        SegmentLength(a, b, &length, &variance);
        if (length > f.length_m) {
          f.length_m = length;
          f.length_variance_m2 = variance;
        }
      }
      break;
    }
    case MapFeatureType::kPoint:
      f.is_line = false;
      f.point = map.points.at(i).point;
      break;
    case MapFeatureType::kBeacon:
      f.is_line = false;
      f.point = map.beacons.at(i).point;
      break;
  }
  return f;
}

ConstraintFeature ObservationConstraintFeature(const Observation& observation,
                                               const SensorView& view) {
  ConstraintFeature f;
  const Pose2& mount = view.robot_from_sensor;
  if (observation.type == ObservationType::kLine) {
    Line in_sensor;
    in_sensor.alpha_rad = observation.z.x();
    in_sensor.r_m = observation.z.y();
    in_sensor.covariance = observation.covariance;
    f.line = LineInParent(in_sensor, mount, view.robot_from_sensor_covariance);
    for (const ObservedSegment& s : observation.segments) {
      double length = 0.0;
      double variance = 0.0;
      SegmentLength(s.first, s.last, &length, &variance);
      if (length > f.length_m) {
        f.length_m = length;
        f.length_variance_m2 = variance;
      }
      f.finite = true;
    }
    return f;
  }
  f.is_line = false;
  const double c = std::cos(mount.theta_rad);
  const double s = std::sin(mount.theta_rad);
  Eigen::Matrix2d rotation;
  rotation << c, -s, s, c;
  const Eigen::Vector2d p = observation.z;
  f.point.position_m = mount * p;
  Eigen::Matrix<double, 2, 3> j_mount;
  j_mount << 1.0, 0.0, -s * p.x() - c * p.y(), 0.0, 1.0, c * p.x() - s * p.y();
  f.point.covariance = rotation * observation.covariance * rotation.transpose() +
                       j_mount * view.robot_from_sensor_covariance * j_mount.transpose();
  return f;
}

bool SatisfiesUnaryConstraint(const ConstraintFeature& local, const ConstraintFeature& global,
                              double gate) {
  if (!local.finite || !global.finite) return true;  // Table 5.1: lines and points have none
  const double variance = local.length_variance_m2 + global.length_variance_m2;  // eq. 5.19
  if (Equal(local.length_m - global.length_m, variance, gate)) return true;      // eqs. 5.20-5.21
  return local.length_m <= global.length_m;                                      // eq. 5.18
}

BinaryDistances ComputeBinaryDistances(const ConstraintFeature& local_i,
                                       const ConstraintFeature& local_j,
                                       const ConstraintFeature& global_i,
                                       const ConstraintFeature& global_j, double gate) {
  BinaryDistances d;
  if (local_i.is_line && local_j.is_line) {
    const double da_l = Wrap(local_i.line.alpha_rad - local_j.line.alpha_rad);  // eq. 5.23
    const double da_g = Wrap(global_i.line.alpha_rad - global_j.line.alpha_rad);
    const double var_a = local_i.line.covariance(0, 0) + local_j.line.covariance(0, 0) +
                         global_i.line.covariance(0, 0) + global_j.line.covariance(0, 0);  // 5.24
    d.angle = Squared(Wrap(da_l - da_g)) / std::max(var_a, 1e-300);                        // 5.26
    const double var_g = global_i.line.covariance(0, 0) + global_j.line.covariance(0, 0);
    d.parallel = Equal(da_g, var_g, gate) ||
                 Equal(std::abs(da_g) - std::numbers::pi, var_g, gate);  // eq. 5.27
    if (d.parallel) {
      double s_l = 0.0, v_l = 0.0, s_g = 0.0, v_g = 0.0;
      Separation(local_i.line, local_j.line, &s_l, &v_l);
      Separation(global_i.line, global_j.line, &s_g, &v_g);
      d.separation = Squared(s_l - s_g) / std::max(v_l + v_g, 1e-300);  // eq. 5.29
    }
    return d;
  }
  double d_l = 0.0, v_l = 0.0, d_g = 0.0, v_g = 0.0;
  if (local_i.is_line != local_j.is_line) {
    const bool i_line = local_i.is_line;
    PointLineDistance(i_line ? local_i.line : local_j.line, i_line ? local_j.point : local_i.point,
                      &d_l, &v_l);
    PointLineDistance(i_line ? global_i.line : global_j.line,
                      i_line ? global_j.point : global_i.point, &d_g, &v_g);
  } else {
    PointPointDistance(local_i.point, local_j.point, &d_l, &v_l);
    PointPointDistance(global_i.point, global_j.point, &d_g, &v_g);
  }
  d.distance = Squared(d_l - d_g) / std::max(v_l + v_g, 1e-300);  // eqs. 5.37, 5.45 with 5.38, 5.46
  return d;
}

bool SatisfiesBinaryConstraint(const ConstraintFeature& local_i, const ConstraintFeature& local_j,
                               const ConstraintFeature& global_i, const ConstraintFeature& global_j,
                               double gate) {
  const BinaryDistances d = ComputeBinaryDistances(local_i, local_j, global_i, global_j, gate);
  if (local_i.is_line && local_j.is_line) {
    if (!(d.angle < gate)) return false;        // eq. 5.25
    return !d.parallel || d.separation < gate;  // eq. 5.28
  }
  return d.distance < gate;  // eqs. 5.36, 5.44
}

}  // namespace pavilion::core
