#include "core/localization/global/global_localizer.h"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <algorithm>
#include <stdexcept>
#include <utility>

#include "core/localization/ekf_update.h"
#include "core/localization/matching.h"
#include "core/localization/scan_observations.h"

namespace pavilion::core {
namespace {

// A generation whose search hit a limit may have missed the true hypothesis:
// a lone survivor then needs this many more cycles before it counts as
// localized. Chosen: two more seconds of two lasers at 2 Hz.
constexpr int kLimitedExtraCycles = 4;

}  // namespace

int GlobalLocalizer::Hypothesis::WindowPairings() const {
  int sum = 0;
  for (const auto& [own, best] : recent) sum += own;
  return sum;
}

int GlobalLocalizer::Hypothesis::WindowBest() const {
  int sum = 0;
  for (const auto& [own, best] : recent) sum += best;
  return sum;
}

void GlobalLocalizerOptions::Validate() const {
  tracking.Validate();
  tree.Validate();
  if (min_evidence < 1) throw std::invalid_argument("min_evidence must be >= 1");
  if (falsify_failed_cycles < 1) throw std::invalid_argument("falsify_failed_cycles must be >= 1");
  if (support_window < 1) throw std::invalid_argument("support_window must be >= 1");
  if (!(min_support_ratio > 0.0 && min_support_ratio <= 1.0)) {
    throw std::invalid_argument("min_support_ratio must be in (0, 1]");
  }
  if (min_window_support < 1) throw std::invalid_argument("min_window_support must be >= 1");
  if (min_cycles_after_ambiguity < min_cycles_to_localize) {
    throw std::invalid_argument("min_cycles_after_ambiguity must be >= min_cycles_to_localize");
  }
  free_space.Validate();
  if (free_space_failed_cycles < 1) {
    throw std::invalid_argument("free_space_failed_cycles must be >= 1");
  }
  if (!(min_position_sigma_m >= 0.0)) {
    throw std::invalid_argument("min_position_sigma_m must be >= 0");
  }
  if (!(min_heading_sigma_rad >= 0.0)) {
    throw std::invalid_argument("min_heading_sigma_rad must be >= 0");
  }
  if (!(max_localize_position_sigma_m > 0.0)) {
    throw std::invalid_argument("max_localize_position_sigma_m must be > 0");
  }
  if (!(max_localize_heading_sigma_rad > 0.0)) {
    throw std::invalid_argument("max_localize_heading_sigma_rad must be > 0");
  }
  if (min_cycles_to_localize < 0)
    throw std::invalid_argument("min_cycles_to_localize must be >= 0");
  if (!(generation_window_s >= 0.0))
    throw std::invalid_argument("generation_window_s must be >= 0");
  if (!(odometry_span_s > 0.0)) throw std::invalid_argument("odometry_span_s must be > 0");
}

const char* GlobalLostCauseName(GlobalLostCause cause) {
  switch (cause) {
    case GlobalLostCause::kNone:
      return "none";
    case GlobalLostCause::kUnknownStart:
      return "unknown_start";
    case GlobalLostCause::kTrackingLost:
      return "tracking_lost";
    case GlobalLostCause::kNoValidPairings:
      return "no_valid_pairings";
    case GlobalLostCause::kNoHypotheses:
      return "no_hypotheses";
  }
  return "unknown";
}

namespace {
const GlobalLocalizerOptions& Validated(const GlobalLocalizerOptions& options) {
  options.Validate();
  return options;
}
}  // namespace

GlobalLocalizer::GlobalLocalizer(RobotMap map, const GlobalLocalizerOptions& options)
    : map_(std::move(map)),
      options_(Validated(options)),
      predictor_(map_, PredictionOptions{options_.tracking.significance,
                                         options_.tracking.use_map_line_angle_variance}),
      tree_(predictor_, options_.tree),
      free_space_(map_, options_.free_space),
      tracker_(map_, options_.tracking),
      odometry_(options_.tracking.odometry.wheelbase_m, options_.tracking.odometry.noise(),
                options_.odometry_span_s) {}

void GlobalLocalizer::Initialize(const Pose2& world_from_robot, const Eigen::Matrix3d& covariance,
                                 double stamp_s) {
  tracker_.Initialize(world_from_robot, covariance, stamp_s);
  track_.reset();
  hypotheses_.clear();
  state_ = GlobalLocalizationState::kLocalized;
  lost_cause_ = GlobalLostCause::kNone;
}

void GlobalLocalizer::AddEncoders(const EncoderReading& reading) {
  tracker_.AddEncoders(reading);
  if (last_encoders_) {
    const WheelTravel travel =
        WheelTravelFromEncoders(*last_encoders_, reading, options_.tracking.odometry);
    dead_reckoning_ =
        DiffDriveStep(dead_reckoning_, travel, options_.tracking.odometry.wheelbase_m);
    if (track_) {
      *track_ = DiffDriveStepWithCovariance(*track_, travel, options_.tracking.odometry.wheelbase_m,
                                            options_.tracking.odometry.noise());
    }
    odometry_.Append(std::max(reading.stamp_s, odometry_.latest_stamp_s()), travel);
  } else {
    odometry_.Reset(reading.stamp_s, PoseWithCovariance{}, dead_reckoning_);
  }
  last_encoders_ = reading;
  if (state_ == GlobalLocalizationState::kLocalized &&
      tracker_.status().state == LocalizationState::kLost) {
    DeclareLost(GlobalLostCause::kTrackingLost);
  }
}

const LaserSensorOptions& GlobalLocalizer::LaserOptions(const std::string& sensor_id) const {
  for (const LaserSensorOptions& laser : options_.tracking.lasers) {
    if (laser.id == sensor_id) return laser;
  }
  return options_.tracking.default_laser;
}

void GlobalLocalizer::AddScan(const LaserScan& scan) {
  ++cycles_;
  if (state_ == GlobalLocalizationState::kLocalized) {
    tracker_.AddScan(scan);
    if (tracker_.status().state == LocalizationState::kLost) {
      DeclareLost(GlobalLostCause::kTrackingLost);
    }
    return;
  }
  if (odometry_.empty()) return;
  const LaserSensorOptions& laser = LaserOptions(scan.sensor_id);
  const std::optional<LaserScan> registered = RegisterScan(scan, laser, odometry_);
  if (!registered || !odometry_.Covers(registered->stamp_s)) return;
  const ObservationBatch batch = ScanObservations(*registered, scan, laser);
  const auto same =
      std::find_if(latest_batches_.begin(), latest_batches_.end(),
                   [&](const ObservationBatch& b) { return b.sensor_id == batch.sensor_id; });
  if (same != latest_batches_.end()) {
    *same = batch;
  } else {
    latest_batches_.push_back(batch);
  }
  if (state_ == GlobalLocalizationState::kLost) {
    Generate(batch, *registered);
  } else {
    TrackAll(batch, *registered);
  }
}

void GlobalLocalizer::Predict(double stamp_s, Hypothesis* h) {
  if (stamp_s <= h->stamp_s) return;
  const double from_s = std::max(h->stamp_s, odometry_.oldest_stamp_s());
  const std::size_t from = odometry_.SplitAt(from_s);
  const std::size_t to = odometry_.SplitAt(stamp_s);
  const double b = options_.tracking.odometry.wheelbase_m;
  const WheelNoise noise = options_.tracking.odometry.noise();
  for (std::size_t k = from + 1; k <= to; ++k) {  // eqs. 4.6-4.7 per recorded step
    const WheelTravel& travel = odometry_.node(k).travel;
    const Eigen::Matrix3d f = DiffDriveStepJacobians(h->state.pose, travel, b).J_next_pose;
    h->state = DiffDriveStepWithCovariance(h->state, travel, b, noise);
    if (!h->correlations.features().empty()) h->correlations.Transform(f);
  }
  h->stamp_s = stamp_s;
}

PoseWithCovariance GlobalLocalizer::AtLatest(const PoseWithCovariance& at, double stamp_s) const {
  PoseWithCovariance state = at;
  const double b = options_.tracking.odometry.wheelbase_m;
  const WheelNoise noise = options_.tracking.odometry.noise();
  for (std::size_t k = 0; k < odometry_.size(); ++k) {
    const OdometryNode& node = odometry_.node(k);
    if (node.stamp_s <= stamp_s) continue;
    state = DiffDriveStepWithCovariance(state, node.travel, b, noise);
  }
  return state;
}

LocalMap GlobalLocalizer::GenerationMap(const ObservationBatch& batch) const {
  LocalMap local;
  local.stamp_s = batch.stamp_s;
  AddToLocalMap(batch, &local);
  const std::optional<Pose2> now = odometry_.OdometryPoseAt(batch.stamp_s);
  for (const ObservationBatch& other : latest_batches_) {
    if (other.sensor_id == batch.sensor_id || other.stamp_s > batch.stamp_s ||
        batch.stamp_s - other.stamp_s > options_.generation_window_s) {
      continue;
    }
    const std::optional<Pose2> then = odometry_.OdometryPoseAt(other.stamp_s);
    if (!now || !then) continue;
    // The other sensor seen from the robot now: its mount compounded with
    // the motion since, that motion's odometry uncertainty (eq. 2.13 from a
    // certain start) added to the mounting covariance — to first order for
    // the few centimetres of the window.
    PoseWithCovariance motion;
    const double b = options_.tracking.odometry.wheelbase_m;
    for (std::size_t k = 0; k < odometry_.size(); ++k) {
      const OdometryNode& node = odometry_.node(k);
      if (node.stamp_s <= other.stamp_s || node.stamp_s > batch.stamp_s) continue;
      motion =
          DiffDriveStepWithCovariance(motion, node.travel, b, options_.tracking.odometry.noise());
    }
    ObservationBatch moved = other;
    moved.view.robot_from_sensor = (now->Inverse() * *then) * other.view.robot_from_sensor;
    moved.view.robot_from_sensor_covariance += motion.covariance;
    AddToLocalMap(moved, &local);
  }
  return local;
}

void GlobalLocalizer::ApplyCovarianceFloor(Eigen::Matrix3d* covariance) const {
  const double floors[3] = {options_.min_position_sigma_m * options_.min_position_sigma_m,
                            options_.min_position_sigma_m * options_.min_position_sigma_m,
                            options_.min_heading_sigma_rad * options_.min_heading_sigma_rad};
  for (int k = 0; k < 3; ++k) (*covariance)(k, k) = std::max((*covariance)(k, k), floors[k]);
}

bool GlobalLocalizer::SeesThrough(const LaserScan& registered,
                                  const PoseWithCovariance& location) const {
  return options_.use_free_space && !free_space_.Satisfied(free_space_.Check(registered, location));
}

void GlobalLocalizer::Generate(const ObservationBatch& batch, const LaserScan& registered) {
  const LocalMap local = GenerationMap(batch);
  last_search_ = TreeSearchStats{};
  std::vector<LocationHypothesisData> found = tree_.Generate(local, &last_search_);
  const auto contradicted = std::remove_if(found.begin(), found.end(), [&](const auto& f) {
    return SeesThrough(registered, f.location);
  });
  counters_.free_space_rejections += std::distance(contradicted, found.end());
  found.erase(contradicted, found.end());
  ++counters_.generations;
  counters_.tree_nodes += last_search_.nodes;
  counters_.node_limit_hits += last_search_.node_limit_hit ? 1 : 0;
  counters_.hypothesis_limit_hits += last_search_.hypothesis_limit_hit ? 1 : 0;
  if (found.empty() && track_) {
    // The EKF's track resumed (resume_track): at the latest encoder time, a
    // scan period at most after the batch.
    found.push_back(LocationHypothesisData{*track_, {}, 0, 0.0});
    ApplyCovarianceFloor(&found.back().location.covariance);
    track_.reset();
    ++counters_.resumed_tracks;
  }
  if (found.empty()) {
    if (lost_cause_ == GlobalLostCause::kNone) lost_cause_ = GlobalLostCause::kNoHypotheses;
    return;
  }
  hypotheses_.clear();
  for (LocationHypothesisData& f : found) {
    Hypothesis h{f.location,
                 batch.stamp_s,
                 PoseMapCrossCovariance(map_),
                 std::move(f.support),
                 f.pairings,
                 f.joint_mahalanobis,
                 0,
                 0,
                 {}};
    hypotheses_.push_back(std::move(h));
  }
  generation_limited_ = last_search_.node_limit_hit || last_search_.hypothesis_limit_hit;
  ambiguous_ = hypotheses_.size() > 1;
  alone_cycles_ = 0;
  state_ = GlobalLocalizationState::kNotLocalized;
  lost_cause_ = GlobalLostCause::kNone;
  Prune();
}

bool GlobalLocalizer::Verify(const LocalMap& local, Hypothesis* h) const {
  // The EKF estimation of an offspring with its supporting set (§5.5:
  // "the robot locations are estimated ... using their respective supporting
  // set"), strongest observation first (§4.4.2); a pairing that leaves the
  // gate at the updated location is moved to the star branch (joint
  // compatibility, §5.3.2.1).
  std::vector<int> order;
  for (const Pairing& p : h->support) {
    if (!p.star) order.push_back(p.local);
  }
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    return local.features[static_cast<std::size_t>(a)].observation.covariance.determinant() <
           local.features[static_cast<std::size_t>(b)].observation.covariance.determinant();
  });
  h->pairings = 0;
  h->joint_mahalanobis = 0.0;
  for (const int i : order) {
    Pairing& pairing = h->support[static_cast<std::size_t>(i)];
    const LocalFeature& l = local.features[static_cast<std::size_t>(i)];
    const PredictedMeasurement p =
        predictor_.Predict(pairing.feature, l.observation.type, h->state, l.view, &h->correlations);
    const Innovation innovation = ComputeInnovation(p, l.observation);
    const Eigen::Matrix2d n = p.feature_covariance + (innovation.S - p.covariance);
    const PairedMapFeature feature{p.feature, p.J_z_map, p.map_covariance};
    if (!(innovation.nis <= tree_.gate(innovation.dimension)) ||
        !UpdatePoseEstimate(innovation.v, p.J_z_pose, n, innovation.dimension, feature, &h->state,
                            &h->correlations)) {
      pairing.star = true;
      continue;
    }
    ++h->pairings;
    h->joint_mahalanobis += innovation.nis;
  }
  return true;
}

std::vector<GlobalLocalizer::Hypothesis> GlobalLocalizer::TrackOne(const LocalMap& local,
                                                                   const LaserScan& registered,
                                                                   Hypothesis& h, bool may_split) {
  TreeSearchStats stats;
  std::vector<LocationHypothesisData> sets = tree_.Track(local, h.state, &h.correlations, &stats);
  counters_.tree_nodes += stats.nodes;
  counters_.node_limit_hits += stats.node_limit_hit ? 1 : 0;
  counters_.hypothesis_limit_hits += stats.hypothesis_limit_hit ? 1 : 0;
  std::vector<Hypothesis> offspring;
  for (LocationHypothesisData& set : sets) {
    Hypothesis o = h;
    o.support = std::move(set.support);
    Verify(local, &o);
    offspring.push_back(std::move(o));
  }
  std::stable_sort(offspring.begin(), offspring.end(),
                   [](const Hypothesis& a, const Hypothesis& b) {
                     if (a.pairings != b.pairings) return a.pairings > b.pairings;
                     return a.joint_mahalanobis < b.joint_mahalanobis;
                   });
  // Only the best hypothesis may split (§5.6); the others are confirmed or
  // falsified by their best offspring.
  if (!may_split && offspring.size() > 1) offspring.erase(offspring.begin() + 1, offspring.end());
  if (offspring.size() > 1) ++counters_.splits;
  // Failed: no valid pairing although the robot observes something (§5.7.1:
  // "no valid pairings ... yielding zero hypotheses"). Whether the hypothesis
  // predicts anything visible does not matter: one that predicts nothing
  // where the robot sees walls (carried off the map by odometry) is
  // contradicted as much as one whose predictions fail the gates.
  const bool evidence = static_cast<int>(local.features.size()) >= options_.min_evidence;
  for (Hypothesis& o : offspring) {
    if (o.pairings > 0) {
      o.failed_cycles = 0;
    } else if (evidence &&
               (!options_.hidden_failures_spare || tracker_.FailureShown(&registered, o.state))) {
      o.failed_cycles = h.failed_cycles + 1;
    }
  }
  return offspring;
}

void GlobalLocalizer::TrackAll(const ObservationBatch& batch, const LaserScan& registered) {
  LocalMap local;
  local.stamp_s = batch.stamp_s;
  AddToLocalMap(batch, &local);
  std::vector<Hypothesis> next;
  for (std::size_t i = 0; i < hypotheses_.size(); ++i) {
    Predict(batch.stamp_s, &hypotheses_[i]);
    ApplyCovarianceFloor(&hypotheses_[i].state.covariance);
    std::vector<Hypothesis> offspring = TrackOne(local, registered, hypotheses_[i], i == 0);
    for (Hypothesis& o : offspring) {
      o.see_through_cycles = SeesThrough(registered, o.state) ? o.see_through_cycles + 1 : 0;
      next.push_back(std::move(o));
    }
  }
  ++counters_.tracking_cycles;
  int best = 0;
  for (const Hypothesis& h : next) best = std::max(best, h.pairings);
  for (Hypothesis& h : next) {
    h.recent.emplace_back(h.pairings, best);
    if (static_cast<int>(h.recent.size()) > options_.support_window)
      h.recent.erase(h.recent.begin());
  }
  hypotheses_ = std::move(next);
  Prune();
  if (hypotheses_.empty()) {
    DeclareLost(GlobalLostCause::kNoValidPairings);
    return;
  }
  if (hypotheses_.size() > 1) {
    ambiguous_ = true;
    alone_cycles_ = 0;
    return;
  }
  // Counted only when this cycle confirmed it (§5.5: verification, |H_t| = 1
  // with a supporting set): a hypothesis carried by odometry alone — the
  // wheels slipping against an obstacle the laser does not see — is not
  // evidence.
  if (hypotheses_.front().pairings < options_.tree.min_pairings) return;
  ++alone_cycles_;
  const int needed =
      (ambiguous_ ? options_.min_cycles_after_ambiguity : options_.min_cycles_to_localize) +
      (generation_limited_ ? kLimitedExtraCycles : 0);
  if (alone_cycles_ >= needed && Determined(hypotheses_.front().state.covariance)) {
    Localize(hypotheses_.front());
  }
}

bool GlobalLocalizer::Determined(const Eigen::Matrix3d& covariance) const {
  const double position_variance =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(covariance.topLeftCorner<2, 2>())
          .eigenvalues()
          .maxCoeff();
  const double position_sigma = options_.max_localize_position_sigma_m;
  const double heading_sigma = options_.max_localize_heading_sigma_rad;
  return position_variance <= position_sigma * position_sigma &&
         covariance(2, 2) <= heading_sigma * heading_sigma;
}

// Falsification, ranking and duplicate removal (eqs. 5.70-5.71).
void GlobalLocalizer::Prune() {
  const std::size_t before = hypotheses_.size();
  std::erase_if(hypotheses_, [&](const Hypothesis& h) {
    if (h.see_through_cycles >= options_.free_space_failed_cycles) {
      ++counters_.free_space_falsified;
      return true;
    }
    return h.failed_cycles >= options_.falsify_failed_cycles ||
           (h.WindowBest() >= options_.min_window_support &&
            h.WindowPairings() < options_.min_support_ratio * h.WindowBest());
  });
  counters_.falsified += static_cast<long>(before - hypotheses_.size());
  // Rank: the most pairings over the window, then §5.5.2 on this cycle.
  std::stable_sort(hypotheses_.begin(), hypotheses_.end(),
                   [](const Hypothesis& a, const Hypothesis& b) {
                     if (a.WindowPairings() != b.WindowPairings()) {
                       return a.WindowPairings() > b.WindowPairings();
                     }
                     if (a.pairings != b.pairings) return a.pairings > b.pairings;
                     return a.joint_mahalanobis < b.joint_mahalanobis;
                   });
  std::vector<Hypothesis> kept;
  for (Hypothesis& h : hypotheses_) {
    const bool duplicate = std::any_of(kept.begin(), kept.end(), [&](const Hypothesis& k) {
      return HypothesisDistance(k.state, h.state) < tree_.gate(3);
    });
    if (duplicate) {
      ++counters_.duplicates;
      continue;
    }
    if (static_cast<int>(kept.size()) >= options_.tree.max_hypotheses) {
      ++counters_.hypothesis_limit_hits;
      break;
    }
    kept.push_back(std::move(h));
  }
  hypotheses_ = std::move(kept);
}

void GlobalLocalizer::DeclareLost(GlobalLostCause cause) {
  if (options_.resume_track && state_ == GlobalLocalizationState::kLocalized) {
    track_ = tracker_.estimate();  // at the latest encoder time
  }
  lost_estimate_ = Estimate();
  lost_estimate_stamp_s_ = odometry_.empty() ? 0.0 : odometry_.latest_stamp_s();
  state_ = GlobalLocalizationState::kLost;
  lost_cause_ = cause;
  last_loss_cause_ = cause;
  last_tracking_reason_ = tracker_.status().reason;
  hypotheses_.clear();
  latest_batches_.clear();
  ++counters_.losses;
}

void GlobalLocalizer::Localize(const Hypothesis& h) {
  track_.reset();
  tracker_.Initialize(h.state.pose, h.state.covariance, h.stamp_s);
  hypotheses_.clear();
  state_ = GlobalLocalizationState::kLocalized;
  lost_cause_ = GlobalLostCause::kNone;
  ++counters_.localizations;
}

void GlobalLocalizer::SuspendLostDetection(bool suspended, double now_s) {
  tracker_.SuspendLostDetection(suspended, now_s);
}

void GlobalLocalizer::AddPoseUncertainty(const Eigen::Matrix3d& covariance) {
  if (state_ == GlobalLocalizationState::kLocalized) tracker_.AddPoseUncertainty(covariance);
  for (Hypothesis& h : hypotheses_) h.state.covariance += covariance;
}

int GlobalLocalizer::hypothesis_count() const {
  if (state_ == GlobalLocalizationState::kLocalized) return 1;
  return static_cast<int>(hypotheses_.size());
}

std::vector<LocationHypothesisData> GlobalLocalizer::Hypotheses() const {
  std::vector<LocationHypothesisData> out;
  if (state_ == GlobalLocalizationState::kLocalized) {
    out.push_back(LocationHypothesisData{tracker_.estimate(), {}, 0, 0.0});
    return out;
  }
  for (const Hypothesis& h : hypotheses_) {
    out.push_back(LocationHypothesisData{AtLatest(h.state, h.stamp_s), h.support, h.pairings,
                                         h.joint_mahalanobis});
  }
  return out;
}

PoseWithCovariance GlobalLocalizer::Estimate() const {
  if (state_ == GlobalLocalizationState::kLocalized) return tracker_.estimate();
  if (!hypotheses_.empty()) return AtLatest(hypotheses_.front().state, hypotheses_.front().stamp_s);
  return AtLatest(lost_estimate_, lost_estimate_stamp_s_);  // lost: carried by odometry
}

}  // namespace pavilion::core
