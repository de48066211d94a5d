#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

#include "core/odometry/diff_drive.h"
#include "core/odometry/umbmark.h"
#include "core/types/pose2.h"
#include "sim/robot/robot_config.h"

namespace pavilion::scenarios {

// Odometry calibration of a simulated robot (issue 4, thesis §2.3): drive the
// standard runs on a bare floor with the robot's own encoders and physics,
// measure the true end poses (what a tape measure gives on a real robot), and
// estimate the systematic factors with UMBmark (Borenstein & Feng 1996) plus
// straight runs, then the §2.3 wheel-space noise k by maximum likelihood.
// Method and formulas: docs/calibration.md, core/odometry/umbmark.cc and
// core/odometry/wheel_noise_fit.cc.

// How the calibration drives.
struct OdometryCalibrationOptions {
  // Physics step rate, [10, 10000] Hz; a multiple of the robot's encoder rate.
  double physics_rate_hz = 200.0;
  int runs = 5;                // runs of each kind (UMBmark: 5 per direction), [1, 100]
  double square_side_m = 4.0;  // UMBmark square side (Borenstein & Feng: 4 m), [0.5, 20]
  // Cruise speeds (m/s, wheel-rim speed for spins), cycled over the runs of each
  // kind so speed-dependent slip enters the estimates; each in (0, 0.8·max rim speed].
  std::vector<double> speeds_mps = {0.2, 0.4, 0.6};
  // Lengths of the straight runs (m), cycled; even runs drive forward, odd ones backward.
  std::vector<double> straight_lengths_m = {2.0, 5.0, 3.0, 6.0, 4.0};
  double spin_angle_rad = 2 * std::numbers::pi;  // in-place spins, alternating direction, (0, 20]
  // Half circles of these radii (m), cycled, alternating left and right: the
  // motion that shows the physics' lateral slip. Each > 0.
  std::vector<double> arc_radii_m = {1.0, 2.0};
  double floor_friction = 0.7;  // Coulomb coefficient of the bare floor (expo_hall's), [0.05, 2]
  std::uint64_t seed = 1;       // encoder-noise streams of the runs

  void Validate() const;  // throws std::invalid_argument naming the field
};

// One leg of a run. The robot drives it with its own odometry (the nominal
// model), as a real robot executes a calibration path.
struct DriveSegment {
  enum class Type { kStraight, kTurn, kArc };
  Type type = Type::kStraight;
  double distance_m = 0.0;  // kStraight: signed (negative backwards); kArc: path length > 0
  double angle_rad = 0.0;   // kTurn, kArc: heading change, positive counter-clockwise
  double speed_mps = 0.3;   // cruise speed of the base; for kTurn of the wheel rims; > 0
};

enum class CalibrationRunKind { kSquareCcw, kSquareCw, kStraight, kSpin, kArc, kPath };

// A named run: segments driven one after the other, stopping after each.
struct DriveRun {
  std::string name;  // e.g. "square_ccw_1"
  CalibrationRunKind kind = CalibrationRunKind::kPath;
  double speed_mps = 0.0;  // the cruise speed of its segments (for reports)
  std::vector<DriveSegment> segments;
};

// Increments of the encoder counts between two consecutive readings.
struct TickStep {
  std::int64_t left = 0;
  std::int64_t right = 0;
};

// What one run recorded: the encoder counts (all the robot knows) and the true
// start and end poses (the tape measurements), both at rest.
struct RecordedRun {
  DriveRun run;
  core::Pose2 true_start;
  core::Pose2 true_end;
  int ticks_per_revolution = 0;
  std::vector<TickStep> ticks;  // one per encoder reading after the start
  double duration_s = 0.0;      // simulated time from start to end
};

// The standard runs for `options.runs` = N: N counter-clockwise and N clockwise
// UMBmark squares, N straight runs, N in-place spins and N half circles.
std::vector<DriveRun> StandardCalibrationRuns(const OdometryCalibrationOptions& options);

// Drives one run in a fresh bare-floor world: the robot of `config` (its
// systematic errors and encoder options, lasers left off) settles at the
// origin, then follows the segments by feedback on its nominal-model odometry.
// `run_seed` seeds the encoder noise. Throws std::invalid_argument for bad
// options or speeds the robot cannot reach, std::runtime_error if it gets stuck.
RecordedRun DriveCalibrationRun(const sim::RobotConfig& config, const DriveRun& run,
                                const OdometryCalibrationOptions& options, std::uint64_t run_seed);

// The odometry a model computes for a recorded run, started at the true start
// pose with zero covariance and propagated with eq. 2.13 under `noise`.
core::PoseWithCovariance IntegrateRecordedRun(const RecordedRun& run,
                                              const core::EncoderOdometryOptions& model,
                                              const core::WheelNoise& noise);

// The model of the URDF: nominal radii and wheelbase, and the given k.
core::EncoderOdometryOptions NominalOdometry(const sim::RobotConfig& config);

// The end-pose error true − odometry of a run, expressed in its start frame
// ([x, y, θ], θ wrapped).
Eigen::Vector3d EndPoseError(const RecordedRun& run, const core::Pose2& odometry_end);

// One run of the report.
struct CalibrationRunReport {
  std::string name;
  CalibrationRunKind kind = CalibrationRunKind::kPath;
  double speed_mps = 0.0;
  double wheel_travel_m = 0.0;  // |s_l| + |s_r| summed, nominal model (m)
  double duration_s = 0.0;
  Eigen::Vector3d error_nominal{0, 0, 0};     // true − odometry, start frame, nominal model
  Eigen::Vector3d error_calibrated{0, 0, 0};  // with the calibrated radii and wheelbase
  double mahalanobis_sq = 0.0;  // e_calibratedᵀ P(k̂)⁻¹ e_calibrated (χ² with 3 dof if consistent)
};

struct OdometryCalibrationReport {
  std::string robot;
  OdometryCalibrationOptions options;
  sim::SystematicErrors systematic;  // the simulated robot's (the truth, for comparison)
  bool encoder_noise = false;        // whether the encoders added §2.3 noise
  double encoder_k_left_m = 0.0;     // the encoders' configured k (the truth when noise is on)
  double encoder_k_right_m = 0.0;
  core::EncoderOdometryOptions nominal;     // URDF values (k as configured in robot.yaml)
  core::EncoderOdometryOptions calibrated;  // the result
  core::UmbmarkResult umbmark_one_step;     // Borenstein & Feng's single correction
  core::UmbmarkResult umbmark;              // iterated on the re-integrated runs (final)
  int umbmark_iterations = 0;
  double straight_scale = 1.0;      // true / odometric distance of the straight runs
  double e_max_syst_after_m = 0.0;  // UMBmark's measure with the calibrated model
  double k_m = 0.0;                 // k̂ (= k_L = k_R)
  double k_turn_m = 0.0;            // k̂_turn, the turn-slip term (core::WheelNoise)
  int k_dof = 0;                    // 3 × runs used
  std::vector<CalibrationRunReport> runs;
  double simulated_s = 0.0;
};

// Drives the standard runs and estimates the calibration. Throws as DriveCalibrationRun.
OdometryCalibrationReport CalibrateOdometry(const sim::RobotConfig& config,
                                            const OdometryCalibrationOptions& options);

// Estimates the calibration from recorded runs: the squares give E_d and the
// wheelbase, the straight runs the scale, and every run enters k̂.
OdometryCalibrationReport EstimateCalibration(const sim::RobotConfig& config,
                                              const OdometryCalibrationOptions& options,
                                              const std::vector<RecordedRun>& runs);

const char* RunKindName(CalibrationRunKind kind);

}  // namespace pavilion::scenarios
