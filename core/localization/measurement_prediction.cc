#include "core/localization/measurement_prediction.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/localization/map_cross_covariance.h"
#include "core/math/chi_square.h"

namespace pavilion::core {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
// Points closer to the sensor origin than this have no defined bearing; they
// are never visible (m).
constexpr double kMinPointDistanceM = 1e-6;
// The sight line to a vertical edge may touch the walls that meet at it:
// crossings this close to the edge do not occlude it (m).
constexpr double kEdgeGrazeM = 0.03;
// Slack when comparing a field of view's width with the full circle (rad).
constexpr double kFullCircleSlackRad = 1e-9;

void Require(bool ok, const char* field, const char* expected) {
  if (!ok) throw std::invalid_argument(std::string(field) + " must be " + expected);
}

// The sensor's pose in the map x_WS = x_WR (+) x_RS, with the Jacobians of the
// compounding (eqs. B.30-B.31) with respect to both operands.
struct SensorFrame {
  Pose2 world_from_sensor;
  Eigen::Matrix3d J_sensor_robot;  // d x_WS / d x_WR
  Eigen::Matrix3d J_sensor_mount;  // d x_WS / d x_RS
};

// True when the segment eye -> target crosses a map segment (of a segment
// or an MS-line) farther than kEdgeGrazeM from the target.
bool SightCrossesMapSegment(const RobotMap& map, const Eigen::Vector2d& eye,
                            const Eigen::Vector2d& target) {
  const Eigen::Vector2d d = target - eye;
  const double length = d.norm();
  if (length <= kEdgeGrazeM) return false;
  const double t_max = 1.0 - kEdgeGrazeM / length;
  const auto crosses = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const Eigen::Vector2d e = b - a;
    const double den = d.x() * e.y() - d.y() * e.x();
    if (std::abs(den) < 1e-12) return false;  // parallel
    const Eigen::Vector2d w = a - eye;
    const double t = (w.x() * e.y() - w.y() * e.x()) / den;  // along the sight line
    const double u = (w.x() * d.y() - w.y() * d.x()) / den;  // along the wall
    return t > 0.0 && t < t_max && u >= 0.0 && u <= 1.0;
  };
  for (const MapSegment& s : map.segments) {
    if (crosses(s.first_endpoint.position_m, s.second_endpoint.position_m)) return true;
  }
  for (const MapMultiSegmentLine& m : map.multi_segment_lines) {
    for (const auto& [a, b] : m.segments) {
      if (crosses(a.position_m, b.position_m)) return true;
    }
  }
  return false;
}

SensorFrame MakeSensorFrame(const Pose2& world_from_robot, const Pose2& robot_from_sensor) {
  SensorFrame f;
  f.world_from_sensor = world_from_robot * robot_from_sensor;
  const double c = std::cos(world_from_robot.theta_rad);
  const double s = std::sin(world_from_robot.theta_rad);
  f.J_sensor_robot << 1.0, 0.0, -(f.world_from_sensor.y_m - world_from_robot.y_m),  //
      0.0, 1.0, f.world_from_sensor.x_m - world_from_robot.x_m,                     //
      0.0, 0.0, 1.0;
  f.J_sensor_mount << c, -s, 0.0,  //
      s, c, 0.0,                   //
      0.0, 0.0, 1.0;
  return f;
}

// A map point expressed in the sensor frame (eq. B.28) with the Jacobians with
// respect to the sensor pose in the map (eq. B.29 composed with B.32) and to
// the point's map coordinates (the rotation block of eq. B.32).
struct PointInSensor {
  Eigen::Vector2d p;
  Eigen::Matrix<double, 2, 3> J_p_sensor;
  Eigen::Matrix2d J_p_point;
};

PointInSensor TransformPoint(const Eigen::Vector2d& point_in_world,
                             const Pose2& world_from_sensor) {
  const double c = std::cos(world_from_sensor.theta_rad);
  const double s = std::sin(world_from_sensor.theta_rad);
  const double dx = point_in_world.x() - world_from_sensor.x_m;
  const double dy = point_in_world.y() - world_from_sensor.y_m;
  PointInSensor out;
  out.p = {c * dx + s * dy, -s * dx + c * dy};
  out.J_p_sensor << -c, -s, out.p.y(),  //
      s, -c, -out.p.x();
  out.J_p_point << c, s,  //
      -s, c;
  return out;
}

// Covariance of a transformed point from the robot pose, the mounting pose and
// the map point.
Eigen::Matrix2d PointCovariance(const PointInSensor& ps, const SensorFrame& frame,
                                const PoseWithCovariance& world_from_robot, const SensorView& view,
                                const Eigen::Matrix2d& point_covariance) {
  const Eigen::Matrix<double, 2, 3> J_pose = ps.J_p_sensor * frame.J_sensor_robot;
  const Eigen::Matrix<double, 2, 3> J_mount = ps.J_p_sensor * frame.J_sensor_mount;
  return J_pose * world_from_robot.covariance * J_pose.transpose() +
         J_mount * view.robot_from_sensor_covariance * J_mount.transpose() +
         ps.J_p_point * point_covariance * ps.J_p_point.transpose();
}

// Gradient of the bearing atan2(y, x) of a point with respect to the point.
Eigen::RowVector2d BearingGradient(const Eigen::Vector2d& p) {
  const double d2 = std::max(p.squaredNorm(), kMinPointDistanceM * kMinPointDistanceM);
  return {-p.y() / d2, p.x() / d2};
}

// Angle in [0, 2 pi).
double WrapPositive(double angle_rad) {
  return angle_rad - kTwoPi * std::floor(angle_rad / kTwoPi);
}

// Whether the counter-clockwise angular intervals [a, a + a_width] and
// [b, b + b_width] (widths in [0, 2 pi]) intersect.
bool IntervalsOverlap(double a, double a_width, double b, double b_width) {
  if (a_width + b_width >= kTwoPi) return true;
  return WrapPositive(b - a) <= a_width || WrapPositive(a - b) <= b_width;
}

bool FullFieldOfView(const SensorView& view) {
  return view.max_bearing_rad - view.min_bearing_rad >= kTwoPi - kFullCircleSlackRad;
}

bool OverlapsFieldOfView(double start_rad, double width_rad, const SensorView& view) {
  return FullFieldOfView(view) || IntervalsOverlap(start_rad, width_rad, view.min_bearing_rad,
                                                   view.max_bearing_rad - view.min_bearing_rad);
}

// Distance from the sensor origin to the segment [a, b].
double DistanceToSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0.0 ? std::clamp(-a.dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab).norm();
}

const Point2Uncertain& MapPointOf(const RobotMap& map, MapFeatureRef ref) {
  if (ref.type == MapFeatureType::kPoint) return map.points.at(ref.index).point;
  if (ref.type == MapFeatureType::kBeacon) return map.beacons.at(ref.index).point;
  throw std::invalid_argument("MapPointOf: not a point feature");
}

const Line& MapLineOf(const RobotMap& map, MapFeatureRef ref) {
  switch (ref.type) {
    case MapFeatureType::kLine:
      return map.lines.at(ref.index).line;
    case MapFeatureType::kSegment:
      return map.segments.at(ref.index).line;
    case MapFeatureType::kMultiSegmentLine:
      return map.multi_segment_lines.at(ref.index).line;
    default:
      throw std::invalid_argument("MapLineOf: not a line feature");
  }
}

}  // namespace

void SensorView::Validate() const {
  Require(std::isfinite(robot_from_sensor.x_m) && std::isfinite(robot_from_sensor.y_m) &&
              std::isfinite(robot_from_sensor.theta_rad),
          "robot_from_sensor", "finite");
  Require(robot_from_sensor_covariance.allFinite() &&
              (robot_from_sensor_covariance - robot_from_sensor_covariance.transpose())
                      .cwiseAbs()
                      .maxCoeff() <= 1e-12 &&
              robot_from_sensor_covariance.diagonal().minCoeff() >= 0.0,
          "robot_from_sensor_covariance", "a finite symmetric matrix with a diagonal >= 0");
  Require(std::isfinite(perception_radius_m) && perception_radius_m > 0.0, "perception_radius_m",
          "a finite value > 0");
  Require(std::isfinite(min_view_angle_rad) && min_view_angle_rad >= 0.0 &&
              min_view_angle_rad < std::numbers::pi,
          "min_view_angle_rad", "in [0, pi)");
  Require(std::isfinite(min_bearing_rad) && std::isfinite(max_bearing_rad) &&
              max_bearing_rad > min_bearing_rad &&
              max_bearing_rad - min_bearing_rad <= kTwoPi + kFullCircleSlackRad,
          "max_bearing_rad", "greater than min_bearing_rad, by at most 2 pi");
}

void PredictionOptions::Validate() const {
  Require(std::isfinite(significance) && significance > 0.0 && significance < 1.0, "significance",
          "in (0, 1)");
}

LitArcMeasurement LitArc(double radius_m, const Eigen::Vector2d& center_m) {
  LitArcMeasurement m{center_m, Eigen::Matrix2d::Identity(), Eigen::Matrix2d::Zero()};
  const double d = center_m.norm();
  if (radius_m <= 0.0 || d <= radius_m) return m;  // a marker on a face; or inside: no arc
  // h(p) = p - delta(d) u with u = p / d: dh/dp = I - (delta / d)(I - u u^T) - delta' u u^T.
  const double delta = radius_m * (kLitArcFarFraction + kLitArcNearFactor * radius_m / d);
  const double delta_prime = -kLitArcNearFactor * radius_m * radius_m / (d * d);
  const Eigen::Vector2d u = center_m / d;
  const Eigen::Matrix2d uu = u * u.transpose();
  m.z = center_m - delta * u;
  m.J_z_center = Eigen::Matrix2d::Identity() - (delta / d) * (Eigen::Matrix2d::Identity() - uu) -
                 delta_prime * uu;
  const double sigma_m = kLitArcSamplingFraction * radius_m;
  m.sampling_covariance = sigma_m * sigma_m * uu;
  return m;
}

const std::string& FeatureId(const RobotMap& map, MapFeatureRef ref) {
  switch (ref.type) {
    case MapFeatureType::kLine:
      return map.lines.at(ref.index).id;
    case MapFeatureType::kSegment:
      return map.segments.at(ref.index).id;
    case MapFeatureType::kMultiSegmentLine:
      return map.multi_segment_lines.at(ref.index).id;
    case MapFeatureType::kPoint:
      return map.points.at(ref.index).id;
    case MapFeatureType::kBeacon:
      return map.beacons.at(ref.index).id;
  }
  throw std::invalid_argument("FeatureId: unknown feature type");
}

bool CanPair(ObservationType observation, MapFeatureType feature) {
  switch (observation) {
    case ObservationType::kLine:
      return feature == MapFeatureType::kLine || feature == MapFeatureType::kSegment ||
             feature == MapFeatureType::kMultiSegmentLine;
    case ObservationType::kBeacon:
      return feature == MapFeatureType::kBeacon;
    case ObservationType::kPoint:
    case ObservationType::kVerticalEdge:
      return feature == MapFeatureType::kPoint;
  }
  return false;
}

MeasurementPredictor::MeasurementPredictor(const RobotMap& map, const PredictionOptions& options)
    : map_(map), options_(options) {
  options_.Validate();
  equality_gate_ = ChiSquareQuantile(options_.significance, 1);
}

PredictedMeasurement MeasurementPredictor::Predict(
    MapFeatureRef feature, ObservationType type, const PoseWithCovariance& world_from_robot,
    const SensorView& view, const PoseMapCrossCovariance* correlations) const {
  if (!CanPair(type, feature.type)) {
    throw std::invalid_argument("Predict: observation type cannot be paired with feature " +
                                FeatureId(map_, feature));
  }
  const SensorFrame frame = MakeSensorFrame(world_from_robot.pose, view.robot_from_sensor);
  PredictedMeasurement out;
  out.feature = feature;
  out.type = type;
  Eigen::Matrix<double, 2, 3> J_z_sensor;  // with respect to the sensor pose in the map
  if (type == ObservationType::kLine) {
    const Line& line = MapLineOf(map_, feature);
    LineTransformJacobians J;
    const Line local = LineInChild(line, frame.world_from_sensor, Eigen::Matrix3d::Zero(), &J);
    out.z = {local.alpha_rad, local.r_m};  // eqs. B.22-B.23
    Eigen::Matrix2d M = line.covariance;
    if (!options_.use_map_line_angle_variance) {  // §4.3
      M(0, 0) = 0.0;
      M(0, 1) = 0.0;
      M(1, 0) = 0.0;
    }
    J_z_sensor = J.J_line_pose;   // eqs. B.14-B.15
    out.J_z_map = J.J_line_line;  // eqs. B.12-B.13
    out.map_covariance = M;
    out.feature_covariance = J.J_line_line * M * J.J_line_line.transpose();
  } else {
    const Point2Uncertain& point = MapPointOf(map_, feature);
    const PointInSensor ps = TransformPoint(point.position_m, frame.world_from_sensor);  // B.28
    const Eigen::Matrix2d M = ps.J_p_point * point.covariance * ps.J_p_point.transpose();
    if (type == ObservationType::kVerticalEdge) {  // §B.3: phi = atan2(y, x)
      const Eigen::RowVector2d g = BearingGradient(ps.p);
      out.z = {std::atan2(ps.p.y(), ps.p.x()), 0.0};
      J_z_sensor.setZero();
      J_z_sensor.row(0) = g * ps.J_p_sensor;
      out.J_z_map.row(0) = g * ps.J_p_point;
      out.feature_covariance.setZero();
      out.feature_covariance(0, 0) = g * M * g.transpose();
    } else {
      // A foil-wrapped column is seen on its lit arc, short of its centre.
      const double radius_m =
          feature.type == MapFeatureType::kBeacon ? map_.beacons.at(feature.index).radius_m : 0.0;
      const LitArcMeasurement arc = LitArc(radius_m, ps.p);
      out.z = arc.z;
      J_z_sensor = arc.J_z_center * ps.J_p_sensor;
      out.J_z_map = arc.J_z_center * ps.J_p_point;
      out.feature_covariance =
          arc.J_z_center * M * arc.J_z_center.transpose() + arc.sampling_covariance;
    }
    out.map_covariance = point.covariance;
  }
  out.J_z_pose = J_z_sensor * frame.J_sensor_robot;                                 // grad h_x
  const Eigen::Matrix<double, 2, 3> J_z_mount = J_z_sensor * frame.J_sensor_mount;  // grad h_s
  out.feature_covariance += J_z_mount * view.robot_from_sensor_covariance * J_z_mount.transpose();
  out.covariance = out.J_z_pose * world_from_robot.covariance * out.J_z_pose.transpose() +
                   out.feature_covariance;  // eq. 4.9
  if (correlations != nullptr) {
    out.pose_map_cross = correlations->Get(feature);
    const Eigen::Matrix2d cross = out.J_z_pose * out.pose_map_cross * out.J_z_map.transpose();
    out.covariance += cross + cross.transpose();
  }
  return out;
}

bool MeasurementPredictor::IsVisible(const PredictedMeasurement& prediction,
                                     const PoseWithCovariance& world_from_robot,
                                     const SensorView& view) const {
  const double gate = equality_gate_;
  // value >= bound, or value statistically equal to bound (two-step decision).
  const auto at_least = [gate](double value, double bound, double variance) {
    if (value >= bound) return true;
    const double d = value - bound;
    return d * d <= gate * variance;
  };
  const double R_S = view.perception_radius_m;
  const SensorFrame frame = MakeSensorFrame(world_from_robot.pose, view.robot_from_sensor);

  // A segment of a map segment or MS-line, [a, b] in the map: eqs. 5.48-5.50.
  const auto segment_visible = [&](const Point2Uncertain& a_w, const Point2Uncertain& b_w) {
    const PointInSensor a = TransformPoint(a_w.position_m, frame.world_from_sensor);
    const PointInSensor b = TransformPoint(b_w.position_m, frame.world_from_sensor);
    if (DistanceToSegment(a.p, b.p) > R_S) return false;
    const double bearing_a = std::atan2(a.p.y(), a.p.x());            // phi_1, eq. 5.49
    const double bearing_b = std::atan2(b.p.y(), b.p.x());            // phi_2
    const double signed_phi = NormalizeAngle(bearing_a - bearing_b);  // eq. 5.50, unwrapped
    const double phi = std::abs(signed_phi);
    // sigma_phi^2 by first-order propagation of all sources.
    const double sign = signed_phi >= 0.0 ? 1.0 : -1.0;
    const Eigen::RowVector2d g_a = sign * BearingGradient(a.p);
    const Eigen::RowVector2d g_b = -sign * BearingGradient(b.p);
    const Eigen::RowVector3d g_sensor = g_a * a.J_p_sensor + g_b * b.J_p_sensor;
    const Eigen::RowVector3d g_pose = g_sensor * frame.J_sensor_robot;
    const Eigen::RowVector3d g_mount = g_sensor * frame.J_sensor_mount;
    const Eigen::RowVector2d g_aw = g_a * a.J_p_point;
    const Eigen::RowVector2d g_bw = g_b * b.J_p_point;
    const double variance = (g_pose * world_from_robot.covariance).dot(g_pose) +
                            (g_mount * view.robot_from_sensor_covariance).dot(g_mount) +
                            (g_aw * a_w.covariance).dot(g_aw) + (g_bw * b_w.covariance).dot(g_bw);
    if (!at_least(phi, view.min_view_angle_rad, variance)) return false;
    return OverlapsFieldOfView(signed_phi >= 0.0 ? bearing_b : bearing_a, phi, view);
  };

  if (prediction.type == ObservationType::kLine) {
    const double r = prediction.z[1];
    const double var_r = prediction.covariance(1, 1);
    if (!at_least(r, 0.0, var_r) || !at_least(R_S, r, var_r)) return false;  // eq. 5.47
    const auto line_in_view = [&] {
      // The line's chord inside the perception disk spans alpha +- beta.
      const double rr = std::max(r, 0.0);
      const double beta = rr >= R_S ? 0.0 : std::atan2(std::sqrt(R_S * R_S - rr * rr), rr);
      return OverlapsFieldOfView(prediction.z[0] - beta, 2.0 * beta, view);
    };
    switch (prediction.feature.type) {
      case MapFeatureType::kSegment: {
        const MapSegment& s = map_.segments.at(prediction.feature.index);
        return segment_visible(s.first_endpoint, s.second_endpoint);  // eq. 5.48
      }
      case MapFeatureType::kMultiSegmentLine: {
        const MapMultiSegmentLine& m = map_.multi_segment_lines.at(prediction.feature.index);
        if (m.segments.empty()) return line_in_view();
        for (const auto& [a, b] : m.segments) {  // Table 5.3: disjunction over segments
          if (segment_visible(a, b)) return true;
        }
        return false;
      }
      default:
        return line_in_view();
    }
  }

  // Points, beacons and vertical edges: eqs. 5.51-5.52 in the sensor frame.
  const Point2Uncertain& point = MapPointOf(map_, prediction.feature);
  if (prediction.type == ObservationType::kVerticalEdge && options_.occlude_vertical_edges &&
      SightCrossesMapSegment(map_, {frame.world_from_sensor.x_m, frame.world_from_sensor.y_m},
                             point.position_m)) {
    return false;
  }
  const PointInSensor ps = TransformPoint(point.position_m, frame.world_from_sensor);
  const double d = ps.p.norm();
  if (d < kMinPointDistanceM) return false;
  const Eigen::Vector2d u = ps.p / d;
  const double var_d =
      u.dot(PointCovariance(ps, frame, world_from_robot, view, point.covariance) * u);
  if (!at_least(R_S, d, var_d)) return false;
  return OverlapsFieldOfView(std::atan2(ps.p.y(), ps.p.x()), 0.0, view);
}

void MeasurementPredictor::PredictVisible(ObservationType type,
                                          const PoseWithCovariance& world_from_robot,
                                          const SensorView& view,
                                          std::vector<PredictedMeasurement>* out,
                                          const PoseMapCrossCovariance* correlations) const {
  const auto consider = [&](MapFeatureType feature_type, std::size_t count) {
    if (!CanPair(type, feature_type)) return;
    for (std::size_t i = 0; i < count; ++i) {
      // A camera sees a column's silhouette, not its centre: vertical edges
      // pair with edges (points of radius 0) only.
      if (type == ObservationType::kVerticalEdge && feature_type == MapFeatureType::kPoint &&
          map_.points[i].radius_m > 0.0) {
        continue;
      }
      PredictedMeasurement p =
          Predict({feature_type, static_cast<int>(i)}, type, world_from_robot, view, correlations);
      if (IsVisible(p, world_from_robot, view)) out->push_back(p);
    }
  };
  consider(MapFeatureType::kLine, map_.lines.size());
  consider(MapFeatureType::kSegment, map_.segments.size());
  consider(MapFeatureType::kMultiSegmentLine, map_.multi_segment_lines.size());
  consider(MapFeatureType::kPoint, map_.points.size());
  consider(MapFeatureType::kBeacon, map_.beacons.size());
}

bool MeasurementPredictor::SatisfiesExtensionConstraint(
    MapFeatureRef feature, std::span<const ObservedSegment> observed_segments,
    const PoseWithCovariance& world_from_robot, const SensorView& view) const {
  if (observed_segments.empty()) return true;
  std::span<const std::pair<Point2Uncertain, Point2Uncertain>> global;
  std::pair<Point2Uncertain, Point2Uncertain> single;
  if (feature.type == MapFeatureType::kSegment) {
    const MapSegment& s = map_.segments.at(feature.index);
    single = {s.first_endpoint, s.second_endpoint};
    global = {&single, 1};
  } else if (feature.type == MapFeatureType::kMultiSegmentLine) {
    global = map_.multi_segment_lines.at(feature.index).segments;
  }
  if (global.empty()) return true;  // lines (Table 5.4: "-") or an MS-line without segments
  const SensorFrame frame = MakeSensorFrame(world_from_robot.pose, view.robot_from_sensor);

  // Eqs. 5.54-5.60 for one observed segment [p, q] (sensor frame) in one map
  // segment [a, b] (map frame).
  const auto contained = [&](const ObservedSegment& local,
                             const std::pair<Point2Uncertain, Point2Uncertain>& g) {
    const Point2Uncertain* map_ends[2] = {&g.first, &g.second};
    const PointInSensor in_sensor[2] = {
        TransformPoint(g.first.position_m, frame.world_from_sensor),
        TransformPoint(g.second.position_m, frame.world_from_sensor)};
    const Point2Uncertain* local_ends[2] = {&local.first, &local.last};
    // d_max among the four endpoint-to-endpoint distances (eq. 5.54).
    int li = 0;
    int gi = 0;
    double d_max = -1.0;
    for (int i = 0; i < 2; ++i) {
      for (int j = 0; j < 2; ++j) {
        const double d = (local_ends[i]->position_m - in_sensor[j].p).norm();
        if (d > d_max) {
          d_max = d;
          li = i;
          gi = j;
        }
      }
    }
    const Eigen::Vector2d ab = g.first.position_m - g.second.position_m;
    const double l_max = ab.norm();  // the map segment's length
    const double f = d_max - l_max;
    if (f <= 0.0) return true;  // eq. 5.55
    // First-order variance of f (eqs. 5.57, 5.60).
    const Eigen::RowVector2d u =
        d_max > 0.0 ? Eigen::RowVector2d(
                          ((local_ends[li]->position_m - in_sensor[gi].p) / d_max).transpose())
                    : Eigen::RowVector2d::Zero();
    const Eigen::RowVector2d v =
        l_max > 0.0 ? Eigen::RowVector2d((ab / l_max).transpose()) : Eigen::RowVector2d::Zero();
    const Eigen::RowVector3d g_sensor = -u * in_sensor[gi].J_p_sensor;
    const Eigen::RowVector3d g_pose = g_sensor * frame.J_sensor_robot;
    const Eigen::RowVector3d g_mount = g_sensor * frame.J_sensor_mount;
    Eigen::RowVector2d g_map[2] = {-v, v};  // -d l / d a, -d l / d b
    g_map[gi] += -u * in_sensor[gi].J_p_point;
    const Eigen::RowVector2d g_local = u;
    const double variance = (g_pose * world_from_robot.covariance).dot(g_pose) +
                            (g_mount * view.robot_from_sensor_covariance).dot(g_mount) +
                            (g_map[0] * map_ends[0]->covariance).dot(g_map[0]) +
                            (g_map[1] * map_ends[1]->covariance).dot(g_map[1]) +
                            (g_local * local_ends[li]->covariance).dot(g_local);
    return f * f <= equality_gate_ * variance;  // eqs. 5.58-5.59
  };

  for (const ObservedSegment& local : observed_segments) {  // Table 5.4: conjunction
    bool any = false;
    for (const auto& g : global) {
      if (contained(local, g)) {
        any = true;
        break;
      }
    }
    if (!any) return false;
  }
  return true;
}

}  // namespace pavilion::core
