#pragma once

// A robot's localization judged against ground truth: every estimation cycle
// of its robot stack (nav::PoseEstimator) compared with the true pose, and the
// run's figures of metrics.md, "Localization". Ground truth stays here, on the
// runner's side: the robot stack never sees it.

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "core/types/pose2.h"
#include "nav/stack/pose_estimator.h"
#include "scenarios/metrics/stride_buffer.h"

namespace pavilion::scenarios {

// One localization cycle compared with the truth (a row of localization.csv).
struct LocalizationCycle {
  double time_s = 0.0;
  core::Pose2 truth;
  core::Pose2 estimate;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double position_error_m = 0.0;
  double heading_error_rad = 0.0;  // estimate - truth, wrapped
  double nees = 0.0;               // e^T P^-1 e, 3 dof
  double two_sigma_frontal_m = 0.0;
  double two_sigma_lateral_m = 0.0;
  double two_sigma_heading_rad = 0.0;
  int predictions = 0;
  int observations = 0;
  int matched_lines = 0;
  int matched_beacons = 0;
  int matched_edges = 0;  // a camera's vertical edges (n_v of Tables 4.1-4.2)
  int matched_other = 0;
  bool lost = false;  // the localizer declares itself lost
  nav::LocalizationMode mode = nav::LocalizationMode::kLocalized;  // thesis Fig. 5.17
  int hypotheses = 1;                                              // n
};

// The run's figures (metrics.md), over all cycles.
struct LocalizationFigures {
  int cycles = 0;
  double position_rmse_m = 0.0;
  double position_median_m = 0.0;
  double position_max_m = 0.0;
  double heading_rmse_deg = 0.0;
  double heading_median_deg = 0.0;
  double heading_max_deg = 0.0;
  double two_sigma_frontal_m = 0.0;  // means over cycles
  double two_sigma_lateral_m = 0.0;
  double two_sigma_heading_deg = 0.0;
  double anees = 0.0;
  double nees_below_95_bound_ratio = 0.0;  // chi^2(3) 95%: 7.81
  double matched_lines_per_cycle = 0.0;
  double matched_beacons_per_cycle = 0.0;
  double matched_edges_per_cycle = 0.0;
  int cycles_without_match = 0;
  int lost_situations = 0;  // metrics.md: true error beyond 0.5 m / 10 deg, or declared lost
  int declared_lost_situations = 0;  // the estimator's own: transitions into kLost
};

// True error beyond which a cycle counts as a lost situation (metrics.md).
inline constexpr double kLostPositionErrorM = 0.5;
inline constexpr double kLostHeadingErrorRad = 10.0 * 3.14159265358979323846 / 180.0;
// One-sided 95% bound of chi^2(3).
inline constexpr double kNees95Bound3 = 7.814727903251178;

class LocalizationTracker {
 public:
  // Records the cycle `cycle` of `estimator` that ended at `now_s` with the
  // robot at `truth`; returns it (a row of localization.csv).
  const LocalizationCycle& Record(const nav::EstimatorCycle& cycle,
                                  const nav::PoseEstimator& estimator, const core::Pose2& truth,
                                  double now_s);

  const LocalizationCycle& last_cycle() const { return plot_cycles_.last(); }
  std::int64_t cycle_count() const { return plot_cycles_.count(); }
  // The cycles for pictures: at most a few thousand, evenly spaced, the last included.
  std::vector<LocalizationCycle> plot_cycles() const { return plot_cycles_.items_and_last(); }
  // A lost situation began with the last recorded cycle (for events).
  bool lost_started() const { return lost_started_; }
  // A lost situation holds after the last recorded cycle.
  bool in_lost_situation() const { return in_lost_situation_; }
  // Why: the estimator's reason, or "true_error" when only the truth says so.
  const std::string& lost_reason() const { return lost_reason_; }
  LocalizationFigures Figures() const;

 private:
  // Memory per cycle: the two errors (16 bytes, for the exact medians); the
  // rest are running sums, in cycle order as a pass over all cycles would add.
  StrideBuffer<LocalizationCycle> plot_cycles_;
  std::vector<double> position_errors_m_;
  std::vector<double> heading_errors_deg_;
  double sum_p2_ = 0.0, sum_h2_ = 0.0, nees_ = 0.0;
  double position_max_m_ = 0.0, heading_max_deg_ = 0.0;
  double two_sigma_frontal_m_ = 0.0, two_sigma_lateral_m_ = 0.0, two_sigma_heading_deg_ = 0.0;
  double matched_lines_ = 0.0, matched_beacons_ = 0.0, matched_edges_ = 0.0;
  int below_ = 0;
  int cycles_without_match_ = 0;
  bool in_lost_situation_ = false;
  bool lost_started_ = false;
  std::string lost_reason_ = "none";
  int lost_situations_ = 0;
  int declared_lost_situations_ = 0;
  nav::LocalizationMode mode_ = nav::LocalizationMode::kLocalized;
};

}  // namespace pavilion::scenarios
