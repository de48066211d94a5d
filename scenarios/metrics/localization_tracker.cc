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
  c.matched_edges = cycle.matched_edges;
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
  position_errors_m_.push_back(c.position_error_m);
  heading_errors_deg_.push_back(std::abs(c.heading_error_rad) * kDeg);
  sum_p2_ += c.position_error_m * c.position_error_m;
  sum_h2_ += c.heading_error_rad * c.heading_error_rad;
  position_max_m_ = std::max(position_max_m_, c.position_error_m);
  heading_max_deg_ = std::max(heading_max_deg_, std::abs(c.heading_error_rad) * kDeg);
  two_sigma_frontal_m_ += c.two_sigma_frontal_m;
  two_sigma_lateral_m_ += c.two_sigma_lateral_m;
  two_sigma_heading_deg_ += c.two_sigma_heading_rad * kDeg;
  nees_ += c.nees;
  below_ += c.nees <= kNees95Bound3 ? 1 : 0;
  matched_lines_ += c.matched_lines;
  matched_beacons_ += c.matched_beacons;
  matched_edges_ += c.matched_edges;
  cycles_without_match_ +=
      c.matched_lines + c.matched_beacons + c.matched_edges + c.matched_other == 0 ? 1 : 0;
  plot_cycles_.Add(c);
  return plot_cycles_.last();
}

LocalizationFigures LocalizationTracker::Figures() const {
  LocalizationFigures f;
  f.cycles = static_cast<int>(plot_cycles_.count());
  f.lost_situations = lost_situations_;
  f.declared_lost_situations = declared_lost_situations_;
  if (plot_cycles_.empty()) return f;
  const double n = static_cast<double>(plot_cycles_.count());
  f.position_rmse_m = std::sqrt(sum_p2_ / n);
  f.heading_rmse_deg = std::sqrt(sum_h2_ / n) * kDeg;
  f.position_max_m = position_max_m_;
  f.heading_max_deg = heading_max_deg_;
  f.position_median_m = Median(position_errors_m_);
  f.heading_median_deg = Median(heading_errors_deg_);
  f.two_sigma_frontal_m = two_sigma_frontal_m_ / n;
  f.two_sigma_lateral_m = two_sigma_lateral_m_ / n;
  f.two_sigma_heading_deg = two_sigma_heading_deg_ / n;
  f.anees = nees_ / n;
  f.nees_below_95_bound_ratio = below_ / n;
  f.matched_lines_per_cycle = matched_lines_ / n;
  f.matched_beacons_per_cycle = matched_beacons_ / n;
  f.matched_edges_per_cycle = matched_edges_ / n;
  f.cycles_without_match = cycles_without_match_;
  return f;
}

}  // namespace pavilion::scenarios
