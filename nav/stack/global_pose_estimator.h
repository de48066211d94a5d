#pragma once

// Global localization (thesis chapter 5, core/localization/global/) as the
// robot stack's estimator: the framework of Fig. 5.17 — generation when lost,
// track splitting while not localized, the chapter-4 EKF while localized —
// on each laser's scans at most `rate_hz` times per second.

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/localization/global/global_localizer.h"
#include "nav/stack/pose_estimator.h"
#include "nav/stack/scan_rate_gate.h"

namespace pavilion::nav {

struct GlobalPoseEstimatorOptions {
  core::GlobalLocalizerOptions localizer;
  double rate_hz = 2.0;             // localization cycles per laser and second, > 0
  std::vector<std::string> lasers;  // lasers whose scans are used
  // The start: a known pose with its covariance, or none (`initial: unknown`:
  // lost until the first generation).
  std::optional<core::PoseWithCovariance> initial;
  // Added to the pose covariance for what the bumpers feel.
  CollisionNoiseOptions collision;

  void Validate() const;  // throws std::invalid_argument naming the field
};

class GlobalPoseEstimator : public PoseEstimator {
 public:
  GlobalPoseEstimator(core::RobotMap map, const GlobalPoseEstimatorOptions& options);
  std::optional<EstimatorCycle> Update(std::span<const core::EncoderReading> encoders,
                                       const std::vector<const core::LaserScan*>& scans) override;
  const core::PoseWithCovariance& estimate() const override { return estimate_; }
  std::string lost_reason() const override;
  LocalizationMode mode() const override;
  std::vector<LocationHypothesis> hypotheses() const override;
  std::size_t hypothesis_count() const override { return localizer_->Hypotheses().size(); }
  void SetPaused(bool paused, double now_s) override;
  void OnContact(const BumperContact& contact) override;
  std::vector<std::pair<std::string, std::int64_t>> counters() const override;
  const core::GlobalLocalizer& localizer() const { return *localizer_; }

 private:
  EstimatorCycle ReportCycle() const;
  // Adds what the tracker's batches since `before` paired to tracked_.
  void NoteTrackerBatches(const core::LocalizerCounters& before);

  std::unique_ptr<core::GlobalLocalizer> localizer_;
  GlobalPoseEstimatorOptions options_;
  ScanRateGate gate_;
  core::PoseWithCovariance estimate_;
  long last_cycles_ = 0;
  long last_losses_ = 0;
  bool reporting_loss_ = false;  // the last cycle reports a loss already followed by a generation
  bool paused_ = false;
  // The tracker's batches since the last reported cycle, summed: a cycle is
  // one tick's scans of every laser (Table 4.2 counts n_l per cycle), and
  // reporting the last batch alone dropped the front laser's pairings.
  EstimatorCycle tracked_;
};

}  // namespace pavilion::nav
