#pragma once

// The estimator seam of the robot stack (nav::Navigator): what turns a robot's
// encoder readings and scans into a pose estimate: the EKF pose tracking of
// thesis §4.4 (EkfPoseEstimator), or global localization with the framework of
// chapter 5, Fig. 5.17 (GlobalPoseEstimator).

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/odometry/diff_drive.h"
#include "core/types/sensor_data.h"

namespace pavilion::nav {

// Where the estimator stands in the framework of thesis Fig. 5.17, by n, the
// number of location hypotheses it holds: localized (n = 1: one hypothesis,
// tracked), not localized (n > 1: unresolved location ambiguity) or lost
// (n = 0). The estimator decides from its own data only.
enum class LocalizationMode { kLocalized, kNotLocalized, kLost };

// "localized", "not_localized", "lost" (events.jsonl, localization.csv).
const char* LocalizationModeName(LocalizationMode mode);

// One location hypothesis (thesis eq. 5.62): its estimate and its support.
struct LocationHypothesis {
  core::PoseWithCovariance estimate;  // at the estimator's latest time
  int pairings = 0;                   // p', the non-star pairings of its supporting set
  double joint_mahalanobis = 0.0;     // its goodness of fit (§5.5.2)
};

// What one estimation cycle did (a localization cycle: thesis Fig. 4.2).
struct EstimatorCycle {
  int predictions = 0;   // visible map features
  int observations = 0;  // extracted features
  int matched_lines = 0;
  int matched_beacons = 0;
  int matched_edges = 0;  // a camera's vertical edges (§4.4, Tables 4.1-4.2: n_v)
  int matched_other = 0;
  bool lost = false;  // the estimator declares itself lost
  LocalizationMode mode = LocalizationMode::kLocalized;
  int hypotheses = 1;  // n at the end of the cycle

  // Adds another batch's counts (predictions, observations, matches).
  void AddCounts(const EstimatorCycle& batch) {
    predictions += batch.predictions;
    observations += batch.observations;
    matched_lines += batch.matched_lines;
    matched_beacons += batch.matched_beacons;
    matched_edges += batch.matched_edges;
    matched_other += batch.matched_other;
  }
};

// What a robot's bumpers felt since the stack last told its estimator: a new
// press (at most one per NavigatorOptions::collision_refractory_s) and how long
// the zones stayed pressed, s.
struct BumperContact {
  bool press = false;
  double held_s = 0.0;
  // How far the odometry turned during the collision (from its press, while
  // the zones stay pressed and for NavigatorOptions::collision_refractory_s
  // after the press), rad >= 0: before this report, and since it.
  double turned_before_rad = 0.0;
  double turned_rad = 0.0;
};

// How much a felt collision may have moved the robot beyond what its odometry
// model allows (thesis §4.5.3: the Computer 2000 robot went lost after its
// collisions): a jump at each new press, plus a random walk while pressed, so
// that the added sigma grows with the square root of the time held. x, y and
// theta independent, 1 sigma each. Chosen from the shoves measured in
// expo_day and expo_rush (true motion against odometry across each contact,
// docs/navigation.md): half of all contacts move a Robox by 2 mm or less;
// contacts under 0.15 s move it by at most 4 cm and 7 degrees at the 90th
// percentile, contacts held 0.6 s or more by 5-20 cm and 9-24 degrees. A
// fixed 10 cm and 0.15 rad at every press opened the gates for a brush, and
// the next cycle paired wrongly: 20 of the rush's 41 losses after a brush were
// of robots the brush had moved by 3 mm or less.
//
// A robot that turns while something holds it turns its wheels, not its body:
// expo_rush's robox_15, turning at 57 deg/s, met a visitor (pressed 0.16 s), and
// in the next half second its odometry turned 14 deg while it turned 0.3 deg;
// the press's 4.5 deg did not cover that, and the crowd let it pair nothing
// until it was declared lost. So the odometry's turn during a collision is
// uncertain by turn_slip_fraction of itself, added as one error over the
// collision (its sigma grows linearly with the turn, not with its root).
struct CollisionNoiseOptions {
  double press_sigma_m = 0.02;      // m, >= 0
  double press_sigma_rad = 0.05;    // rad, >= 0
  double hold_sigma_m = 0.10;       // m per square-root second held, >= 0
  double hold_sigma_rad = 0.15;     // rad per square-root second held, >= 0
  double turn_slip_fraction = 1.0;  // sigma per radian the odometry turned, >= 0

  // Throws std::invalid_argument naming `owner` and the field.
  void Validate(const char* owner) const;
  // The covariance `contact` adds to the pose (x, y, theta).
  Eigen::Matrix3d Covariance(const BumperContact& contact) const;
};

class PoseEstimator {
 public:
  virtual ~PoseEstimator() = default;
  // One tick's readings in time order. Returns the cycle when an estimation
  // cycle completed in this tick, none otherwise (odometry only).
  virtual std::optional<EstimatorCycle> Update(
      std::span<const core::EncoderReading> encoders,
      const std::vector<const core::LaserScan*>& scans) = 0;
  // A tick's camera images, before Update with the same tick's readings
  // (which integrates them in time order among the scans). Estimators that
  // use no camera ignore them.
  virtual void AddImages(const std::vector<const core::CameraImage*>& /*images*/) {}
  // The estimate the robot acts on: its only hypothesis when localized, the
  // best one (§5.5.2) otherwise; meaningless when lost.
  virtual const core::PoseWithCovariance& estimate() const = 0;
  virtual LocalizationMode mode() const {
    return lost_reason() == "none" ? LocalizationMode::kLocalized : LocalizationMode::kLost;
  }
  // The hypothesis set, best first (empty when lost).
  virtual std::vector<LocationHypothesis> hypotheses() const {
    if (mode() == LocalizationMode::kLost) return {};
    return {LocationHypothesis{estimate(), 0, 0.0}};
  }
  // How many hypotheses it holds (hypotheses().size(), without copying them).
  virtual std::size_t hypothesis_count() const { return hypotheses().size(); }
  // Why the estimator declares itself lost ("none" while it tracks), for events.
  virtual std::string lost_reason() const = 0;
  // While paused (the navigation near a goal, §6.3.3: "localization gets
  // deactivated") scans are not integrated and the estimator cannot go lost;
  // odometry still moves the estimate. Resuming at `now_s` restarts its lost
  // detection there.
  virtual void SetPaused(bool /*paused*/, double /*now_s*/) {}
  // The bumpers felt a collision: the pose may have moved by more than the
  // odometry model allows (CollisionNoiseOptions).
  virtual void OnContact(const BumperContact& /*contact*/) {}
  // The estimator's own cumulative counts (search sizes, limit hits,
  // falsifications), by name, for the run's metrics; empty when it keeps none.
  virtual std::vector<std::pair<std::string, std::int64_t>> counters() const { return {}; }
};

}  // namespace pavilion::nav
