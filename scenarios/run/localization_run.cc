#include "scenarios/run/localization_run.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <stdexcept>

#include "scenarios/config/input_error.h"
#include "scenarios/maps/map_derivation.h"
#include "scenarios/maps/map_file.h"

namespace pavilion::scenarios {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

core::LocalizerOptions OptionsFor(const RobotEntry& robot) {
  core::LocalizerOptions o;
  const sim::OdometryCalibration& c = robot.config.odometry;
  o.odometry.left_wheel_radius_m = c.left_wheel_radius_m;
  o.odometry.right_wheel_radius_m = c.right_wheel_radius_m;
  o.odometry.wheelbase_m = c.wheelbase_m;
  o.odometry.k_left_m = c.k_left_m;
  o.odometry.k_right_m = c.k_right_m;
  o.odometry.k_turn_m = c.k_turn_m;
  // The calibration measured the physics' own error with encoder noise off;
  // injected encoder noise is independent of it, so the variances add (§2.3:
  // Var = k|s| per wheel, hence the k add).
  const sim::EncoderOptions& encoders = robot.config.encoders;
  if (encoders.noise) {
    o.odometry.k_left_m += encoders.k_left_m;
    o.odometry.k_right_m += encoders.k_right_m;
  }
  o.significance = robot.localization.significance;
  for (const sim::LaserMount& mount : robot.config.lasers) {
    core::LaserSensorOptions laser;
    laser.id = mount.id;
    o.lasers.push_back(laser);
  }
  return o;
}

double Median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const std::size_t mid = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<long>(mid), v.end());
  return v[mid];
}

}  // namespace

core::RobotMap LoadRobotMap(const RobotEntry& robot, const Scenario& scenario,
                            const sim::World& world) {
  const LocalizationEntry& entry = robot.localization;
  try {
    if (entry.derive_map_noise_m) {
      MapDerivationOptions options;
      options.noise_sigma_m = *entry.derive_map_noise_m;
      options.seed = scenario.seed;
      return DeriveRobotMap(world, options);
    }
    std::string file = entry.map_file;
    if (file.empty()) {
      file = (std::filesystem::path(scenario.world_file).parent_path() / "map.yaml").string();
    }
    return LoadMapFile(file);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(
        Diagnostic{scenario.source_file, 0, "robots." + robot.id + ".localization.map", e.what()});
  }
}

LocalizationRun::LocalizationRun(const RobotEntry& robot, core::RobotMap map)
    : entry_(robot.localization) {
  localizer_ = std::make_unique<core::Localizer>(std::move(map), OptionsFor(robot));
  for (const sim::LaserMount& mount : robot.config.lasers) {
    if (entry_.lasers.empty() ||
        std::find(entry_.lasers.begin(), entry_.lasers.end(), mount.id) != entry_.lasers.end()) {
      laser_ids_.push_back(mount.id);
      next_due_s_.push_back(0.0);
    }
  }
  const core::Pose2 start{
      robot.pose.x_m + entry_.initial_offset.x_m, robot.pose.y_m + entry_.initial_offset.y_m,
      core::NormalizeAngle(robot.pose.theta_rad + entry_.initial_offset.theta_rad)};
  const Eigen::Vector3d var = entry_.initial_sigma.cwiseProduct(entry_.initial_sigma);
  localizer_->Initialize(start, var.asDiagonal().toDenseMatrix(), 0.0);
}

bool LocalizationRun::tracking() const {
  return localizer_->status().state == core::LocalizationState::kTracking;
}

const char* LocalizationRun::lost_reason() const {
  switch (localizer_->status().reason) {
    case core::LostReason::kNone:
      return in_lost_situation_ ? "true_error" : "none";
    case core::LostReason::kNoMatchTimeout:
      return "no_match_timeout";
    case core::LostReason::kRepeatedGateFailures:
      return "repeated_gate_failures";
    case core::LostReason::kUncertaintyTooLarge:
      return "uncertainty_too_large";
  }
  return "unknown";
}

bool LocalizationRun::Update(const std::vector<core::EncoderReading>& encoders,
                             const std::vector<const core::LaserScan*>& scans,
                             const core::Pose2& truth, double now_s) {
  lost_started_ = false;
  const long before_matches = localizer_->counters().matches;
  for (const core::EncoderReading& e : encoders) localizer_->AddEncoders(e);
  // Scans in the order they finished; each laser's at most rate_hz times per s.
  std::vector<const core::LaserScan*> due;
  for (const core::LaserScan* scan : scans) {
    const auto it = std::find(laser_ids_.begin(), laser_ids_.end(), scan->sensor_id);
    if (it == laser_ids_.end()) continue;
    double& next = next_due_s_[static_cast<std::size_t>(it - laser_ids_.begin())];
    if (scan->stamp_s + 1e-9 < next) continue;
    next = std::max(next + 1.0 / entry_.rate_hz, scan->stamp_s);
    localizer_->AddScan(*scan);
  }
  const long cycles = localizer_->counters().cycles;
  if (cycles == last_cycles_) return false;
  last_cycles_ = cycles;

  LocalizationCycle c;
  c.time_s = now_s;
  c.truth = truth;
  c.estimate = localizer_->estimate().pose;
  c.covariance = localizer_->estimate().covariance;
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
  const core::CycleReport& report = localizer_->last_cycle();
  c.predictions = report.predictions;
  c.observations = report.observations;
  // Matches of every batch integrated in this tick.
  const long matched = localizer_->counters().matches - before_matches;
  for (const core::FeatureMatch& m : report.matches) {
    if (m.type == core::ObservationType::kLine) {
      ++c.matched_lines;
    } else if (m.type == core::ObservationType::kBeacon) {
      ++c.matched_beacons;
    } else {
      ++c.matched_other;
    }
  }
  // Batches before the last one in this tick: count their matches as lines
  // unless the report says otherwise (lasers give lines and beacons).
  c.matched_lines += static_cast<int>(
      std::max(0L, matched - (c.matched_lines + c.matched_beacons + c.matched_other)));
  c.lost = localizer_->status().state == core::LocalizationState::kLost;
  const bool lost_now = c.lost || c.position_error_m > kLostPositionErrorM ||
                        std::abs(c.heading_error_rad) > kLostHeadingErrorRad;
  if (lost_now && !in_lost_situation_) {
    ++lost_situations_;
    lost_started_ = true;
  }
  in_lost_situation_ = lost_now;
  cycles_.push_back(c);
  return true;
}

LocalizationFigures LocalizationRun::Figures() const {
  LocalizationFigures f;
  f.cycles = static_cast<int>(cycles_.size());
  f.lost_situations = lost_situations_;
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
