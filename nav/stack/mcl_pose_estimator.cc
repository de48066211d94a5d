#include "nav/stack/mcl_pose_estimator.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

namespace pavilion::nav {
namespace {
// Symmetry and semi-definiteness of the initial covariance up to rounding.
constexpr double kCovarianceTolerance = 1e-12;
}  // namespace

void MclPoseEstimatorOptions::Validate() const {
  mcl.Validate();
  const bool finite = initial_covariance.allFinite() && std::isfinite(initial_pose.x_m) &&
                      std::isfinite(initial_pose.y_m) && std::isfinite(initial_pose.theta_rad);
  const bool symmetric =
      finite && (initial_covariance - initial_covariance.transpose()).cwiseAbs().maxCoeff() <=
                    kCovarianceTolerance;
  if (!symmetric ||
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(initial_covariance).eigenvalues().minCoeff() <
          -kCovarianceTolerance) {
    throw std::invalid_argument(
        "MclPoseEstimatorOptions.initial_covariance must be finite, symmetric and positive "
        "semi-definite (and initial_pose finite)");
  }
}

MclPoseEstimator::MclPoseEstimator(core::RobotMap map, const core::EncoderOdometryOptions& odometry,
                                   const MclPoseEstimatorOptions& options)
    : options_(options) {
  options_.Validate();
  mcl_ = std::make_unique<core::MonteCarloLocalizer>(std::move(map), odometry, options_.mcl);
  if (options_.global_start) {
    mcl_->InitializeGlobal();
  } else {
    mcl_->Initialize({options_.initial_pose, options_.initial_covariance});
  }
}

bool MclPoseEstimator::Uses(const core::LaserScan& scan) const {
  return options_.lasers.empty() || std::find(options_.lasers.begin(), options_.lasers.end(),
                                              scan.sensor_id) != options_.lasers.end();
}

std::optional<EstimatorCycle> MclPoseEstimator::Update(
    std::span<const core::EncoderReading> encoders,
    const std::vector<const core::LaserScan*>& scans) {
  for (const core::EncoderReading& e : encoders) mcl_->AddEncoders(e);
  if (paused_) return std::nullopt;
  int beams = 0;
  bool updated = false;
  for (const core::LaserScan* scan : scans) {
    if (!Uses(*scan) || !mcl_->AddScan(*scan)) continue;
    updated = true;
    beams += mcl_->last_beams();
  }
  if (!updated) return std::nullopt;
  EstimatorCycle cycle;
  cycle.observations = beams;
  cycle.lost = !mcl_->converged();
  return cycle;
}

std::string MclPoseEstimator::lost_reason() const {
  return mcl_->converged() ? "none" : "not_converged";
}

void MclPoseEstimator::SetPaused(bool paused, double /*now_s*/) { paused_ = paused; }

}  // namespace pavilion::nav
