#pragma once

#include <string>
#include <vector>

#include "core/types/pose2.h"
#include "core/types/sensor_data.h"

namespace pavilion::scenarios {

// Angular step between the n readings of a CARMEN FLASER message. The first
// reading is at -90° (robot's right); the files do not record whether the n
// readings span 180° in n steps or in n - 1 steps (see docs/carmen_logs.md for
// the choice per log, made with DecideCarmenAngleStep).
enum class CarmenAngleStep {
  kFovOverN,        // step 180°/n: the last reading at 90° - 180°/n
  kFovOverNMinus1,  // step 180°/(n-1): the last reading at exactly 90°
};

// Bearing of reading `index` (0-based) of a scan of `num_readings`, in radians
// counter-clockwise from the laser's x axis.
double CarmenBearingRad(int index, int num_readings, CarmenAngleStep step);

struct CarmenOptions {
  // Readings >= this or <= 0 are no-returns (valid = false); the logs' no-return
  // values range from 32.8 to 81.9 m. Metres, finite, > 0.
  double max_range_m = 30.0;
  // Bearing convention used for every reading.
  CarmenAngleStep angle_step = CarmenAngleStep::kFovOverN;

  // Throws std::invalid_argument naming the field.
  void Validate() const;
};

// One FLASER message with the wheel odometry that led to it.
struct CarmenScan {
  int line = 0;          // 1-based line of the FLASER message in the file
  double stamp_s = 0.0;  // FLASER timestamp (all 0 in orebro, 6 digits in csail)
  // The readings, right to left; invalid ones carry range_m = max_range_m.
  // robot_from_sensor is the identity (the logged pose is the laser's).
  core::LaserScan scan;
  // Reference ("ground truth") laser pose of the corrected trajectory.
  core::Pose2 world_from_laser;
  // Whether the wheel odometry since the previous scan is known: false for the
  // first scan and for intervals without wheel odometry (never zero motion).
  bool odometry_known = false;
  // Wheel-odometry motion since the previous scan, expressed in the previous
  // scan's frame: (ODOM anchor)⁻¹ ⊕ (last ODOM before this FLASER). Identity
  // when !odometry_known.
  core::Pose2 previous_from_current_odom;
};

// A whole CARMEN log, scans in file order.
struct CarmenLog {
  std::string path;
  std::vector<CarmenScan> scans;

  // Scan intervals (scans after the first) whose odometry is unknown.
  int UnknownOdometryIntervals() const;
};

// Reads a CARMEN log, plain text or gzip (".log" or ".log.gz"). FLASER messages
// become scans; the odometry increment of each scan is taken from the ODOM lines
// between it and the previous FLASER: the first ODOM after the previous FLASER is
// the anchor (the corrected pose, from which the wheels integrate), the last ODOM
// before this FLASER the end point; an interval holding only the anchor, or no
// ODOM at all, has unknown odometry. Odometry fields of FLASER (a copy of the
// corrected pose) are ignored. Other message types and '#' comments are skipped.
// Throws InputError (a std::runtime_error) "path:line: what was expected" on a
// malformed FLASER or ODOM line, and naming the path if it cannot be read.
CarmenLog ReadCarmenLog(const std::string& path, const CarmenOptions& options = {});

// Recomputes every reading's bearing for `step`; ranges are unchanged.
void SetCarmenAngleStep(CarmenAngleStep step, CarmenLog* log);

// How DecideCarmenAngleStep finds long straight runs of consecutive readings.
struct CarmenStraightnessOptions {
  // Consecutive valid points farther apart than this start a new run. Metres, > 0.
  double break_distance_m = 0.3;
  // Iterative end-point fit: a run is split at its farthest point from the chord
  // while that distance exceeds this. Metres, > 0.
  double split_distance_m = 0.05;
  // A run is kept as a wall if it has at least this many points (>= 3) ...
  int min_points = 20;
  // ... and its end points are at least this far apart. Metres, > 0.
  double min_length_m = 2.0;

  void Validate() const;
};

// The long straight runs ("walls") of one scan, as the ascending indices of
// their readings, runs in reading order. Chains of consecutive valid readings
// (an invalid reading, or two consecutive points more than break_distance_m
// apart, ends a chain) are split by iterative end-point fit at the point
// farthest from the chord while that distance exceeds split_distance_m; the
// pieces of at least min_points readings whose end points are at least
// min_length_m apart are kept (docs/carmen_logs.md). Points are at each
// reading's range_m and bearing_rad in the sensor frame. The segmentation of
// DecideCarmenAngleStep and of the residual statistics of
// scenarios/realism/scan_residuals.h. Throws std::invalid_argument for invalid
// options.
std::vector<std::vector<int>> FindStraightRuns(const core::LaserScan& scan,
                                               const CarmenStraightnessOptions& options = {});

// Outcome of DecideCarmenAngleStep, with the numbers that justify it.
struct CarmenAngleStepDecision {
  CarmenAngleStep step = CarmenAngleStep::kFovOverN;
  int runs = 0;    // straight runs used (over all scans)
  int points = 0;  // readings in those runs
  // RMS perpendicular residual of a total-least-squares line fitted to each run,
  // over all runs, with each step. Metres.
  double rms_fov_over_n_m = 0.0;
  double rms_fov_over_n_minus_1_m = 0.0;
  // Weighted median over runs of the step that makes each run straightest, as a
  // fraction of the way from 180°/n (0) to 180°/(n-1) (1); decides the step
  // (< 0.5: 180°/n).
  double median_step_fraction = 0.0;
  // Paired significance of the difference: mean over runs of (squared residual
  // with 180°/n − with 180°/(n-1)) divided by its standard error. Positive
  // favours 180°/(n-1); |z| < 2 means the logs hardly tell the two apart.
  double paired_z = 0.0;
};

// Decides which angular step makes long straight walls straightest. Runs of
// consecutive points that are straight within split_distance_m are segmented
// once, with the step halfway between the two, so both steps are scored on the
// same points. A wrong step bends a straight wall (the normal error grows as
// d·ε·φ·tanφ for a wall at distance d seen φ off its normal, ε the relative step
// error), which raises the residual of a straight-line fit. Each run's squared
// residual is fitted as a parabola in the step and the run votes for its
// minimum, weighted by the parabola's curvature; the weighted median vote picks
// the nearer of the two steps. The median, unlike the total residual, is not
// swayed by the few runs that are not truly straight (docs/carmen_logs.md).
CarmenAngleStepDecision DecideCarmenAngleStep(const CarmenLog& log,
                                              const CarmenStraightnessOptions& options = {});

}  // namespace pavilion::scenarios
