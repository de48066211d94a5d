#pragma once

// EKF pose tracking with features (thesis chapter 4, §4.4): multi-sensor,
// on-the-fly. The class the rest of the system reads for the robot's pose.

#include <Eigen/Core>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "core/features/beacon_extraction.h"
#include "core/features/line_extraction.h"
#include "core/localization/camera_observations.h"
#include "core/localization/encoder_odometry.h"
#include "core/localization/free_space_constraint.h"
#include "core/localization/map_cross_covariance.h"
#include "core/localization/matching.h"
#include "core/localization/measurement_prediction.h"
#include "core/localization/observation.h"
#include "core/localization/odometry_buffer.h"
#include "core/map/robot_map.h"
#include "core/odometry/diff_drive.h"
#include "core/types/sensor_data.h"

namespace pavilion::core {

// How the Localizer turns one laser's scans into observations.
struct LaserSensorOptions {
  std::string id;  // LaserScan::sensor_id these options apply to
  // R_S, perception radius (eq. 5.47), m; >= 0, 0: the scan's max_range_m.
  double perception_radius_m = 0.0;
  // Phi_S (eq. 5.48), rad; in [0, pi). See SensorView::min_view_angle_rad.
  double min_view_angle_rad = SensorView{}.min_view_angle_rad;
  // P_S, covariance of the mounting pose (eq. 4.9); zero for a SICK (§2.2.2).
  Eigen::Matrix3d robot_from_sensor_covariance = Eigen::Matrix3d::Zero();
  LineExtractionOptions lines = LineExtractionOptions::SickLms200();
  bool extract_beacons = true;  // retro-reflectors (§3.3) as kBeacon observations
  BeaconExtractionOptions beacons;
  // Register the scan into the frame of its first reading before extraction
  // (§2.2.1.4, §4.4.4) when its readings carry different time offsets.
  bool deskew = true;

  void Validate() const;  // throws std::invalid_argument naming the field
};

struct LocalizerOptions {
  EncoderOdometryOptions odometry;  // calibrated radii, wheelbase, k_L, k_R (§2.3)
  // alpha of the validation gate (eq. 4.16) and of the Mahalanobis pre-tests of
  // the visibility (eq. 5.47) and extension (eq. 5.58) constraints; the
  // thesis' experiments use 0.95 (§5.7); in (0, 1).
  double significance = 0.95;
  // Extension constraint for map segments and MS-lines (§5.3.2.3).
  bool use_extension_constraint = true;
  // See PredictionOptions::use_map_line_angle_variance. The thesis (§4.3)
  // neglects it; here true by default: a map line's angle error is as real as
  // its offset error, and with the full (alpha, r) covariance eq. B.16
  // transforms it correctly to first order. Neglecting it made the office
  // tour's heading overconfident.
  bool use_map_line_angle_variance = true;
  // Keep the pose-map cross-covariance of every used map feature (a
  // Schmidt-Kalman filter, map_cross_covariance.h): the map's error is one
  // draw, shared by all cycles, instead of independent per cycle as in eq.
  // 4.9. false: the thesis' filter.
  bool map_correlations = true;
  // How far back odometry is kept: the oldest observation time stamp that can
  // still be integrated, relative to the latest encoder reading, s; > 0.
  double odometry_buffer_s = 2.0;
  // Scans from sensors without an entry in `lasers` use `default_laser`.
  LaserSensorOptions default_laser;
  std::vector<LaserSensorOptions> lasers;  // ids unique
  // Cameras whose images AddImage takes (vertical edges, §3.4, §4.4); ids unique.
  std::vector<CameraSensorOptions> cameras;

  // "Lost" detection. The thesis counts a lost situation when manual
  // relocalization was needed, and saw periods of 5-10 s without any match
  // from which the robot recovered by itself (§4.5.3.1): the timeout lies
  // above those. Lost is sticky until the next Initialize().
  double lost_no_match_timeout_s = 20.0;  // no match for this long, s; > 0
  // ... and over this much wheel travel (the mean of the two wheels' rolled
  // distances) since the match, m; >= 0. Odometry's error grows with the
  // distance the wheels roll (eq. 2.9), not with time: a robot standing or
  // inching among visitors who hide its walls stays where it believes. In
  // expo_rush, Robox that had crept 0.6-2.3 m in 20 s without a match were
  // declared lost 2-4 mm from the truth (σ 4-15 mm), and a lost robot finds
  // no hypothesis in such a crowd for minutes. 5 m: the thesis' robots
  // recovered from 5-10 s without a match (§4.5.3.1) at up to 0.5 m/s. 0:
  // the time alone decides.
  double lost_no_match_travel_m = 5.0;
  // Consecutive failed cycles: at least `min_observations_for_failure`
  // observations and as many visible predictions, but no pairing in any
  // validation gate (the signature of a kidnapped robot); >= 1.
  int lost_failed_cycles = 20;
  int min_observations_for_failure = 3;  // >= 1
  // A failed cycle of a scan counts only when the scan shows the map: at the
  // estimate, at most this fraction of its readings that should meet a mapped
  // wall end short of it — or some see through one (the free-space test of
  // global localization, the mark of a wrong pose). Visitors standing round a
  // robot hide its walls, and their bodies' lines pair with nothing, while it
  // is where it believes (Expo.02's crowds, §6.5); counted, six such cycles
  // declared it lost and sent it to global localization among look-alikes.
  // In [0, 1]; 1: every failed cycle counts (the thesis' rule). Batches
  // without a scan (AddObservations, images) always count.
  double max_short_ratio_for_failure = 0.5;
  // And only when some mapped wall was seen along at least this length, m,
  // by one unbroken run of beams that reached it (FreeSpaceCheck::wall_run_m):
  // a wall the extraction could have found, which keeps a line only when one
  // run of its readings is as long (LineExtractionOptions::min_length_m, eq.
  // 5.15). A crowd leaves gaps; the beams that reach the walls through them
  // may be more than half of those aimed at the map, yet no wall can be
  // extracted from them (expo_rush seed 1, 2,922 s: a robot standing 2.5 cm
  // from its belief saw its walls 3.4-7.7 m away in runs of at most 0.46 m,
  // extracted one spurious line per cycle, declared itself lost, found no
  // hypothesis in the crowd and drifted 1.2 m off). Such a cycle is a hidden
  // failure too. >= 0; 0: any run counts.
  double min_wall_run_for_failure_m = 0.5;
  FreeSpaceOptions failure_free_space;  // the casting of that test
  // A cycle that pairs nothing is matched once more with this added to the
  // pose's covariance at its stamp (world frame x, y, theta), and kept when
  // that pairs at least `slip_min_matches` features. An unmodelled jump the
  // bumpers did not feel — a wheel that slips in a quick reversal of turning,
  // a visitor's shove the crowd hides — leaves the robot close to its
  // prediction but outside the validation gate (eq. 4.16). §4.6 names it as
  // the limit of the data association: each of Computer 2000's 60 collisions
  // lost the robot "although the vehicle was typically close to its pose
  // prediction". computer2000 at 378ac77, 11,067 s, turned 0.67° more
  // than its wheels said with a heading 2σ of 0.17°, failed six cycles and
  // was declared lost 3 mm from the truth. The wider gate still admits only
  // what lies within a few of these sigmas, and the matcher's distractor test
  // (§4.4) refuses an ambiguous pairing, so a kidnap's wrong place stays
  // unpaired. Zero (the thesis' filter): no second match.
  Eigen::Matrix3d slip_covariance = Eigen::Matrix3d::Zero();
  int slip_min_matches = 2;  // >= 1
  // Position uncertainty beyond which tracking is hopeless (the validation
  // gates then admit wrong pairings, Fig. 4.4): largest sigma of (x, y), m; > 0.
  double lost_position_sigma_m = 1.0;

  void Validate() const;  // throws std::invalid_argument naming the field
};

enum class LocalizationState { kUninitialized, kTracking, kLost };
enum class LostReason { kNone, kNoMatchTimeout, kRepeatedGateFailures, kUncertaintyTooLarge };

struct LocalizerStatus {
  LocalizationState state = LocalizationState::kUninitialized;
  LostReason reason = LostReason::kNone;
  double lost_since_s = 0.0;          // when kLost: the time it was detected
  double last_match_s = 0.0;          // stamp of the latest cycle with a match (or of Initialize)
  double travel_since_match_m = 0.0;  // wheel travel since then (lost_no_match_travel_m)
  int consecutive_failed_cycles = 0;
};

// What happened to an observation batch or scan handed to the Localizer.
enum class ObservationStatus {
  kIntegrated,      // matched and estimated at its time stamp, carried forward
  kDeferred,        // waits for odometry to reach it (or behind an earlier deferred item)
  kNotInitialized,  // dropped: Initialize() first
  kTooOld,          // dropped: older than the odometry buffer
  kOutOfOrder,      // dropped: older than an already integrated observation (§4.4.3)
};

// The latest localization cycle (one batch of one sensor).
struct CycleReport {
  std::string sensor_id;
  double stamp_s = 0.0;
  int predictions = 0;                // visible map features
  int observations = 0;               // extracted features
  std::vector<FeatureMatch> matches;  // predicted feature, observation index, innovation, NIS
};

// Cumulative counts since construction.
struct LocalizerCounters {
  long cycles = 0;
  long predictions = 0;
  long observations = 0;
  long matches = 0;
  long deferred = 0;
  long too_old = 0;
  long out_of_order = 0;
  // Cycles without a pairing that did not count towards lost_failed_cycles:
  // their scans' readings ended short of the map (max_short_ratio_for_failure)
  // or reached it in no run long enough to extract (min_wall_run_for_failure_m).
  long hidden_failures = 0;
  // Cycles that paired nothing at first and enough with slip_covariance added.
  long slip_rematches = 0;
};

// EKF pose tracking (§4.4). Odometry from encoder readings predicts the state
// step by step (eqs. 4.6-4.7 with 2.5-2.13) into an odometry buffer; every
// observation batch is matched and estimated at its own time stamp against the
// state predicted for that instant, and the correction is carried forward to
// the present by re-running the buffered odometry steps (§4.4.3). Sensors are
// integrated sequentially in time-stamp order, never as nested filters (§4.4.3),
// so a slow sensor's update cannot overwrite a faster one's. A batch stamped
// after the latest encoder reading waits until odometry reaches its stamp (a
// scan to be registered: its last reading), and later-stamped batches wait
// behind it; one stamped before an already integrated batch is refused
// (kOutOfOrder): callers hand over data in time-stamp order within the
// buffer's latency.
//
// Not copyable or movable (the predictor refers to the owned map).
class Localizer {
 public:
  // Throws std::invalid_argument from options.Validate().
  Localizer(RobotMap map, const LocalizerOptions& options);
  Localizer(const Localizer&) = delete;
  Localizer& operator=(const Localizer&) = delete;

  // Sets the estimate (e.g. from global localization) at the latest encoder
  // time, or at `stamp_s`: a stamp within the odometry buffer is carried forward
  // to the present; one after the latest encoder reading is taken as the
  // latest; an older one throws std::invalid_argument. Resets the lost state.
  void Initialize(const Pose2& world_from_robot, const Eigen::Matrix3d& covariance);
  void Initialize(const Pose2& world_from_robot, const Eigen::Matrix3d& covariance, double stamp_s);

  // One odometry step from cumulative encoder counts (first reading: starts the
  // count). Throws std::invalid_argument for a stamp earlier than the previous
  // reading's or a bad ticks_per_revolution. Integrates deferred batches that
  // the new odometry reaches.
  void AddEncoders(const EncoderReading& reading);

  // Registers (deskew), extracts lines (grouping the pieces of one line,
  // Segment::line_id, into one observation) and beacons, and integrates them.
  ObservationStatus AddScan(const LaserScan& scan);

  // Extracts the vertical edges of a camera's image (§3.4) and integrates
  // their bearings (eq. 4.3) at the image's stamp. Throws
  // std::invalid_argument for a camera without an entry in `cameras` or an
  // image not of its size.
  ObservationStatus AddImage(const CameraImage& image);

  // Integrates already extracted observations (any sensor, e.g. a camera's
  // vertical edges). Throws std::invalid_argument for a bad view, a non-finite
  // observation, or one whose type is not in a non-empty `batch.types`.
  ObservationStatus AddObservations(const ObservationBatch& batch);

  // Suspends lost detection (the navigation paused localization at a goal,
  // §6.3.3: a robot waiting at a station is not lost for having no match), or
  // resumes it at `now_s` with the no-match time and failed cycles afresh.
  void SuspendLostDetection(bool suspended, double now_s);

  // Adds `covariance` (world frame x, y, theta) to the latest pose estimate's:
  // an unmodelled pose jump, such as a collision felt by the bumpers, that the
  // odometry model of §2.3 does not cover (§4.5.3: after a collision the robot
  // was close to its prediction but lost for the validation gate).
  void AddPoseUncertainty(const Eigen::Matrix3d& covariance);

  // The estimate at the latest encoder time stamp_s(). Meaningful once initialized.
  const PoseWithCovariance& estimate() const;
  double stamp_s() const;
  const LocalizerStatus& status() const { return status_; }
  const CycleReport& last_cycle() const { return last_cycle_; }
  const LocalizerCounters& counters() const { return counters_; }
  const RobotMap& map() const { return map_; }
  const LocalizerOptions& options() const { return options_; }
  const OdometryBuffer& odometry_buffer() const { return buffer_; }
  // Whether a cycle of `scan` (registered) that paired nothing at `state`
  // shows a failure: the scan shows the map there (max_short_ratio_for_failure,
  // min_wall_run_for_failure_m); a batch without a scan always does.
  bool FailureShown(const LaserScan* scan, const PoseWithCovariance& state) const;

 private:
  struct Pending {
    double stamp_s = 0.0;  // time of integration (a scan's first reading)
    double ready_s = 0.0;  // odometry must reach this time (a scan's last reading)
    std::optional<LaserScan> scan;
    ObservationBatch batch;
  };

  const LaserSensorOptions& LaserOptions(const std::string& sensor_id) const;
  ObservationStatus ProcessScan(const LaserScan& scan);
  // `scan`: the registered scan the batch was extracted from, if any.
  ObservationStatus Integrate(const ObservationBatch& batch, const LaserScan* scan = nullptr);
  // Matches `batch` at `state` (updated in place) with the correlations, if kept.
  MatchingResult Match(const ObservationBatch& batch, PoseWithCovariance* state);
  // The second match of a cycle that paired nothing (slip_covariance): on
  // success `state` and `result` take its outcome, else both stay untouched.
  void MatchAgainWithSlip(const ObservationBatch& batch, PoseWithCovariance* state,
                          MatchingResult* result);
  // kOutOfOrder, kTooOld, or kIntegrated when the stamp can still be integrated.
  ObservationStatus Admit(double stamp_s) const;
  bool MustWait(double stamp_s, double ready_s) const;
  void Defer(Pending pending);
  void ProcessPending();
  void CheckLost(double now_s);
  bool lost_detection_suspended_ = false;
  void DeclareLost(LostReason reason, double now_s);

  RobotMap map_;
  LocalizerOptions options_;
  MeasurementPredictor predictor_;
  IterativeMatcher matcher_;
  FreeSpaceConstraint free_space_;
  OdometryBuffer buffer_;
  // At the latest odometry node; used when options_.map_correlations.
  PoseMapCrossCovariance correlations_;
  std::optional<EncoderReading> last_encoders_;
  Pose2 dead_reckoning_;  // uncorrected odometry pose
  double last_integrated_s_ = 0.0;
  std::vector<Pending> pending_;  // by stamp_s
  LocalizerStatus status_;
  CycleReport last_cycle_;
  LocalizerCounters counters_;
};

}  // namespace pavilion::core
