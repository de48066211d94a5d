#include "core/localization/localizer.h"

#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

#include "core/localization/scan_observations.h"

namespace pavilion::core {
namespace {

void Require(bool ok, const std::string& field, const char* expected) {
  if (!ok) throw std::invalid_argument(field + " must be " + expected);
}

// Largest standard deviation of the position, sqrt of the largest eigenvalue
// of the 2x2 position block.
double MaxPositionSigma(const Eigen::Matrix3d& P) {
  const double a = P(0, 0);
  const double b = P(0, 1);
  const double c = P(1, 1);
  const double lambda = 0.5 * (a + c) + std::sqrt(0.25 * (a - c) * (a - c) + b * b);
  return std::sqrt(std::max(lambda, 0.0));
}

bool Finite(const Pose2& p) {
  return std::isfinite(p.x_m) && std::isfinite(p.y_m) && std::isfinite(p.theta_rad);
}

}  // namespace

void LaserSensorOptions::Validate() const {
  const std::string prefix = id.empty() ? "" : "lasers[" + id + "].";
  Require(std::isfinite(perception_radius_m) && perception_radius_m >= 0.0,
          prefix + "perception_radius_m", "a finite value >= 0");
  Require(std::isfinite(min_view_angle_rad) && min_view_angle_rad >= 0.0 &&
              min_view_angle_rad < std::numbers::pi,
          prefix + "min_view_angle_rad", "in [0, pi)");
  Require(robot_from_sensor_covariance.allFinite() &&
              robot_from_sensor_covariance.diagonal().minCoeff() >= 0.0 &&
              (robot_from_sensor_covariance - robot_from_sensor_covariance.transpose())
                      .cwiseAbs()
                      .maxCoeff() <= 1e-12,
          prefix + "robot_from_sensor_covariance", "finite and symmetric with a diagonal >= 0");
  try {
    lines.Validate();
    beacons.Validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(prefix + e.what());
  }
}

void LocalizerOptions::Validate() const {
  try {
    odometry.Validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("odometry.") + e.what());
  }
  Require(std::isfinite(significance) && significance > 0.0 && significance < 1.0, "significance",
          "in (0, 1)");
  Require(std::isfinite(odometry_buffer_s) && odometry_buffer_s > 0.0, "odometry_buffer_s",
          "a finite value > 0");
  default_laser.Validate();
  std::set<std::string> ids;
  for (const LaserSensorOptions& laser : lasers) {
    laser.Validate();
    Require(ids.insert(laser.id).second, "lasers[" + laser.id + "].id", "unique");
  }
  ids.clear();
  for (const CameraSensorOptions& camera : cameras) {
    camera.Validate();
    Require(ids.insert(camera.id).second, "cameras[" + camera.id + "].id", "unique");
  }
  Require(std::isfinite(lost_no_match_timeout_s) && lost_no_match_timeout_s > 0.0,
          "lost_no_match_timeout_s", "a finite value > 0");
  Require(std::isfinite(lost_no_match_travel_m) && lost_no_match_travel_m >= 0.0,
          "lost_no_match_travel_m", "a finite value >= 0");
  Require(lost_failed_cycles >= 1, "lost_failed_cycles", "an integer >= 1");
  Require(max_short_ratio_for_failure >= 0.0 && max_short_ratio_for_failure <= 1.0,
          "max_short_ratio_for_failure", "in [0, 1]");
  Require(min_wall_run_for_failure_m >= 0.0, "min_wall_run_for_failure_m", ">= 0");
  try {
    failure_free_space.Validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("failure_free_space.") + e.what());
  }
  Require(min_observations_for_failure >= 1, "min_observations_for_failure", "an integer >= 1");
  Require(slip_covariance.allFinite() && slip_covariance.diagonal().minCoeff() >= 0.0 &&
              (slip_covariance - slip_covariance.transpose()).cwiseAbs().maxCoeff() <= 1e-12,
          "slip_covariance", "finite and symmetric with a diagonal >= 0");
  Require(slip_min_matches >= 1, "slip_min_matches", "an integer >= 1");
  Require(std::isfinite(lost_position_sigma_m) && lost_position_sigma_m > 0.0,
          "lost_position_sigma_m", "a finite value > 0");
}

namespace {

const LocalizerOptions& Validated(const LocalizerOptions& options) {
  options.Validate();
  return options;
}

}  // namespace

Localizer::Localizer(RobotMap map, const LocalizerOptions& options)
    : map_(std::move(map)),
      options_(Validated(options)),
      predictor_(map_,
                 PredictionOptions{options_.significance, options_.use_map_line_angle_variance}),
      matcher_(MatchingOptions{options_.significance, options_.use_extension_constraint}),
      free_space_(map_, options_.failure_free_space),
      buffer_(options_.odometry.wheelbase_m, options_.odometry.noise(), options_.odometry_buffer_s),
      correlations_(map_) {}

void Localizer::Initialize(const Pose2& world_from_robot, const Eigen::Matrix3d& covariance) {
  Initialize(world_from_robot, covariance, buffer_.empty() ? 0.0 : buffer_.latest_stamp_s());
}

void Localizer::Initialize(const Pose2& world_from_robot, const Eigen::Matrix3d& covariance,
                           double stamp_s) {
  Require(Finite(world_from_robot), "Initialize: world_from_robot", "finite");
  Require(covariance.allFinite() && covariance.diagonal().minCoeff() >= 0.0,
          "Initialize: covariance", "finite with a diagonal >= 0");
  Require(std::isfinite(stamp_s), "Initialize: stamp_s", "finite");
  PoseWithCovariance state{world_from_robot, 0.5 * (covariance + covariance.transpose())};
  state.pose.theta_rad = NormalizeAngle(state.pose.theta_rad);
  if (buffer_.empty()) {
    buffer_.Reset(stamp_s, state, dead_reckoning_);
  } else if (stamp_s >= buffer_.latest_stamp_s()) {
    stamp_s = buffer_.latest_stamp_s();
    buffer_.CorrectAt(buffer_.size() - 1, state);
  } else {
    Require(stamp_s >= buffer_.oldest_stamp_s(), "Initialize: stamp_s",
            "within the odometry buffer");
    buffer_.CorrectAt(buffer_.SplitAt(stamp_s), state);
  }
  pending_.clear();
  correlations_.Clear();  // the new prior is independent of the map
  last_integrated_s_ = stamp_s;
  status_ = LocalizerStatus{};
  status_.state = LocalizationState::kTracking;
  status_.last_match_s = stamp_s;
  last_cycle_ = CycleReport{};
}

void Localizer::AddEncoders(const EncoderReading& reading) {
  Require(std::isfinite(reading.stamp_s), "EncoderReading.stamp_s", "finite");
  if (!last_encoders_) {
    Require(reading.ticks_per_revolution > 0, "EncoderReading.ticks_per_revolution", "> 0");
    last_encoders_ = reading;
    if (buffer_.empty()) {
      buffer_.Reset(reading.stamp_s, PoseWithCovariance{dead_reckoning_, Eigen::Matrix3d::Zero()},
                    dead_reckoning_);
    } else if (reading.stamp_s > buffer_.latest_stamp_s()) {
      buffer_.Append(reading.stamp_s, WheelTravel{});  // initialized earlier: standing until now
    }
    return;
  }
  Require(reading.stamp_s >= last_encoders_->stamp_s, "EncoderReading.stamp_s",
          "at or after the previous reading's");
  const WheelTravel travel = WheelTravelFromEncoders(*last_encoders_, reading, options_.odometry);
  last_encoders_ = reading;
  dead_reckoning_ = DiffDriveStep(dead_reckoning_, travel, options_.odometry.wheelbase_m);
  status_.travel_since_match_m += 0.5 * (std::abs(travel.left_m) + std::abs(travel.right_m));
  if (buffer_.empty()) {
    buffer_.Reset(reading.stamp_s, PoseWithCovariance{dead_reckoning_, Eigen::Matrix3d::Zero()},
                  dead_reckoning_);
  } else {
    // An Initialize() stamped after the previous reading moved the buffer's
    // latest time forward; that step then ends at the later of the two.
    buffer_.Append(std::max(reading.stamp_s, buffer_.latest_stamp_s()), travel);
    if (options_.map_correlations && !correlations_.features().empty()) {
      correlations_.Transform(buffer_.Transition(buffer_.size() - 2, buffer_.size() - 1));
    }
  }
  ProcessPending();
  if (status_.state == LocalizationState::kTracking) CheckLost(buffer_.latest_stamp_s());
}

const LaserSensorOptions& Localizer::LaserOptions(const std::string& sensor_id) const {
  for (const LaserSensorOptions& laser : options_.lasers) {
    if (laser.id == sensor_id) return laser;
  }
  return options_.default_laser;
}

ObservationStatus Localizer::Admit(double stamp_s) const {
  if (stamp_s < last_integrated_s_) return ObservationStatus::kOutOfOrder;
  if (stamp_s < buffer_.oldest_stamp_s()) return ObservationStatus::kTooOld;
  return ObservationStatus::kIntegrated;
}

bool Localizer::MustWait(double stamp_s, double ready_s) const {
  // Sequential integration in time-stamp order (§4.4.3): an item waits for
  // odometry to reach it, and behind any earlier-stamped item still waiting.
  return ready_s > buffer_.latest_stamp_s() ||
         (!pending_.empty() && pending_.front().stamp_s <= stamp_s);
}

void Localizer::Defer(Pending pending) {
  ++counters_.deferred;
  const auto at = std::upper_bound(pending_.begin(), pending_.end(), pending.stamp_s,
                                   [](double t, const Pending& p) { return t < p.stamp_s; });
  pending_.insert(at, std::move(pending));
}

void Localizer::ProcessPending() {
  while (!pending_.empty() && pending_.front().ready_s <= buffer_.latest_stamp_s()) {
    Pending p = std::move(pending_.front());
    pending_.erase(pending_.begin());
    const ObservationStatus s = Admit(p.stamp_s);
    if (s == ObservationStatus::kTooOld) ++counters_.too_old;
    if (s == ObservationStatus::kOutOfOrder) ++counters_.out_of_order;
    if (s != ObservationStatus::kIntegrated) continue;
    if (p.scan) {
      ProcessScan(*p.scan);
    } else {
      Integrate(p.batch);
    }
  }
}

ObservationStatus Localizer::AddScan(const LaserScan& scan) {
  if (status_.state == LocalizationState::kUninitialized) {
    return ObservationStatus::kNotInitialized;
  }
  Require(std::isfinite(scan.stamp_s) && std::isfinite(scan.max_range_m) && scan.max_range_m > 0,
          "LaserScan(" + scan.sensor_id + ").stamp_s and max_range_m", "finite, max_range_m > 0");
  Require(Finite(scan.robot_from_sensor), "LaserScan(" + scan.sensor_id + ").robot_from_sensor",
          "finite");
  double first_s = scan.stamp_s;
  double last_s = scan.stamp_s;
  if (!scan.readings.empty()) {
    first_s += scan.readings.front().time_offset_s;
    const bool deskew = LaserOptions(scan.sensor_id).deskew;
    for (const LaserReading& r : scan.readings) {
      Require(std::isfinite(r.time_offset_s) && std::isfinite(r.bearing_rad) &&
                  (!r.valid || std::isfinite(r.range_m)),
              "LaserScan(" + scan.sensor_id + ").readings",
              "finite (time offset, bearing, and range when valid)");
      if (deskew) last_s = std::max(last_s, scan.stamp_s + r.time_offset_s);
    }
  }
  const ObservationStatus s = Admit(first_s);
  if (s == ObservationStatus::kTooOld) ++counters_.too_old;
  if (s == ObservationStatus::kOutOfOrder) ++counters_.out_of_order;
  if (s != ObservationStatus::kIntegrated) return s;
  const double ready_s = std::max(first_s, last_s);
  if (MustWait(first_s, ready_s)) {
    Defer(Pending{first_s, ready_s, scan, {}});
    return ObservationStatus::kDeferred;
  }
  return ProcessScan(scan);
}

ObservationStatus Localizer::ProcessScan(const LaserScan& raw) {
  const LaserSensorOptions& laser = LaserOptions(raw.sensor_id);
  std::optional<LaserScan> scan = RegisterScan(raw, laser, buffer_);
  if (!scan) {
    ++counters_.too_old;
    return ObservationStatus::kTooOld;
  }
  const ObservationStatus admitted = Admit(scan->stamp_s);
  if (admitted != ObservationStatus::kIntegrated) {
    if (admitted == ObservationStatus::kTooOld) ++counters_.too_old;
    if (admitted == ObservationStatus::kOutOfOrder) ++counters_.out_of_order;
    return admitted;
  }
  return Integrate(ScanObservations(*scan, raw, laser), &*scan);
}

ObservationStatus Localizer::AddImage(const CameraImage& image) {
  const auto camera =
      std::find_if(options_.cameras.begin(), options_.cameras.end(),
                   [&](const CameraSensorOptions& c) { return c.id == image.sensor_id; });
  Require(camera != options_.cameras.end(), "CameraImage(" + image.sensor_id + ").sensor_id",
          "a camera of LocalizerOptions::cameras");
  if (status_.state == LocalizationState::kUninitialized) {
    return ObservationStatus::kNotInitialized;
  }
  return AddObservations(EdgeObservations(image, *camera));
}

ObservationStatus Localizer::AddObservations(const ObservationBatch& batch) {
  batch.view.Validate();
  Require(std::isfinite(batch.stamp_s), "ObservationBatch(" + batch.sensor_id + ").stamp_s",
          "finite");
  for (const Observation& o : batch.observations) {
    Require(o.z.allFinite() && o.covariance.allFinite(),
            "ObservationBatch(" + batch.sensor_id + ").observations", "finite");
    Require(batch.types.empty() ||
                std::find(batch.types.begin(), batch.types.end(), o.type) != batch.types.end(),
            "ObservationBatch(" + batch.sensor_id + ").observations",
            "of the types listed in `types`");
  }
  if (status_.state == LocalizationState::kUninitialized) {
    return ObservationStatus::kNotInitialized;
  }
  const ObservationStatus s = Admit(batch.stamp_s);
  if (s == ObservationStatus::kTooOld) ++counters_.too_old;
  if (s == ObservationStatus::kOutOfOrder) ++counters_.out_of_order;
  if (s != ObservationStatus::kIntegrated) return s;
  if (MustWait(batch.stamp_s, batch.stamp_s)) {
    Defer(Pending{batch.stamp_s, batch.stamp_s, std::nullopt, batch});
    return ObservationStatus::kDeferred;
  }
  return Integrate(batch);
}

ObservationStatus Localizer::Integrate(const ObservationBatch& batch, const LaserScan* scan) {
  // The state predicted at the observation's time stamp T (§4.4.3), matched
  // and estimated there, then carried forward to the present.
  const std::size_t at = buffer_.SplitAt(batch.stamp_s);
  const std::size_t now = buffer_.size() - 1;
  PoseWithCovariance state = buffer_.node(at).state;
  // The cross-covariances live at the latest node: back to T through the
  // inverse transition (determinant 1, eq. 2.11), updated with the state,
  // and forward again along the corrected, re-linearized steps.
  if (options_.map_correlations && !correlations_.features().empty()) {
    correlations_.Transform(buffer_.Transition(at, now).inverse());
  }
  MatchingResult result = Match(batch, &state);
  if (result.matches.empty() && status_.state == LocalizationState::kTracking &&
      !options_.slip_covariance.isZero(0.0)) {
    MatchAgainWithSlip(batch, &state, &result);
  }
  if (!result.matches.empty()) buffer_.CorrectAt(at, state);
  if (options_.map_correlations && !correlations_.features().empty()) {
    correlations_.Transform(buffer_.Transition(at, now));
  }
  last_integrated_s_ = batch.stamp_s;

  last_cycle_.sensor_id = batch.sensor_id;
  last_cycle_.stamp_s = batch.stamp_s;
  last_cycle_.predictions = result.predictions;
  last_cycle_.observations = result.observations;
  last_cycle_.matches = std::move(result.matches);
  ++counters_.cycles;
  counters_.predictions += last_cycle_.predictions;
  counters_.observations += last_cycle_.observations;
  counters_.matches += static_cast<long>(last_cycle_.matches.size());

  if (status_.state == LocalizationState::kTracking) {
    if (!last_cycle_.matches.empty()) {
      status_.last_match_s = std::max(status_.last_match_s, batch.stamp_s);
      status_.travel_since_match_m = 0.0;
      status_.consecutive_failed_cycles = 0;
    } else if (last_cycle_.observations >= options_.min_observations_for_failure &&
               last_cycle_.predictions >= options_.min_observations_for_failure) {
      if (FailureShown(scan, state)) {
        ++status_.consecutive_failed_cycles;
      } else {
        ++counters_.hidden_failures;
      }
    }
    CheckLost(buffer_.latest_stamp_s());
  }
  return ObservationStatus::kIntegrated;
}

MatchingResult Localizer::Match(const ObservationBatch& batch, PoseWithCovariance* state) {
  return options_.map_correlations
             ? matcher_.MatchAndUpdate(predictor_, batch, state, &correlations_)
             : matcher_.MatchAndUpdate(predictor_, batch, state);
}

void Localizer::MatchAgainWithSlip(const ObservationBatch& batch, PoseWithCovariance* state,
                                   MatchingResult* result) {
  if (result->observations < options_.slip_min_matches ||
      result->predictions < options_.slip_min_matches) {
    return;
  }
  PoseWithCovariance widened = *state;  // unchanged by a match that paired nothing
  widened.covariance += options_.slip_covariance;
  // A second match that pairs too few is undone, correlations included.
  std::optional<PoseMapCrossCovariance> kept;
  if (options_.map_correlations) kept = correlations_;
  MatchingResult again = Match(batch, &widened);
  if (static_cast<int>(again.matches.size()) >= options_.slip_min_matches) {
    *state = widened;
    *result = std::move(again);
    ++counters_.slip_rematches;
  } else if (kept) {
    correlations_ = std::move(*kept);
  }
}

bool Localizer::FailureShown(const LaserScan* scan, const PoseWithCovariance& state) const {
  if (scan == nullptr || options_.max_short_ratio_for_failure >= 1.0) return true;
  const FreeSpaceCheck check = free_space_.Check(*scan, state, /*count_short=*/true);
  if (!free_space_.Satisfied(check) || check.mapped == 0) return true;
  return check.short_of_map <= options_.max_short_ratio_for_failure * check.mapped &&
         check.wall_run_m >= options_.min_wall_run_for_failure_m;
}

void Localizer::SuspendLostDetection(bool suspended, double now_s) {
  if (lost_detection_suspended_ && !suspended && status_.state == LocalizationState::kTracking) {
    status_.last_match_s = std::max(status_.last_match_s, now_s);
    status_.travel_since_match_m = 0.0;
    status_.consecutive_failed_cycles = 0;
  }
  lost_detection_suspended_ = suspended;
}

void Localizer::AddPoseUncertainty(const Eigen::Matrix3d& covariance) {
  if (buffer_.empty()) return;
  PoseWithCovariance state = buffer_.latest().state;
  state.covariance += covariance;
  buffer_.CorrectAt(buffer_.size() - 1, state);
}

void Localizer::CheckLost(double now_s) {
  if (lost_detection_suspended_) return;
  if (status_.consecutive_failed_cycles >= options_.lost_failed_cycles) {
    DeclareLost(LostReason::kRepeatedGateFailures, now_s);
  } else if (now_s - status_.last_match_s > options_.lost_no_match_timeout_s &&
             status_.travel_since_match_m >= options_.lost_no_match_travel_m) {
    DeclareLost(LostReason::kNoMatchTimeout, now_s);
  } else if (MaxPositionSigma(buffer_.latest().state.covariance) > options_.lost_position_sigma_m) {
    DeclareLost(LostReason::kUncertaintyTooLarge, now_s);
  }
}

void Localizer::DeclareLost(LostReason reason, double now_s) {
  status_.state = LocalizationState::kLost;
  status_.reason = reason;
  status_.lost_since_s = now_s;
}

const PoseWithCovariance& Localizer::estimate() const {
  static const PoseWithCovariance kNone{};
  return buffer_.empty() ? kNone : buffer_.latest().state;
}

double Localizer::stamp_s() const { return buffer_.empty() ? 0.0 : buffer_.latest_stamp_s(); }

}  // namespace pavilion::core
