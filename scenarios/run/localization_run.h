#pragma once

// A robot's localization inside a scenario run: feeds its encoder readings and
// laser scans to the core's EKF pose tracking (core/localization/localizer.h)
// at the scenario's rate, compares every cycle with ground truth and keeps the
// figures of metrics.md, "Localization".

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "core/localization/localizer.h"
#include "core/types/sensor_data.h"
#include "scenarios/config/scenario.h"

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
  int matched_other = 0;
  bool lost = false;  // the localizer declares itself lost
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
  int cycles_without_match = 0;
  int lost_situations = 0;  // metrics.md: true error beyond 0.5 m / 10 deg, or declared lost
};

// True error beyond which a cycle counts as a lost situation (metrics.md).
inline constexpr double kLostPositionErrorM = 0.5;
inline constexpr double kLostHeadingErrorRad = 10.0 * 3.14159265358979323846 / 180.0;
// One-sided 95% bound of chi^2(3).
inline constexpr double kNees95Bound3 = 7.814727903251178;

// The map a robot localizes and plans with: its map file (default: the
// world's map.yaml), or for `map: derive` a map derived from `world` (static
// geometry only: call before bodies and robots are added) with the entry's
// tape-measure noise drawn from the scenario's seed. Throws InputError naming
// the scenario key for a bad map.
core::RobotMap LoadRobotMap(const RobotEntry& robot, const Scenario& scenario,
                            const sim::World& world);

class LocalizationRun {
 public:
  // Takes `map` (the robot's map file, loaded by LoadRobotMap), sets the
  // localizer up from the robot's calibrated odometry and lasers, and
  // initializes it at the true start pose plus the entry's offset.
  LocalizationRun(const RobotEntry& robot, core::RobotMap map);

  // The tick's sensor outputs in time order; `truth` is the robot's true pose
  // at the end of the tick (time `now_s`). Returns true when a localization
  // cycle completed in this tick (then last_cycle() holds it).
  bool Update(const std::vector<core::EncoderReading>& encoders,
              const std::vector<const core::LaserScan*>& scans, const core::Pose2& truth,
              double now_s);

  const core::Localizer& localizer() const { return *localizer_; }
  bool tracking() const;
  const LocalizationCycle& last_cycle() const { return cycles_.back(); }
  const std::vector<LocalizationCycle>& cycles() const { return cycles_; }
  // Newly started lost situations in the last Update (for events).
  bool lost_started() const { return lost_started_; }
  const char* lost_reason() const;
  LocalizationFigures Figures() const;

 private:
  std::unique_ptr<core::Localizer> localizer_;
  LocalizationEntry entry_;
  std::vector<double> next_due_s_;  // per laser id in entry order
  std::vector<std::string> laser_ids_;
  std::vector<LocalizationCycle> cycles_;
  long last_cycles_ = 0;
  bool in_lost_situation_ = false;
  bool lost_started_ = false;
  int lost_situations_ = 0;
};

}  // namespace pavilion::scenarios
