#pragma once

// Synthetic maps, observations and encoder streams for the EKF localization
// tests and benchmark: no simulator, only the measurement models.

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "core/features/uncertain_geometry.h"
#include "core/localization/observation.h"
#include "core/map/robot_map.h"
#include "core/odometry/diff_drive.h"
#include "core/random/random_stream.h"
#include "core/types/pose2.h"
#include "core/types/sensor_data.h"

namespace pavilion::testing {

// A map line through the points a and b (map frame), visible from `seen_from`
// (eq. B.4: n . seen_from < r), with covariance diag(sigma_alpha^2, sigma_r^2).
inline core::MapLine MapLineThrough(const std::string& id, const Eigen::Vector2d& a,
                                    const Eigen::Vector2d& b, const Eigen::Vector2d& seen_from,
                                    double sigma_alpha_rad = 0.0, double sigma_r_m = 0.0) {
  const Eigen::Vector2d t = (b - a).normalized();
  core::Line line;
  line.alpha_rad = std::atan2(t.x(), -t.y());
  line.r_m = line.normal().dot(a);
  if (line.normal().dot(seen_from) >= line.r_m) {
    line.alpha_rad += std::numbers::pi;
    line.r_m = -line.r_m;
  }
  line.alpha_rad = core::NormalizeAngle(line.alpha_rad);
  line.covariance =
      Eigen::Vector2d(sigma_alpha_rad * sigma_alpha_rad, sigma_r_m * sigma_r_m).asDiagonal();
  return {id, line};
}

// A rectangular room [x0, x1] x [y0, y1] of four infinite lines, seen from inside.
inline core::RobotMap RectangularRoom(double x0, double y0, double x1, double y1,
                                      double sigma_r_m = 0.0) {
  core::RobotMap map;
  map.name = "room";
  const Eigen::Vector2d c(0.5 * (x0 + x1), 0.5 * (y0 + y1));
  const Eigen::Vector2d p[4] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  const char* names[4] = {"south", "east", "north", "west"};
  for (int i = 0; i < 4; ++i) {
    map.lines.push_back(MapLineThrough(names[i], p[i], p[(i + 1) % 4], c, 0.0, sigma_r_m));
  }
  return map;
}

// Samples x ~ N(0, C) for a symmetric positive semi-definite 2x2 or 3x3 C.
template <int N>
Eigen::Matrix<double, N, 1> SampleGaussian(const Eigen::Matrix<double, N, N>& C,
                                           core::RandomStream& rng) {
  const Eigen::LDLT<Eigen::Matrix<double, N, N>> ldlt(C);
  Eigen::Matrix<double, N, 1> w;
  for (int i = 0; i < N; ++i) w[i] = rng.Normal() * std::sqrt(std::max(ldlt.vectorD()[i], 0.0));
  return ldlt.transpositionsP().transpose() * (ldlt.matrixL() * w);
}

// The observation of map line `line` from a sensor at `world_from_sensor`: its
// true (alpha, r) in the sensor frame (eqs. B.22-B.23), with covariance R and,
// when `rng` is given, noise drawn from R. Brought to r >= 0 like an
// extracted line.
inline core::Observation ObserveLine(const core::Line& line, const core::Pose2& world_from_sensor,
                                     const Eigen::Matrix2d& R, core::RandomStream* rng = nullptr) {
  core::Line local = core::LineInChild(line, world_from_sensor);
  core::Observation o;
  o.type = core::ObservationType::kLine;
  o.z = {local.alpha_rad, local.r_m};
  if (rng != nullptr) o.z += SampleGaussian<2>(R, *rng);
  o.covariance = R;
  if (o.z[1] < 0.0) {
    o.z = {o.z[0] + std::numbers::pi, -o.z[1]};
    o.covariance(0, 1) = -o.covariance(0, 1);
    o.covariance(1, 0) = -o.covariance(1, 0);
  }
  o.z[0] = core::NormalizeAngle(o.z[0]);
  return o;
}

// Observations of every map line with r in (0, max_range_m] from the sensor.
inline std::vector<core::Observation> ObserveVisibleLines(const core::RobotMap& map,
                                                          const core::Pose2& world_from_sensor,
                                                          const Eigen::Matrix2d& R,
                                                          core::RandomStream* rng = nullptr,
                                                          double max_range_m = 8.0) {
  std::vector<core::Observation> out;
  for (const core::MapLine& l : map.lines) {
    const core::Line local = core::LineInChild(l.line, world_from_sensor);
    if (local.r_m > 0.0 && local.r_m <= max_range_m) {
      out.push_back(ObserveLine(l.line, world_from_sensor, R, rng));
    }
  }
  return out;
}

// A typical extracted line's covariance: sigma_alpha, sigma_r, uncorrelated.
inline Eigen::Matrix2d LineCovariance(double sigma_alpha_rad, double sigma_r_m) {
  return Eigen::Vector2d(sigma_alpha_rad * sigma_alpha_rad, sigma_r_m * sigma_r_m).asDiagonal();
}

// A 360-degree sensor at the robot origin.
inline core::SensorView CentredView(double perception_radius_m = 8.0) {
  core::SensorView view;
  view.perception_radius_m = perception_radius_m;
  return view;
}

// Cumulative encoder counts: each call adds a step of whole ticks.
class EncoderStream {
 public:
  EncoderStream(int ticks_per_revolution, double left_radius_m, double right_radius_m)
      : ticks_per_revolution_(ticks_per_revolution),
        left_radius_m_(left_radius_m),
        right_radius_m_(right_radius_m) {}

  // The reading after `left`, `right` more ticks at time `stamp_s`.
  core::EncoderReading Step(double stamp_s, std::int64_t left, std::int64_t right) {
    left_ += left;
    right_ += right;
    return {stamp_s, left_, right_, ticks_per_revolution_};
  }
  // The wheel travel of `left`, `right` ticks.
  core::WheelTravel Travel(std::int64_t left, std::int64_t right) const {
    const double per_tick = 2.0 * std::numbers::pi / ticks_per_revolution_;
    return {static_cast<double>(left) * per_tick * left_radius_m_,
            static_cast<double>(right) * per_tick * right_radius_m_};
  }

 private:
  int ticks_per_revolution_;
  double left_radius_m_;
  double right_radius_m_;
  std::int64_t left_ = 0;
  std::int64_t right_ = 0;
};

// Normalized estimation error squared e^T P^-1 e of a pose estimate.
inline double Nees(const core::PoseWithCovariance& estimate, const core::Pose2& truth) {
  const Eigen::Vector3d e(estimate.pose.x_m - truth.x_m, estimate.pose.y_m - truth.y_m,
                          core::NormalizeAngle(estimate.pose.theta_rad - truth.theta_rad));
  return e.dot(estimate.covariance.ldlt().solve(e));
}

}  // namespace pavilion::testing
