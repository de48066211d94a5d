#include "core/localization/global/location_estimate.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <optional>
#include <stdexcept>

#include "core/localization/matching.h"

namespace pavilion::core {
namespace {

// Information below this fraction of the largest eigenvalue counts as zero:
// grad h^T grad h singular (eq. 5.68).
constexpr double kSingularRatio = 1e-12;

// The heading that aligns the local map with the map (see EstimateLocation).
std::optional<double> StartHeading(const LocalMap& local, const RobotMap& map,
                                   std::span<const Pairing> support) {
  double sum_cos = 0.0;
  double sum_sin = 0.0;
  int lines = 0;
  const Pairing* points[2] = {nullptr, nullptr};
  int point_count = 0;
  for (const Pairing& p : support) {
    if (p.star) continue;
    const ConstraintFeature& l = local.features[static_cast<std::size_t>(p.local)].geometry;
    const ConstraintFeature g = MapConstraintFeature(map, p.feature.type, p.feature.index);
    if (l.is_line) {
      const double theta = NormalizeAngle(g.line.alpha_rad - l.line.alpha_rad);
      sum_cos += std::cos(theta);
      sum_sin += std::sin(theta);
      ++lines;
    } else if (point_count < 2) {
      points[point_count++] = &p;
    }
  }
  if (lines > 0) return std::atan2(sum_sin, sum_cos);
  if (point_count < 2) return std::nullopt;
  const auto& l0 = local.features[static_cast<std::size_t>(points[0]->local)].geometry.point;
  const auto& l1 = local.features[static_cast<std::size_t>(points[1]->local)].geometry.point;
  const ConstraintFeature g0 =
      MapConstraintFeature(map, points[0]->feature.type, points[0]->feature.index);
  const ConstraintFeature g1 =
      MapConstraintFeature(map, points[1]->feature.type, points[1]->feature.index);
  const Eigen::Vector2d dl = l1.position_m - l0.position_m;
  const Eigen::Vector2d dg = g1.point.position_m - g0.point.position_m;
  if (dl.norm() <= 0.0 || dg.norm() <= 0.0) return std::nullopt;
  return NormalizeAngle(std::atan2(dg.y(), dg.x()) - std::atan2(dl.y(), dl.x()));
}

// The position given the heading: weighted linear least squares.
std::optional<Eigen::Vector2d> StartPosition(const LocalMap& local, const RobotMap& map,
                                             std::span<const Pairing> support, double theta) {
  Eigen::Matrix2d a = Eigen::Matrix2d::Zero();
  Eigen::Vector2d b = Eigen::Vector2d::Zero();
  const Eigen::Matrix2d rotation = Eigen::Rotation2Dd(theta).toRotationMatrix();
  for (const Pairing& p : support) {
    if (p.star) continue;
    const ConstraintFeature& l = local.features[static_cast<std::size_t>(p.local)].geometry;
    const ConstraintFeature g = MapConstraintFeature(map, p.feature.type, p.feature.index);
    if (l.is_line) {  // n_g . t = r_g - r_l
      const Eigen::Vector2d n = g.line.normal();
      const double w = 1.0 / std::max(l.line.covariance(1, 1) + g.line.covariance(1, 1), 1e-12);
      a += w * n * n.transpose();
      b += w * n * (g.line.r_m - l.line.r_m);
    } else {  // t = p_g - R p_l
      const Eigen::Vector2d t = g.point.position_m - rotation * l.point.position_m;
      const double w =
          1.0 / std::max(l.point.covariance.trace() + g.point.covariance.trace(), 1e-12);
      a += w * Eigen::Matrix2d::Identity();
      b += w * t;
    }
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(a);
  if (!(eig.eigenvalues().minCoeff() > kSingularRatio * eig.eigenvalues().maxCoeff())) {
    return std::nullopt;
  }
  return a.ldlt().solve(b);
}

// One pass over the pairings at `pose`: the normal equations of eq. 5.67.
double Accumulate(const MeasurementPredictor& predictor, const LocalMap& local,
                  std::span<const Pairing> support, const Pose2& pose, Eigen::Matrix3d* info,
                  Eigen::Vector3d* gradient) {
  info->setZero();
  gradient->setZero();
  double joint = 0.0;
  const PoseWithCovariance at{pose, Eigen::Matrix3d::Zero()};
  for (const Pairing& p : support) {
    if (p.star) continue;
    const LocalFeature& l = local.features[static_cast<std::size_t>(p.local)];
    const PredictedMeasurement prediction =
        predictor.Predict(p.feature, l.observation.type, at, l.view);
    const Innovation innovation = ComputeInnovation(prediction, l.observation);
    const int n = innovation.dimension;
    const Eigen::MatrixXd h = prediction.J_z_pose.topRows(n);
    const Eigen::MatrixXd s_inv = innovation.S.topLeftCorner(n, n).inverse();
    *info += h.transpose() * s_inv * h;
    *gradient += h.transpose() * s_inv * innovation.v.head(n);
    joint += innovation.nis;
  }
  return joint;
}

}  // namespace

void LocationEstimateOptions::Validate() const {
  if (max_iterations < 1) throw std::invalid_argument("max_iterations must be >= 1");
  if (!(converged_m > 0.0)) throw std::invalid_argument("converged_m must be > 0");
  if (!(max_position_sigma_m > 0.0))
    throw std::invalid_argument("max_position_sigma_m must be > 0");
  if (!(max_heading_sigma_rad > 0.0)) {
    throw std::invalid_argument("max_heading_sigma_rad must be > 0");
  }
}

LocationEstimate EstimateLocation(const MeasurementPredictor& predictor, const LocalMap& local,
                                  std::span<const Pairing> support,
                                  const LocationEstimateOptions& options) {
  LocationEstimate result;
  const RobotMap& map = predictor.map();
  const std::optional<double> theta = StartHeading(local, map, support);
  if (!theta) return result;
  const std::optional<Eigen::Vector2d> t = StartPosition(local, map, support, *theta);
  if (!t) return result;
  Pose2 pose{t->x(), t->y(), *theta};
  Eigen::Matrix3d info;
  Eigen::Vector3d gradient;
  double joint = 0.0;
  for (int k = 0; k < options.max_iterations; ++k) {
    joint = Accumulate(predictor, local, support, pose, &info, &gradient);
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(info);
    if (!(eig.eigenvalues().minCoeff() > kSingularRatio * eig.eigenvalues().maxCoeff())) {
      return result;  // grad h^T grad h singular: location_available false
    }
    const Eigen::Vector3d step = info.ldlt().solve(gradient);
    pose =
        Pose2{pose.x_m + step.x(), pose.y_m + step.y(), NormalizeAngle(pose.theta_rad + step.z())};
    if (step.cwiseAbs().maxCoeff() < options.converged_m) break;
  }
  joint = Accumulate(predictor, local, support, pose, &info, &gradient);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(info);
  if (!(eig.eigenvalues().minCoeff() > kSingularRatio * eig.eigenvalues().maxCoeff()))
    return result;
  Eigen::Matrix3d covariance = info.inverse();
  covariance = 0.5 * (covariance + covariance.transpose());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> position(covariance.topLeftCorner<2, 2>());
  result.location = PoseWithCovariance{pose, covariance};
  result.joint_mahalanobis = joint;
  result.available =
      std::sqrt(std::max(position.eigenvalues().maxCoeff(), 0.0)) <= options.max_position_sigma_m &&
      std::sqrt(std::max(covariance(2, 2), 0.0)) <= options.max_heading_sigma_rad;
  return result;
}

}  // namespace pavilion::core
