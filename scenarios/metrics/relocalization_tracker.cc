#include "scenarios/metrics/relocalization_tracker.h"

#include <algorithm>
#include <cmath>

namespace pavilion::scenarios {
namespace {

double Mean(const std::vector<double>& v) {
  if (v.empty()) return 0.0;
  double sum = 0.0;
  for (double x : v) sum += x;
  return sum / static_cast<double>(v.size());
}

// The middle value; the mean of the two middle ones for an even count.
double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t mid = v.size() / 2;
  return v.size() % 2 == 1 ? v[mid] : 0.5 * (v[mid - 1] + v[mid]);
}

double Ratio(int count, int of) { return of > 0 ? static_cast<double>(count) / of : 0.0; }

}  // namespace

void RelocalizationTracker::OnStep(double dt_s, double distance_m) {
  if (outcomes_.empty() || dt_s <= 0.0) return;
  KidnapOutcome& k = outcomes_.back();
  if (distance_m / dt_s > kMovingSpeedMps) k.motion_s += dt_s;
  k.distance_m += distance_m;
}

void RelocalizationTracker::OnKidnap(double now_s) {
  outcomes_.push_back(KidnapOutcome{.at_s = now_s});
  pending_relocalization_ = true;
  if (mode_ == nav::LocalizationMode::kLocalized) unnoticed_kidnap_ = true;
  fbt_good_since_s_.reset();
}

RelocalizationChange RelocalizationTracker::OnCycle(double now_s, nav::LocalizationMode mode,
                                                    int hypotheses, double position_error_m,
                                                    double heading_error_rad) {
  using Mode = nav::LocalizationMode;
  RelocalizationChange change;
  change.hypotheses_changed = hypotheses != hypotheses_;
  change.lost = mode == Mode::kLost && mode_ != Mode::kLost;
  change.localized = mode == Mode::kLocalized && mode_ != Mode::kLocalized;
  const double heading_rad = std::abs(heading_error_rad);
  const bool within =
      position_error_m <= kRelocalizedPositionM && heading_rad <= kRelocalizedHeadingRad;
  if (change.lost) {
    ++declared_losses_;
    pending_relocalization_ = true;
  }
  if (change.localized && pending_relocalization_) {
    change.relocalized = true;
    change.correct = within;
    pending_relocalization_ = false;
  }
  // A false relocalization: declared localized (from lost or not localized)
  // while off. Being off later — a push or a collision the tracking did not
  // follow — is a lost situation (LocalizationTracker), not a relocalization.
  const bool off = mode == Mode::kLocalized &&
                   (position_error_m > kFalsePositionM || heading_rad > kFalseHeadingRad);
  if (mode != Mode::kLocalized || !off) unnoticed_kidnap_ = false;
  if (off && change.localized && !unnoticed_kidnap_) ++false_relocalizations_;
  if (!outcomes_.empty()) {
    KidnapOutcome& k = outcomes_.back();
    if (!k.recovered && !k.lost_declared && mode == Mode::kLost) {
      k.lost_declared = true;
      k.motion_to_lost_s = k.motion_s;
    }
    if (!k.localized_correctly && mode == Mode::kLocalized && within) {
      k.localized_correctly = true;
      k.motion_to_correct_s = k.motion_s;
    }
    if (!k.recovered && mode == Mode::kLocalized && within && k.motion_s <= kRecoveryMotionS) {
      k.recovered = true;
      k.motion_to_relocalize_s = k.motion_s;
      k.distance_to_relocalize_m = k.distance_m;
    }
    if (position_error_m <= kFbtPositionM) {
      if (!fbt_good_since_s_) fbt_good_since_s_ = now_s;
      if (!k.fbt_recovered && now_s - *fbt_good_since_s_ > kFbtHoldS) {
        k.fbt_recovered = true;
        k.fbt_recovery_s = *fbt_good_since_s_ - k.at_s;
      }
    } else {
      fbt_good_since_s_.reset();
    }
  }
  ++cycles_;
  hypotheses_sum_ += hypotheses;
  max_hypotheses_ = std::max(max_hypotheses_, hypotheses);
  mode_ = mode;
  hypotheses_ = hypotheses;
  return change;
}

RelocalizationFigures RelocalizationTracker::Figures() const {
  RelocalizationFigures f;
  f.outcomes = outcomes_;
  f.kidnaps = static_cast<int>(outcomes_.size());
  std::vector<double> to_lost, to_relocalize, distance, fbt;
  int lost_in_time = 0, fbt_recovered = 0;
  for (const KidnapOutcome& k : outcomes_) {
    if (k.lost_declared) {
      to_lost.push_back(k.motion_to_lost_s);
      if (k.motion_to_lost_s <= kLostDeclaredMotionS) ++lost_in_time;
    }
    if (k.recovered) {
      ++f.recovered;
      to_relocalize.push_back(k.motion_to_relocalize_s);
      distance.push_back(k.distance_to_relocalize_m);
    }
    if (k.fbt_recovered) {
      ++fbt_recovered;
      fbt.push_back(k.fbt_recovery_s);
    }
  }
  f.recovered_ratio = Ratio(f.recovered, f.kidnaps);
  f.lost_declared_within_10s_ratio = Ratio(lost_in_time, f.kidnaps);
  f.mean_time_to_lost_s = Mean(to_lost);
  f.median_time_to_lost_s = Median(to_lost);
  f.mean_time_to_relocalize_s = Mean(to_relocalize);
  f.median_time_to_relocalize_s = Median(to_relocalize);
  f.mean_distance_to_relocalize_m = Mean(distance);
  f.median_distance_to_relocalize_m = Median(distance);
  f.declared_losses = declared_losses_;
  f.false_relocalizations = false_relocalizations_;
  f.fbt_recovered_ratio = Ratio(fbt_recovered, f.kidnaps);
  f.fbt_mean_recovery_s = Mean(fbt);
  f.mean_hypotheses =
      cycles_ > 0 ? static_cast<double>(hypotheses_sum_) / static_cast<double>(cycles_) : 0.0;
  f.max_hypotheses = max_hypotheses_;
  return f;
}

}  // namespace pavilion::scenarios
