#pragma once

// Monte Carlo localization (core/localization/mcl/monte_carlo_localizer.h) as
// the robot stack's estimator: the baseline from outside the thesis that runs
// in shadow beside the feature-based localization on the same sensor data.

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "core/localization/encoder_odometry.h"
#include "core/localization/mcl/monte_carlo_localizer.h"
#include "nav/stack/pose_estimator.h"

namespace pavilion::nav {

struct MclPoseEstimatorOptions {
  core::MonteCarloOptions mcl;
  std::vector<std::string> lasers;  // lasers whose scans are used; empty: every laser
  // true: particles uniform over the map's free space (global localization);
  // false: a Gaussian cloud N(initial_pose, initial_covariance).
  bool global_start = false;
  core::Pose2 initial_pose;  // the estimate at time 0 when !global_start
  // Covariance of the initial cloud (x m, y m, theta rad); symmetric positive
  // semi-definite. Chosen: 0.1 m and 0.1 rad (1 sigma), a hand-placed start.
  Eigen::Matrix3d initial_covariance = Eigen::Vector3d(0.01, 0.01, 0.01).asDiagonal();

  void Validate() const;  // throws std::invalid_argument naming the field
};

class MclPoseEstimator : public PoseEstimator {
 public:
  MclPoseEstimator(core::RobotMap map, const core::EncoderOdometryOptions& odometry,
                   const MclPoseEstimatorOptions& options);
  // Encoders first, then each used laser's scans (while not paused). A cycle is
  // returned when at least one sensor update happened: observations = beams
  // scored, predictions and matches 0 (MCL matches no features), lost =
  // !converged().
  std::optional<EstimatorCycle> Update(std::span<const core::EncoderReading> encoders,
                                       const std::vector<const core::LaserScan*>& scans) override;
  const core::PoseWithCovariance& estimate() const override { return mcl_->estimate(); }
  // "not_converged" while the particle set is not converged, else "none".
  std::string lost_reason() const override;
  void SetPaused(bool paused, double now_s) override;
  bool paused() const { return paused_; }
  const core::MonteCarloLocalizer& localizer() const { return *mcl_; }

 private:
  bool Uses(const core::LaserScan& scan) const;

  std::unique_ptr<core::MonteCarloLocalizer> mcl_;
  MclPoseEstimatorOptions options_;
  bool paused_ = false;
};

}  // namespace pavilion::nav
