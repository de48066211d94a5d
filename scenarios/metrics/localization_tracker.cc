#include "scenarios/metrics/localization_tracker.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <numbers>

namespace pavilion::scenarios {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(mid), v.end());
  return v[mid];
}

}  // namespace

const LocalizationCycle& LocalizationTracker::Record(const nav::EstimatorCycle& cycle,
                                                     const nav::PoseEstimator& estimator,
                                                     const core::Pose2& truth, double now_s) {
  LocalizationCycle c;
  c.time_s = now_s;
  c.truth = truth;
  c.estimate = estimator.estimate().pose;
  c.covariance = estimator.estimate().covariance;
  const Eigen::Vector3d e(c.estimate.x_m - truth.x_m, c.estimate.y_m - truth.y_m,
                          core::NormalizeAngle(c.estimate.theta_rad - truth.theta_rad));
  c.position_error_m = e.head<2>().norm();
  c.heading_error_rad = e.z();
  c.nees = e.dot(c.covariance.ldlt().solve(e));
  // Position covariance in the robot's frame: frontal (x) and lateral (y).
  const double ct = std::cos(truth.theta_rad), st = std::sin(truth.theta_rad);
  Eigen::Matrix2d rot;
  rot << ct, -st, st, ct;
  const Eigen::Matrix2d local = rot.transpose() * c.covariance.topLeftCorner<2, 2>() * rot;
  c.two_sigma_frontal_m = 2.0 * std::sqrt(std::max(0.0, local(0, 0)));
  c.two_sigma_lateral_m = 2.0 * std::sqrt(std::max(0.0, local(1, 1)));
  c.two_sigma_heading_rad = 2.0 * std::sqrt(std::max(0.0, c.covariance(2, 2)));
  c.predictions = cycle.predictions;
  c.observations = cycle.observations;
  c.matched_lines = cycle.matched_lines;
  c.matched_beacons = cycle.matched_beacons;
  c.matched_other = cycle.matched_other;
  c.lost = cycle.lost;
  c.mode = cycle.mode;
  c.hypotheses = cycle.hypotheses;
  if (c.mode == nav::LocalizationMode::kLost && mode_ != nav::LocalizationMode::kLost) {
    ++declared_lost_situations_;
  }
  mode_ = c.mode;
  const bool lost_now = c.lost || c.position_error_m > kLostPositionErrorM ||
                        std::abs(c.heading_error_rad) > kLostHeadingErrorRad;
  lost_started_ = lost_now && !in_lost_situation_;
  if (lost_started_) ++lost_situations_;
  in_lost_situation_ = lost_now;
  lost_reason_ = estimator.lost_reason();
  if (lost_reason_ == "none" && in_lost_situation_) lost_reason_ = "true_error";
  cycles_.push_back(c);
  return cycles_.back();
}

LocalizationFigures LocalizationTracker::Figures() const {
  LocalizationFigures f;
  f.cycles = static_cast<int>(cycles_.size());
  f.lost_situations = lost_situations_;
  f.declared_lost_situations = declared_lost_situations_;
  if (cycles_.empty()) return f;
  std::vector<double> position, heading;
  double sum_p2 = 0.0, sum_h2 = 0.0, nees = 0.0;
  int below = 0;
  for (const LocalizationCycle& c : cycles_) {
    position.push_back(c.position_error_m);
    heading.push_back(std::abs(c.heading_error_rad) * kDeg);
    sum_p2 += c.position_error_m * c.position_error_m;
    sum_h2 += c.heading_error_rad * c.heading_error_rad;
    f.position_max_m = std::max(f.position_max_m, c.position_error_m);
    f.heading_max_deg = std::max(f.heading_max_deg, std::abs(c.heading_error_rad) * kDeg);
    f.two_sigma_frontal_m += c.two_sigma_frontal_m;
    f.two_sigma_lateral_m += c.two_sigma_lateral_m;
    f.two_sigma_heading_deg += c.two_sigma_heading_rad * kDeg;
    nees += c.nees;
    below += c.nees <= kNees95Bound3 ? 1 : 0;
    f.matched_lines_per_cycle += c.matched_lines;
    f.matched_beacons_per_cycle += c.matched_beacons;
    f.cycles_without_match += c.matched_lines + c.matched_beacons + c.matched_other == 0 ? 1 : 0;
  }
  const double n = static_cast<double>(cycles_.size());
  f.position_rmse_m = std::sqrt(sum_p2 / n);
  f.heading_rmse_deg = std::sqrt(sum_h2 / n) * kDeg;
  f.position_median_m = Median(position);
  f.heading_median_deg = Median(heading);
  f.two_sigma_frontal_m /= n;
  f.two_sigma_lateral_m /= n;
  f.two_sigma_heading_deg /= n;
  f.anees = nees / n;
  f.nees_below_95_bound_ratio = below / n;
  f.matched_lines_per_cycle /= n;
  f.matched_beacons_per_cycle /= n;
  return f;
}

}  // namespace pavilion::scenarios
