#include "nav/stack/ekf_pose_estimator.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace pavilion::nav {

void EkfPoseEstimatorOptions::Validate() const {
  if (!(rate_hz > 0.0)) throw std::invalid_argument("EkfPoseEstimatorOptions.rate_hz must be > 0");
  if (!(collision_sigma_m >= 0.0) || !(collision_sigma_rad >= 0.0)) {
    throw std::invalid_argument("EkfPoseEstimatorOptions.collision_sigma_m must be >= 0");
  }
}

EkfPoseEstimator::EkfPoseEstimator(core::RobotMap map, const EkfPoseEstimatorOptions& options)
    : options_(options), gate_(options.lasers, options.rate_hz) {
  options_.Validate();
  localizer_ = std::make_unique<core::Localizer>(std::move(map), options_.localizer);
  localizer_->Initialize(options_.initial_pose, options_.initial_covariance, 0.0);
}

std::optional<EstimatorCycle> EkfPoseEstimator::Update(
    std::span<const core::EncoderReading> encoders,
    const std::vector<const core::LaserScan*>& scans) {
  const long matches_before = localizer_->counters().matches;
  for (const core::EncoderReading& e : encoders) localizer_->AddEncoders(e);
  // Scans in the order they finished; each laser's at most rate_hz times per s.
  for (const core::LaserScan* scan : scans) {
    if (paused_) break;
    if (gate_.Admit(*scan)) localizer_->AddScan(*scan);
  }
  const long cycles = localizer_->counters().cycles;
  if (cycles == last_cycles_) return std::nullopt;
  last_cycles_ = cycles;
  return ReportCycle(matches_before);
}

EstimatorCycle CycleFromReport(const core::CycleReport& report) {
  EstimatorCycle c;
  c.predictions = report.predictions;
  c.observations = report.observations;
  for (const core::FeatureMatch& m : report.matches) {
    if (m.type == core::ObservationType::kLine) {
      ++c.matched_lines;
    } else if (m.type == core::ObservationType::kBeacon) {
      ++c.matched_beacons;
    } else {
      ++c.matched_other;
    }
  }
  return c;
}

Eigen::Matrix3d CollisionCovariance(double sigma_m, double sigma_rad) {
  return Eigen::Vector3d(sigma_m * sigma_m, sigma_m * sigma_m, sigma_rad * sigma_rad).asDiagonal();
}

EstimatorCycle EkfPoseEstimator::ReportCycle(long matches_before) const {
  EstimatorCycle c = CycleFromReport(localizer_->last_cycle());
  // Batches before the last one of this tick: their matches count as lines
  // (lasers give lines and beacons; the last report says how many of each).
  const long matched = localizer_->counters().matches - matches_before;
  c.matched_lines += static_cast<int>(
      std::max(0L, matched - (c.matched_lines + c.matched_beacons + c.matched_other)));
  c.lost = localizer_->status().state == core::LocalizationState::kLost;
  c.mode = c.lost ? LocalizationMode::kLost : LocalizationMode::kLocalized;
  c.hypotheses = c.lost ? 0 : 1;
  return c;
}

void EkfPoseEstimator::OnCollision() {
  localizer_->AddPoseUncertainty(
      CollisionCovariance(options_.collision_sigma_m, options_.collision_sigma_rad));
}

void EkfPoseEstimator::SetPaused(bool paused, double now_s) {
  if (paused_ != paused) localizer_->SuspendLostDetection(paused, now_s);
  paused_ = paused;
}

std::string EkfPoseEstimator::lost_reason() const {
  return LostReasonName(localizer_->status().reason);
}

const char* LostReasonName(core::LostReason reason) {
  switch (reason) {
    case core::LostReason::kNone:
      return "none";
    case core::LostReason::kNoMatchTimeout:
      return "no_match_timeout";
    case core::LostReason::kRepeatedGateFailures:
      return "repeated_gate_failures";
    case core::LostReason::kUncertaintyTooLarge:
      return "uncertainty_too_large";
  }
  return "unknown";
}

}  // namespace pavilion::nav
