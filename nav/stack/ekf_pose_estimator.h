#pragma once

// EKF pose tracking (thesis §4.4, core/localization/localizer.h) as the robot
// stack's estimator: the encoders at their own rate, each laser's scans at
// most `rate_hz` times per second (the thesis localized at 2 Hz, §4.5.2), and
// the vertical edges of the cameras in `localizer.cameras` after the lines
// (§4.4.2), each image at its own stamp. A cycle (a row of localization.csv)
// is a tick of that rate: one scan of each laser, whether their stamps agree
// or differ by the lasers' latencies.

#include <Eigen/Core>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include "core/localization/localizer.h"
#include "nav/stack/pose_estimator.h"
#include "nav/stack/scan_rate_gate.h"

namespace pavilion::nav {

struct EkfPoseEstimatorOptions {
  core::LocalizerOptions localizer;
  double rate_hz = 2.0;             // localization cycles per second, > 0
  std::vector<std::string> lasers;  // lasers whose scans are used, in the robot's order
  core::Pose2 initial_pose;         // the estimate at time 0
  Eigen::Matrix3d initial_covariance = Eigen::Matrix3d::Identity() * 1e-4;
  // Added to the pose covariance for what the bumpers feel.
  CollisionNoiseOptions collision;
  // > 0: scans and camera images wait this long after their stamps and are
  // then integrated in time-stamp order (the localizer integrates in order,
  // §4.4.3, and an image arrives the grabber's delay after its exposure: set
  // it longer than that delay plus a sweep); the correction is carried
  // forward to the present by the odometry buffer. 0: scans are integrated
  // as they arrive, images as soon as no earlier scan can come. s, [0, 1].
  double hold_s = 0.0;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// A cycle's counts from the EKF's report of its latest batch: predictions,
// observations and the matches by type.
EstimatorCycle CycleFromReport(const core::CycleReport& report);

// "none", "no_match_timeout", "repeated_gate_failures", "uncertainty_too_large".
const char* LostReasonName(core::LostReason reason);

class EkfPoseEstimator : public PoseEstimator {
 public:
  EkfPoseEstimator(core::RobotMap map, const EkfPoseEstimatorOptions& options);
  std::optional<EstimatorCycle> Update(std::span<const core::EncoderReading> encoders,
                                       const std::vector<const core::LaserScan*>& scans) override;
  void AddImages(const std::vector<const core::CameraImage*>& images) override;
  const core::PoseWithCovariance& estimate() const override { return localizer_->estimate(); }
  std::string lost_reason() const override;
  void SetPaused(bool paused, double now_s) override;
  void OnContact(const BumperContact& contact) override;
  bool paused() const { return paused_; }
  const core::Localizer& localizer() const { return *localizer_; }

 private:
  // The open tick's cycle: the latest laser batch's counts, and the lines of
  // the tick's earlier batches (the scan matches beyond tick_matches_).
  EstimatorCycle ReportCycle();
  // Ends the open tick: its lasers become the ones the next waits for.
  void CloseTick();
  bool InTick(const std::string& laser) const;  // a scan of `laser` was admitted in the open tick
  long ScanCycles() const;                      // the localizer's cycles that were the lasers'
  long ResolvedScans() const;  // admitted scans integrated or refused (too old, out of order)
  // Integrates the waiting scans and images stamped before `before_s` in
  // time-stamp order (the localizer refuses a batch older than one it has
  // integrated, §4.4.3: an image arrives a grabber's delay late).
  void IntegrateHeld(double before_s);
  // Keeps the localizer's latest report when a laser's batch made it.
  void NoteScanCycle();
  bool IsCamera(const std::string& sensor_id) const;

  std::unique_ptr<core::Localizer> localizer_;
  EkfPoseEstimatorOptions options_;
  ScanRateGate gate_;
  // The lasers a tick waits for: those of the last tick (at first, all). A
  // laser that stops delivering leaves it when its tick is ended by the next.
  std::vector<std::string> expected_lasers_;
  // The open tick: the lasers admitted in it, and the scan cycles, resolved
  // scans and scan matches before its first.
  std::vector<std::string> tick_lasers_;
  long tick_cycles_ = 0;
  long tick_resolved_ = 0;
  long tick_matches_ = 0;
  bool paused_ = false;
  std::deque<core::CameraImage> images_;     // waiting, in stamp order
  std::vector<core::LaserScan> held_scans_;  // admitted, waiting with the images
  long image_cycles_ = 0;                    // the localizer's cycles and matches that were images'
  long image_matches_ = 0;
  long image_refusals_ = 0;  // images the localizer refused (too old, out of order)
  int edge_matches_ = 0;     // matched vertical edges since the last reported cycle
  long noted_cycles_ = 0;
  core::CycleReport scan_report_;  // the latest laser batch's
};

}  // namespace pavilion::nav
