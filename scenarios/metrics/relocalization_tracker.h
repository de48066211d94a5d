#pragma once

// Relocalization after a kidnap, judged against ground truth (metrics.md,
// "Relocalization"; issue 18): per kidnap, whether and how soon the robot's
// estimator declared itself lost and then localized again at the true pose,
// false relocalizations, the hypothesis count over time, and the recovery of
// Fox, Burgard & Thrun (JAIR 1999). Ground truth stays on the runner's side.
//
// Motion time: the seconds in which the robot's true speed exceeded
// kMovingSpeedMps. Times after a kidnap are counted in motion time, since a
// robot standing still sees nothing new (issue 18: "within 30 s of motion");
// the Fox-Burgard-Thrun recovery time is simulated time, as theirs.

#include <optional>
#include <vector>

#include "nav/stack/pose_estimator.h"

namespace pavilion::scenarios {

// True speed above which a robot counts as moving, m/s (chosen: above the
// jitter of a robot at rest on its wheels, below any drive speed).
inline constexpr double kMovingSpeedMps = 0.02;
// Recovered: declared localized within these of the truth (issue 18).
inline constexpr double kRelocalizedPositionM = 0.2;
inline constexpr double kRelocalizedHeadingRad = 5.0 * 3.14159265358979323846 / 180.0;
// ... within this much motion time after the kidnap, s (issue 18).
inline constexpr double kRecoveryMotionS = 30.0;
// Lost declared in time: within this much motion time after the kidnap, s (issue 18).
inline constexpr double kLostDeclaredMotionS = 10.0;
// False relocalization: declared localized while this far off (metrics.md).
inline constexpr double kFalsePositionM = 0.5;
inline constexpr double kFalseHeadingRad = 10.0 * 3.14159265358979323846 / 180.0;
// Fox, Burgard & Thrun 1999: recovered when the estimate stays within this of
// the true position for more than kFbtHoldS.
inline constexpr double kFbtPositionM = 0.45;
inline constexpr double kFbtHoldS = 10.0;

// One kidnap and what followed it, until the next kidnap or the run's end.
struct KidnapOutcome {
  double at_s = 0.0;
  double motion_s = 0.0;    // motion time after it
  double distance_m = 0.0;  // true distance travelled after it
  bool lost_declared = false;
  double motion_to_lost_s = 0.0;  // when lost_declared
  bool recovered = false;
  double motion_to_relocalize_s = 0.0;    // when recovered
  double distance_to_relocalize_m = 0.0;  // when recovered
  // The first declaration of localized within 0.2 m / 5 deg after it, however
  // late (global_start's 60 s criterion), before the next kidnap.
  bool localized_correctly = false;
  double motion_to_correct_s = 0.0;  // when localized_correctly
  bool fbt_recovered = false;
  double fbt_recovery_s = 0.0;  // simulated s from the kidnap to the start of the good stretch
};

struct RelocalizationFigures {
  std::vector<KidnapOutcome> outcomes;
  int kidnaps = 0;
  int recovered = 0;
  double recovered_ratio = 0.0;
  double lost_declared_within_10s_ratio = 0.0;
  double mean_time_to_lost_s = 0.0;  // motion s, over kidnaps with a declared loss
  double median_time_to_lost_s = 0.0;
  double mean_time_to_relocalize_s = 0.0;  // motion s, over recovered kidnaps
  double median_time_to_relocalize_s = 0.0;
  double mean_distance_to_relocalize_m = 0.0;
  double median_distance_to_relocalize_m = 0.0;
  int declared_losses = 0;  // transitions into kLost, kidnap or not
  int false_relocalizations = 0;
  double fbt_recovered_ratio = 0.0;
  double fbt_mean_recovery_s = 0.0;  // over FBT-recovered kidnaps
  double mean_hypotheses = 0.0;      // n over the estimation cycles
  int max_hypotheses = 0;
};

// What one estimation cycle changed, for events.jsonl.
struct RelocalizationChange {
  bool hypotheses_changed = false;  // n differs from the last cycle's
  bool lost = false;                // the mode became kLost
  bool localized = false;           // the mode became kLocalized from another
  bool relocalized = false;         // ... after a kidnap or a declared loss
  bool correct = false;             // relocalized within 0.2 m and 5 deg of the truth
};

class RelocalizationTracker {
 public:
  // One physics step of dt_s in which the robot truly travelled distance_m.
  void OnStep(double dt_s, double distance_m);
  // The robot was kidnapped at now_s.
  void OnKidnap(double now_s);
  // An estimation cycle ended at now_s in `mode` with `hypotheses` (n) and
  // this true error of the estimate the robot acts on.
  RelocalizationChange OnCycle(double now_s, nav::LocalizationMode mode, int hypotheses,
                               double position_error_m, double heading_error_rad);
  // Whether the run had a kidnap or a declared loss (the section is reported).
  bool active() const { return !outcomes_.empty() || declared_losses_ > 0; }
  RelocalizationFigures Figures() const;

 private:
  std::vector<KidnapOutcome> outcomes_;
  nav::LocalizationMode mode_ = nav::LocalizationMode::kLocalized;
  int hypotheses_ = 1;
  bool pending_relocalization_ = false;  // a kidnap or a declared loss since the last one
  // Localized through a kidnap and not yet out of kLocalized since: being off
  // is the kidnap's doing, not a false relocalization.
  bool unnoticed_kidnap_ = false;
  std::optional<double> fbt_good_since_s_;
  int declared_losses_ = 0;
  int false_relocalizations_ = 0;
  long long cycles_ = 0;
  long long hypotheses_sum_ = 0;
  int max_hypotheses_ = 0;
};

}  // namespace pavilion::scenarios
