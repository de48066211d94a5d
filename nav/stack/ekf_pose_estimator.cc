#include "nav/stack/ekf_pose_estimator.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace pavilion::nav {

void EkfPoseEstimatorOptions::Validate() const {
  if (!(rate_hz > 0.0)) throw std::invalid_argument("EkfPoseEstimatorOptions.rate_hz must be > 0");
  collision.Validate("EkfPoseEstimatorOptions");
  if (!(hold_s >= 0.0 && hold_s <= 1.0)) {
    throw std::invalid_argument("EkfPoseEstimatorOptions.hold_s must be in [0, 1] s");
  }
}

EkfPoseEstimator::EkfPoseEstimator(core::RobotMap map, const EkfPoseEstimatorOptions& options)
    : options_(options), gate_(options.lasers, options.rate_hz), expected_lasers_(options.lasers) {
  options_.Validate();
  localizer_ = std::make_unique<core::Localizer>(std::move(map), options_.localizer);
  localizer_->Initialize(options_.initial_pose, options_.initial_covariance, 0.0);
}

namespace {

// Without a hold, an image waits this long for the scans begun before its
// exposure (longer than a sweep), s.
constexpr double kSweepWaitS = 0.1;

// A scan's integration stamp: its first reading's time (Localizer::AddScan).
double FirstReadingStamp(const core::LaserScan& scan) {
  return scan.stamp_s + (scan.readings.empty() ? 0.0 : scan.readings.front().time_offset_s);
}

}  // namespace

std::optional<EstimatorCycle> EkfPoseEstimator::Update(
    std::span<const core::EncoderReading> encoders,
    const std::vector<const core::LaserScan*>& scans) {
  for (const core::EncoderReading& e : encoders) localizer_->AddEncoders(e);
  NoteScanCycle();
  // Scans in the order they finished, each laser's at most rate_hz times per
  // s; with a hold, they wait with the images (IntegrateHeld).
  const bool hold = options_.hold_s > 0.0;
  std::optional<EstimatorCycle> closed;
  for (const core::LaserScan* scan : scans) {
    if (paused_) break;
    if (!gate_.Admit(*scan)) continue;
    // A tick holds one scan of each laser: a second scan of one ends it (the
    // other's was lost or refused).
    if (InTick(scan->sensor_id)) {
      if (!closed && ScanCycles() > tick_cycles_) closed = ReportCycle();
      CloseTick();  // its lasers are those that still deliver
    }
    if (tick_lasers_.empty()) {
      tick_cycles_ = ScanCycles();
      tick_resolved_ = ResolvedScans();
      tick_matches_ = localizer_->counters().matches - image_matches_;
    }
    tick_lasers_.push_back(scan->sensor_id);
    if (hold) {
      held_scans_.push_back(*scan);
    } else {
      localizer_->AddScan(*scan);
      NoteScanCycle();
    }
  }
  if (paused_) {
    images_.clear();  // not integrated while paused
    held_scans_.clear();
  } else if (!encoders.empty()) {
    // Without a hold, only images wait: for the scans begun before them.
    IntegrateHeld(encoders.back().stamp_s - (hold ? options_.hold_s : kSweepWaitS));
  }
  if (closed) return closed;
  // A cycle is a tick of the gate: each laser's scan of it integrated (or
  // refused). Two lasers whose stamps differ by their latencies still make
  // one cycle, as two with the same stamps do (Table 4.2 counts n_l per
  // cycle); the images integrated since the last one report with the next.
  if (tick_lasers_.empty() || ScanCycles() == tick_cycles_) return std::nullopt;
  if (ResolvedScans() - tick_resolved_ < static_cast<long>(tick_lasers_.size())) {
    return std::nullopt;
  }
  for (const std::string& laser : expected_lasers_) {
    if (!InTick(laser)) return std::nullopt;  // its scan of this tick is still to come
  }
  const EstimatorCycle cycle = ReportCycle();
  CloseTick();
  return cycle;
}

bool EkfPoseEstimator::InTick(const std::string& laser) const {
  return std::find(tick_lasers_.begin(), tick_lasers_.end(), laser) != tick_lasers_.end();
}

void EkfPoseEstimator::CloseTick() {
  expected_lasers_ = std::move(tick_lasers_);
  tick_lasers_.clear();
}

long EkfPoseEstimator::ScanCycles() const { return localizer_->counters().cycles - image_cycles_; }

long EkfPoseEstimator::ResolvedScans() const {
  const core::LocalizerCounters& c = localizer_->counters();
  return c.cycles + c.too_old + c.out_of_order - image_cycles_ - image_refusals_;
}

void EkfPoseEstimator::IntegrateHeld(double before_s) {
  while (true) {
    // The oldest waiting scan (two lasers' may finish out of order) or image.
    auto scan = std::min_element(held_scans_.begin(), held_scans_.end(),
                                 [](const core::LaserScan& a, const core::LaserScan& b) {
                                   return FirstReadingStamp(a) < FirstReadingStamp(b);
                                 });
    const double scan_s = scan == held_scans_.end() ? before_s : FirstReadingStamp(*scan);
    const double image_s = images_.empty() ? before_s : images_.front().stamp_s;
    if (std::min(scan_s, image_s) >= before_s) return;
    if (scan_s <= image_s) {  // lines before the edges of the same instant (§4.4.2)
      localizer_->AddScan(*scan);
      held_scans_.erase(scan);
      NoteScanCycle();
      continue;
    }
    const core::LocalizerCounters before = localizer_->counters();
    localizer_->AddImage(images_.front());
    images_.pop_front();
    const core::LocalizerCounters& after = localizer_->counters();
    image_cycles_ += after.cycles - before.cycles;
    image_refusals_ += after.too_old + after.out_of_order - before.too_old - before.out_of_order;
    image_matches_ += after.matches - before.matches;
    edge_matches_ += static_cast<int>(after.matches - before.matches);
    noted_cycles_ = after.cycles;
  }
}

void EkfPoseEstimator::NoteScanCycle() {
  const long cycles = localizer_->counters().cycles;
  if (cycles == noted_cycles_) return;
  noted_cycles_ = cycles;
  if (!IsCamera(localizer_->last_cycle().sensor_id)) scan_report_ = localizer_->last_cycle();
}

bool EkfPoseEstimator::IsCamera(const std::string& sensor_id) const {
  return std::any_of(options_.localizer.cameras.begin(), options_.localizer.cameras.end(),
                     [&](const core::CameraSensorOptions& c) { return c.id == sensor_id; });
}

void EkfPoseEstimator::AddImages(const std::vector<const core::CameraImage*>& images) {
  if (paused_) return;
  for (const core::CameraImage* image : images) {
    if (IsCamera(image->sensor_id)) images_.push_back(*image);
  }
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
    } else if (m.type == core::ObservationType::kVerticalEdge) {
      ++c.matched_edges;
    } else {
      ++c.matched_other;
    }
  }
  return c;
}

EstimatorCycle EkfPoseEstimator::ReportCycle() {
  EstimatorCycle c = CycleFromReport(scan_report_);
  // Batches before the last one of this tick: their matches count as lines
  // (lasers give lines and beacons; the last report says how many of each).
  const long matched = localizer_->counters().matches - image_matches_ - tick_matches_;
  c.matched_lines += static_cast<int>(
      std::max(0L, matched - (c.matched_lines + c.matched_beacons + c.matched_other)));
  c.matched_edges = edge_matches_;
  edge_matches_ = 0;
  c.lost = localizer_->status().state == core::LocalizationState::kLost;
  c.mode = c.lost ? LocalizationMode::kLost : LocalizationMode::kLocalized;
  c.hypotheses = c.lost ? 0 : 1;
  return c;
}

void EkfPoseEstimator::OnContact(const BumperContact& contact) {
  localizer_->AddPoseUncertainty(options_.collision.Covariance(contact));
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
