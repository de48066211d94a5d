#pragma once

// The estimator seam of the robot stack (nav::Navigator): what turns a robot's
// encoder readings and scans into a pose estimate. Today the EKF pose tracking
// of thesis §4.4 (EkfPoseEstimator); global localization (chapter 5) next.

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/odometry/diff_drive.h"
#include "core/types/sensor_data.h"

namespace pavilion::nav {

// What one estimation cycle did (a localization cycle: thesis Fig. 4.2).
struct EstimatorCycle {
  int predictions = 0;   // visible map features
  int observations = 0;  // extracted features
  int matched_lines = 0;
  int matched_beacons = 0;
  int matched_other = 0;
  bool lost = false;  // the estimator declares itself lost
};

class PoseEstimator {
 public:
  virtual ~PoseEstimator() = default;
  // One tick's readings in time order. Returns the cycle when an estimation
  // cycle completed in this tick, none otherwise (odometry only).
  virtual std::optional<EstimatorCycle> Update(
      std::span<const core::EncoderReading> encoders,
      const std::vector<const core::LaserScan*>& scans) = 0;
  virtual const core::PoseWithCovariance& estimate() const = 0;
  // Why the estimator declares itself lost ("none" while it tracks), for events.
  virtual std::string lost_reason() const = 0;
  // While paused (the navigation near a goal, §6.3.3: "localization gets
  // deactivated") scans are not integrated and the estimator cannot go lost;
  // odometry still moves the estimate. Resuming at `now_s` restarts its lost
  // detection there.
  virtual void SetPaused(bool /*paused*/, double /*now_s*/) {}
  // The bumpers felt a collision: the pose may have jumped by more than the
  // odometry model allows.
  virtual void OnCollision() {}
};

}  // namespace pavilion::nav
