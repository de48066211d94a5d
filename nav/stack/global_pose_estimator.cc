#include "nav/stack/global_pose_estimator.h"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "nav/stack/ekf_pose_estimator.h"

namespace pavilion::nav {

void GlobalPoseEstimatorOptions::Validate() const {
  if (!(rate_hz > 0.0))
    throw std::invalid_argument("GlobalPoseEstimatorOptions.rate_hz must be > 0");
  collision.Validate("GlobalPoseEstimatorOptions");
  localizer.Validate();
}

GlobalPoseEstimator::GlobalPoseEstimator(core::RobotMap map,
                                         const GlobalPoseEstimatorOptions& options)
    : options_(options), gate_(options.lasers, options.rate_hz) {
  options_.Validate();
  localizer_ = std::make_unique<core::GlobalLocalizer>(std::move(map), options_.localizer);
  if (options_.initial) {
    localizer_->Initialize(options_.initial->pose, options_.initial->covariance, 0.0);
  }
  estimate_ = localizer_->Estimate();
}

std::optional<EstimatorCycle> GlobalPoseEstimator::Update(
    std::span<const core::EncoderReading> encoders,
    const std::vector<const core::LaserScan*>& scans) {
  for (const core::EncoderReading& e : encoders) localizer_->AddEncoders(e);
  for (const core::LaserScan* scan : scans) {
    if (paused_) break;
    if (!gate_.Admit(*scan)) continue;
    const core::LocalizerCounters before = localizer_->tracker().counters();
    localizer_->AddScan(*scan);
    NoteTrackerBatches(before);
  }
  estimate_ = localizer_->Estimate();
  if (localizer_->cycles() == last_cycles_) return std::nullopt;
  last_cycles_ = localizer_->cycles();
  reporting_loss_ = false;
  EstimatorCycle c = ReportCycle();
  tracked_ = EstimatorCycle{};
  // A loss and a new generation within one tick: the cycle reports the loss,
  // so that it is seen (events, metrics); the next one the new hypotheses.
  if (localizer_->counters().losses != last_losses_ && c.mode != LocalizationMode::kLost) {
    c.mode = LocalizationMode::kLost;
    c.hypotheses = 0;
    c.lost = true;
    reporting_loss_ = true;
  }
  last_losses_ = localizer_->counters().losses;
  return c;
}

void GlobalPoseEstimator::NoteTrackerBatches(const core::LocalizerCounters& before) {
  const core::LocalizerCounters& after = localizer_->tracker().counters();
  if (after.cycles == before.cycles || mode() != LocalizationMode::kLocalized) return;
  EstimatorCycle batch = CycleFromReport(localizer_->tracker().last_cycle());
  if (after.cycles > before.cycles + 1) {
    // Deferred batches integrated together: their other pairings count as
    // lines (lasers give lines and beacons; the last batch says how many of each).
    const long paired =
        batch.matched_lines + batch.matched_beacons + batch.matched_edges + batch.matched_other;
    batch.matched_lines += static_cast<int>(std::max(0L, after.matches - before.matches - paired));
    batch.predictions = static_cast<int>(after.predictions - before.predictions);
    batch.observations = static_cast<int>(after.observations - before.observations);
  }
  tracked_.AddCounts(batch);
}

EstimatorCycle GlobalPoseEstimator::ReportCycle() const {
  const LocalizationMode now = mode();
  EstimatorCycle c = now == LocalizationMode::kLocalized ? tracked_ : EstimatorCycle{};
  c.mode = now;
  c.hypotheses = localizer_->hypothesis_count();
  c.lost = c.mode == LocalizationMode::kLost;
  if (c.mode != LocalizationMode::kLocalized && c.hypotheses > 0) {
    c.matched_lines = localizer_->Hypotheses().front().pairings;  // the best hypothesis's p'
  }
  return c;
}

LocalizationMode GlobalPoseEstimator::mode() const {
  switch (localizer_->state()) {
    case core::GlobalLocalizationState::kLocalized:
      return LocalizationMode::kLocalized;
    case core::GlobalLocalizationState::kNotLocalized:
      return LocalizationMode::kNotLocalized;
    case core::GlobalLocalizationState::kLost:
      break;
  }
  return LocalizationMode::kLost;
}

std::vector<LocationHypothesis> GlobalPoseEstimator::hypotheses() const {
  std::vector<LocationHypothesis> out;
  for (const core::LocationHypothesisData& h : localizer_->Hypotheses()) {
    out.push_back(LocationHypothesis{h.location, h.pairings, h.joint_mahalanobis});
  }
  return out;
}

std::string GlobalPoseEstimator::lost_reason() const {
  if (localizer_->state() != core::GlobalLocalizationState::kLost && !reporting_loss_) {
    return "none";
  }
  if (localizer_->last_loss_cause() == core::GlobalLostCause::kTrackingLost) {
    const core::LostReason reason = localizer_->last_tracking_reason();
    return reason == core::LostReason::kNone ? "tracking_lost" : LostReasonName(reason);
  }
  return core::GlobalLostCauseName(localizer_->last_loss_cause());
}

void GlobalPoseEstimator::SetPaused(bool paused, double now_s) {
  if (paused_ != paused) localizer_->SuspendLostDetection(paused, now_s);
  paused_ = paused;
}

void GlobalPoseEstimator::OnContact(const BumperContact& contact) {
  localizer_->AddPoseUncertainty(options_.collision.Covariance(contact));
}

std::vector<std::pair<std::string, std::int64_t>> GlobalPoseEstimator::counters() const {
  const core::GlobalLocalizerCounters& c = localizer_->counters();
  return {{"generations", c.generations},
          {"tracking_cycles", c.tracking_cycles},
          {"tree_nodes", c.tree_nodes},
          {"node_limit_hits", c.node_limit_hits},
          {"hypothesis_limit_hits", c.hypothesis_limit_hits},
          {"splits", c.splits},
          {"falsified", c.falsified},
          {"free_space_rejections", c.free_space_rejections},
          {"free_space_falsified", c.free_space_falsified},
          {"resumed_tracks", c.resumed_tracks},
          {"duplicates", c.duplicates},
          {"losses", c.losses},
          {"localizations", c.localizations},
          {"slip_rematches", localizer_->tracker().counters().slip_rematches}};
}

}  // namespace pavilion::nav
