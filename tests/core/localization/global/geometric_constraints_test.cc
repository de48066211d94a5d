// The location independent constraints of global localization (thesis
// §5.3.1): unary (Table 5.1) and binary (Table 5.2) tests against
// hand-computed cases, and the variances of eqs. 5.34-5.35 and 5.43 against
// a finite-difference propagation.
#include "core/localization/global/geometric_constraints.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <tuple>

#include "core/math/chi_square.h"

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;
constexpr double kStep = 1e-6;  // central-difference step (m, rad)
// Central differences of smooth functions of order 1: O(h^2) + eps/h ~ 1e-10.
constexpr double kVarianceRelTol = 1e-6;

double Gate() { return ChiSquareQuantile(0.95, 1); }  // 3.841

Point2Uncertain P(double x, double y, double sx, double sy) {
  return {{x, y}, Eigen::Vector2d(sx * sx, sy * sy).asDiagonal()};
}

ConstraintFeature SegmentFeature(double length_m, double variance_m2) {
  ConstraintFeature f;
  f.finite = true;
  f.length_m = length_m;
  f.length_variance_m2 = variance_m2;
  return f;
}

ConstraintFeature LineFeature(double alpha_rad, double r_m, double sigma_alpha_rad,
                              double sigma_r_m) {
  ConstraintFeature f;
  f.line.alpha_rad = alpha_rad;
  f.line.r_m = r_m;
  f.line.covariance =
      Eigen::Vector2d(sigma_alpha_rad * sigma_alpha_rad, sigma_r_m * sigma_r_m).asDiagonal();
  return f;
}

ConstraintFeature PointFeature(const Point2Uncertain& p) {
  ConstraintFeature f;
  f.is_line = false;
  f.point = p;
  return f;
}

// Eqs. 5.15-5.16: a 3-4-5 segment, u = (0.6, 0.8); both endpoints
// diag(0.01^2, 0.02^2): sigma^2 = 2 (0.36e-4 + 0.64 * 4e-4) = 5.84e-4.
TEST(GeometricConstraintsTest, SegmentLengthAndVariance) {
  double length = 0.0;
  double variance = 0.0;
  SegmentLength(P(1, 1, 0.01, 0.02), P(4, 5, 0.01, 0.02), &length, &variance);
  EXPECT_NEAR(length, 5.0, 1e-12);
  EXPECT_NEAR(variance, 5.84e-4, 1e-12);
}

// Table 5.1 with a 3 m map segment (endpoints sigma 1 cm along it: sigma^2 = 2e-4).
TEST(GeometricConstraintsTest, UnarySegmentLengths) {
  RobotMap map;
  MapSegment s;
  s.id = "wall";
  s.first_endpoint = P(0, 0, 0.01, 0.05);
  s.second_endpoint = P(3, 0, 0.01, 0.05);
  map.segments.push_back(s);
  const ConstraintFeature global = MapConstraintFeature(map, MapFeatureType::kSegment, 0);
  ASSERT_TRUE(global.finite);
  EXPECT_NEAR(global.length_m, 3.0, 1e-12);
  EXPECT_NEAR(global.length_variance_m2, 2e-4, 1e-12);
  // Local 3.02 m, sigma^2 2e-4: D^2 = 0.02^2 / 4e-4 = 1 < 3.84, equal: passes.
  EXPECT_TRUE(SatisfiesUnaryConstraint(SegmentFeature(3.02, 2e-4), global, Gate()));
  // Local 3.05 m: D^2 = 0.05^2 / 4e-4 = 6.25, not equal, and 3.05 > 3: fails.
  EXPECT_FALSE(SatisfiesUnaryConstraint(SegmentFeature(3.05, 2e-4), global, Gate()));
  EXPECT_FALSE(SatisfiesUnaryConstraint(SegmentFeature(3.5, 2e-4), global, Gate()));
  // Local 2 m: D^2 = 2500, not equal, but 2 <= 3 (eq. 5.18): passes.
  EXPECT_TRUE(SatisfiesUnaryConstraint(SegmentFeature(2.0, 2e-4), global, Gate()));
  // An infinite line (or a point) has no length: always passes, both ways.
  ConstraintFeature infinite;
  EXPECT_TRUE(SatisfiesUnaryConstraint(SegmentFeature(30.0, 1e-4), infinite, Gate()));
  EXPECT_TRUE(SatisfiesUnaryConstraint(infinite, global, Gate()));
}

// Table 5.1 for an MS-line: its longest segment (4 m of 1 m and 4 m) counts.
TEST(GeometricConstraintsTest, UnaryMultiSegmentLineUsesItsLongestSegment) {
  RobotMap map;
  MapMultiSegmentLine m;
  m.id = "ms";
  m.segments.push_back({P(0, 0, 0.01, 0.01), P(1, 0, 0.01, 0.01)});
  m.segments.push_back({P(2, 0, 0.01, 0.01), P(6, 0, 0.01, 0.01)});
  map.multi_segment_lines.push_back(m);
  const ConstraintFeature global = MapConstraintFeature(map, MapFeatureType::kMultiSegmentLine, 0);
  EXPECT_NEAR(global.length_m, 4.0, 1e-12);
  EXPECT_NEAR(global.length_variance_m2, 2e-4, 1e-12);
  // 3.9 m < 4 m passes; 4.5 m: D^2 = 0.25 / 4e-4 = 625, 4.5 > 4: fails. With
  // the sum of the pieces (5 m) or the first piece (1 m) both answers would differ.
  EXPECT_TRUE(SatisfiesUnaryConstraint(SegmentFeature(3.9, 2e-4), global, Gate()));
  EXPECT_FALSE(SatisfiesUnaryConstraint(SegmentFeature(4.5, 2e-4), global, Gate()));
}

// Eqs. 5.23-5.26: relative angles. Local 0 and 90 deg, global 17 and 107 deg:
// the same -90 deg, D^2 = 0. Sigmas 1 deg on all four: var = 4 deg^2, so
// 10 deg off gives D^2 = 100 / 4 = 25 (fails), 3 deg off 9 / 4 = 2.25 (passes).
TEST(GeometricConstraintsTest, BinaryLineLineAngle) {
  const double s = 1.0 * kDeg;
  const ConstraintFeature li = LineFeature(0.0, 2.0, s, 0.01);
  const ConstraintFeature lj = LineFeature(90 * kDeg, 3.0, s, 0.01);
  const ConstraintFeature gi = LineFeature(17 * kDeg, 5.0, s, 0.01);
  for (const auto& [offset_deg, expected_d2, passes] :
       {std::tuple{0.0, 0.0, true}, std::tuple{3.0, 2.25, true}, std::tuple{10.0, 25.0, false}}) {
    const ConstraintFeature gj = LineFeature((107 + offset_deg) * kDeg, 1.0, s, 0.01);
    const BinaryDistances d = ComputeBinaryDistances(li, lj, gi, gj, Gate());
    EXPECT_NEAR(d.angle, expected_d2, 1e-9) << offset_deg;
    EXPECT_FALSE(d.parallel);
    EXPECT_EQ(SatisfiesBinaryConstraint(li, lj, gi, gj, Gate()), passes) << offset_deg;
  }
}

// Eqs. 5.27-5.29, same normals: local r 1 and 3 (separation r_i - r_j = -2),
// global alpha 0.5 rad, r 4 and 6 (-2): D_r^2 = 0, passes. Global r 6.5
// (-2.5): sigma_r 5 cm on all four, var = 0.01, D_r^2 = 0.25 / 0.01 = 25: fails
// although the angles agree.
TEST(GeometricConstraintsTest, BinaryParallelLinesSeparation) {
  const double sa = 0.5 * kDeg;
  const ConstraintFeature li = LineFeature(0.0, 1.0, sa, 0.05);
  const ConstraintFeature lj = LineFeature(0.0, 3.0, sa, 0.05);
  const ConstraintFeature gi = LineFeature(0.5, 4.0, sa, 0.05);
  for (const auto& [r_j, expected_d2, passes] :
       {std::tuple{6.0, 0.0, true}, std::tuple{6.5, 25.0, false}}) {
    const ConstraintFeature gj = LineFeature(0.5, r_j, sa, 0.05);
    const BinaryDistances d = ComputeBinaryDistances(li, lj, gi, gj, Gate());
    EXPECT_TRUE(d.parallel);
    EXPECT_NEAR(d.angle, 0.0, 1e-12);
    EXPECT_NEAR(d.separation, expected_d2, 1e-9) << r_j;
    EXPECT_EQ(SatisfiesBinaryConstraint(li, lj, gi, gj, Gate()), passes) << r_j;
  }
}

// Antiparallel corridor walls: the robot sees y = +1 (alpha 90 deg, r 1) and
// y = -1.5 (alpha -90 deg, r 1.5): separation r_i + r_j = 2.5. The map's
// walls y = 3 (alpha 90 deg, r 3) and y = 0.5 seen from y = 1.5 (alpha -90
// deg, r -0.5): 3 - (-0.5)(-1) = 2.5, passes; a 3 m corridor (y = 0) gives
// 3, D^2 = 0.25 / (4 * 0.03^2) = 69.4, fails.
TEST(GeometricConstraintsTest, BinaryAntiparallelCorridorWalls) {
  const double sa = 0.5 * kDeg;
  const ConstraintFeature li = LineFeature(kPi / 2, 1.0, sa, 0.03);
  const ConstraintFeature lj = LineFeature(-kPi / 2, 1.5, sa, 0.03);
  const ConstraintFeature gi = LineFeature(kPi / 2, 3.0, sa, 0.03);
  for (const auto& [r_j, expected_d2, passes] :
       {std::tuple{-0.5, 0.0, true}, std::tuple{0.0, 0.25 / 0.0036, false}}) {
    const ConstraintFeature gj = LineFeature(-kPi / 2, r_j, sa, 0.03);
    const BinaryDistances d = ComputeBinaryDistances(li, lj, gi, gj, Gate());
    EXPECT_TRUE(d.parallel);
    EXPECT_NEAR(d.angle, 0.0, 1e-12);
    EXPECT_NEAR(d.separation, expected_d2, 1e-9) << r_j;
    EXPECT_EQ(SatisfiesBinaryConstraint(li, lj, gi, gj, Gate()), passes) << r_j;
  }
}

// Numerical variance of f at x with covariance C: J C J^T, J by central differences.
double PropagatedVariance(const std::function<double(const Eigen::Vector4d&)>& f,
                          const Eigen::Vector4d& x, const Eigen::Matrix4d& C) {
  Eigen::RowVector4d J;
  for (int k = 0; k < 4; ++k) {
    Eigen::Vector4d plus = x;
    Eigen::Vector4d minus = x;
    plus[k] += kStep;
    minus[k] -= kStep;
    J[k] = (f(plus) - f(minus)) / (2 * kStep);
  }
  return J * C * J.transpose();
}

// Eq. 5.30: d = x cos(alpha) + y sin(alpha) - r, signed. Local line alpha 0.2,
// r 2; point (1, 0.5): d = 0.980067 + 0.099335 - 2 = -0.920598. The global
// pair (x axis alpha 0, r 0; point at x = d_l + delta, certain) has d_g =
// d_l + delta, so D^2 = delta^2 / var_l, var_l of eqs. 5.34-5.35 checked
// against the finite-difference propagation of (alpha, r, x, y).
TEST(GeometricConstraintsTest, BinaryLinePointDistanceAndVariance) {
  ConstraintFeature line = LineFeature(0.2, 2.0, 0.01, 0.03);
  line.line.covariance(0, 1) = line.line.covariance(1, 0) = 0.5 * 0.01 * 0.03;
  Point2Uncertain p{{1.0, 0.5}, Eigen::Matrix2d::Zero()};
  p.covariance << 4e-4, 1e-4, 1e-4, 9e-4;
  const ConstraintFeature point = PointFeature(p);
  auto distance = [](const Eigen::Vector4d& v) {
    return v[2] * std::cos(v[0]) + v[3] * std::sin(v[0]) - v[1];
  };
  const Eigen::Vector4d x(0.2, 2.0, 1.0, 0.5);
  const double d_l = distance(x);
  EXPECT_NEAR(d_l, -0.920598, 1e-6);
  Eigen::Matrix4d C = Eigen::Matrix4d::Zero();
  C.topLeftCorner<2, 2>() = line.line.covariance;
  C.bottomRightCorner<2, 2>() = p.covariance;
  const double variance = PropagatedVariance(distance, x, C);
  const double delta = 0.05;
  const ConstraintFeature g_line = LineFeature(0.0, 0.0, 0.0, 0.0);
  const ConstraintFeature g_point = PointFeature({{d_l + delta, 7.0}, Eigen::Matrix2d::Zero()});
  const BinaryDistances d = ComputeBinaryDistances(line, point, g_line, g_point, Gate());
  EXPECT_NEAR(d.distance, delta * delta / variance, kVarianceRelTol * d.distance);
  // The order of the two pairings (point first) does not matter.
  const BinaryDistances swapped = ComputeBinaryDistances(point, line, g_point, g_line, Gate());
  EXPECT_NEAR(swapped.distance, d.distance, 1e-12);
  EXPECT_EQ(SatisfiesBinaryConstraint(line, point, g_line, g_point, Gate()),
            delta * delta / variance < Gate());
  // Signed: the point mirrored to the other side of the global line (d_g = -d_l) fails.
  const ConstraintFeature mirrored = PointFeature({{-d_l, 7.0}, Eigen::Matrix2d::Zero()});
  EXPECT_FALSE(SatisfiesBinaryConstraint(line, point, g_line, mirrored, Gate()));
}

// Eqs. 5.39-5.45: local points (1, 2) and (4, 6), d = 5; var of eq. 5.43
// against the finite-difference propagation; the global points 5.1 m apart
// (certain): D^2 = 0.01 / var.
TEST(GeometricConstraintsTest, BinaryPointPointDistanceAndVariance) {
  Point2Uncertain a{{1.0, 2.0}, Eigen::Matrix2d::Zero()};
  Point2Uncertain b{{4.0, 6.0}, Eigen::Matrix2d::Zero()};
  a.covariance << 4e-4, -1e-4, -1e-4, 1e-4;
  b.covariance << 1e-4, 2e-4, 2e-4, 9e-4;
  auto distance = [](const Eigen::Vector4d& v) { return std::hypot(v[2] - v[0], v[3] - v[1]); };
  Eigen::Matrix4d C = Eigen::Matrix4d::Zero();
  C.topLeftCorner<2, 2>() = a.covariance;
  C.bottomRightCorner<2, 2>() = b.covariance;
  const double variance = PropagatedVariance(distance, Eigen::Vector4d(1, 2, 4, 6), C);
  // u = (0.6, 0.8): u^T (Ca + Cb) u = 0.36 * 5e-4 + 2 * 0.48 * 1e-4 + 0.64 * 1e-3 = 9.16e-4.
  EXPECT_NEAR(variance, 9.16e-4, 1e-12);
  const ConstraintFeature la = PointFeature(a);
  const ConstraintFeature lb = PointFeature(b);
  const ConstraintFeature ga = PointFeature({{0.0, 0.0}, Eigen::Matrix2d::Zero()});
  for (const double d_g : {5.0, 5.03, 5.1}) {
    const ConstraintFeature gb = PointFeature({{0.0, d_g}, Eigen::Matrix2d::Zero()});
    const double expected = (d_g - 5.0) * (d_g - 5.0) / variance;
    const BinaryDistances d = ComputeBinaryDistances(la, lb, ga, gb, Gate());
    EXPECT_NEAR(d.distance, expected, kVarianceRelTol * expected + 1e-12) << d_g;
    EXPECT_EQ(SatisfiesBinaryConstraint(la, lb, ga, gb, Gate()), expected < Gate()) << d_g;
  }
}

// A sensor mounted at (0.3, 0.1, 90 deg): its x axis is the robot's y axis.
// The line x_s = 2 (alpha 0, r 2) is y_r = 0.1 + 2 = 2.1 (alpha 90 deg, r
// 2.1); r_r = r_s + n_r . t with d(n_r . t)/d alpha = (-1, 0) . (0.3, 0.1) =
// -0.3, so Cov = J diag(sa^2, sr^2) J^T, J = [1 0; -0.3 1]. The point (1,
// 0.5) is R (1, 0.5) + t = (-0.5, 1) + (0.3, 0.1) = (-0.2, 1.1), its
// covariance diag(a, b) rotated by 90 deg: diag(b, a). Lengths are frame invariant.
TEST(GeometricConstraintsTest, ObservationFeaturesOfAMountedSensor) {
  SensorView view;
  view.robot_from_sensor = {0.3, 0.1, kPi / 2};
  const double sa = 0.5 * kDeg;
  const double sr = 0.01;
  Observation line;
  line.type = ObservationType::kLine;
  line.z = {0.0, 2.0};
  line.covariance = Eigen::Vector2d(sa * sa, sr * sr).asDiagonal();
  line.segments.push_back({P(2, -1, 0.01, 0.01), P(2, 1, 0.01, 0.01)});
  const ConstraintFeature l = ObservationConstraintFeature(line, view);
  EXPECT_TRUE(l.is_line);
  EXPECT_NEAR(NormalizeAngle(l.line.alpha_rad - kPi / 2), 0.0, 1e-12);
  EXPECT_NEAR(l.line.r_m, 2.1, 1e-12);
  EXPECT_NEAR(l.line.covariance(0, 0), sa * sa, 1e-15);
  EXPECT_NEAR(l.line.covariance(0, 1), -0.3 * sa * sa, 1e-15);
  EXPECT_NEAR(l.line.covariance(1, 1), 0.09 * sa * sa + sr * sr, 1e-15);
  EXPECT_TRUE(l.finite);
  EXPECT_NEAR(l.length_m, 2.0, 1e-12);
  EXPECT_NEAR(l.length_variance_m2, 2e-4, 1e-15);
  Observation point;
  point.type = ObservationType::kPoint;
  point.z = {1.0, 0.5};
  point.covariance = Eigen::Vector2d(4e-4, 1e-4).asDiagonal();
  const ConstraintFeature p = ObservationConstraintFeature(point, view);
  EXPECT_FALSE(p.is_line);
  EXPECT_FALSE(p.finite);
  EXPECT_NEAR(p.point.position_m.x(), -0.2, 1e-12);
  EXPECT_NEAR(p.point.position_m.y(), 1.1, 1e-12);
  EXPECT_NEAR(p.point.covariance(0, 0), 1e-4, 1e-15);
  EXPECT_NEAR(p.point.covariance(1, 1), 4e-4, 1e-15);
  EXPECT_NEAR(p.point.covariance(0, 1), 0.0, 1e-15);
}

}  // namespace
}  // namespace pavilion::core
