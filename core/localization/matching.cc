#include "core/localization/matching.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/localization/ekf_update.h"
#include "core/math/chi_square.h"

namespace pavilion::core {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Integration order of observation types (§4.4.2: laser first).
constexpr ObservationType kTypeOrder[] = {ObservationType::kLine, ObservationType::kBeacon,
                                          ObservationType::kPoint, ObservationType::kVerticalEdge};

double Nis(const Eigen::Vector2d& v, const Eigen::Matrix2d& S, int dimension) {
  if (dimension == 1) return S(0, 0) > 0.0 ? v[0] * v[0] / S(0, 0) : kInfinity;
  const double det = S(0, 0) * S(1, 1) - S(0, 1) * S(1, 0);
  if (!(det > 0.0) || !(S(0, 0) > 0.0)) return kInfinity;
  return (S(1, 1) * v[0] * v[0] - (S(0, 1) + S(1, 0)) * v[0] * v[1] + S(0, 0) * v[1] * v[1]) / det;
}

}  // namespace

Innovation ComputeInnovation(const PredictedMeasurement& prediction,
                             const Observation& observation) {
  if (prediction.type != observation.type) {
    throw std::invalid_argument("ComputeInnovation: prediction and observation types differ");
  }
  Innovation in;
  in.dimension = prediction.dimension();
  switch (prediction.type) {
    case ObservationType::kLine: {
      double d_alpha = NormalizeAngle(observation.z[0] - prediction.z[0]);
      double r = observation.z[1];
      Eigen::Matrix2d R = observation.covariance;
      if (std::abs(d_alpha) > 0.5 * std::numbers::pi) {  // (alpha + pi, -r), eq. B.4
        d_alpha = NormalizeAngle(d_alpha + std::numbers::pi);
        r = -r;
        R(0, 1) = -R(0, 1);
        R(1, 0) = -R(1, 0);
      }
      in.v = {d_alpha, r - prediction.z[1]};
      in.S = prediction.covariance + R;
      break;
    }
    case ObservationType::kVerticalEdge:
      in.v = {NormalizeAngle(observation.z[0] - prediction.z[0]), 0.0};
      in.S.setZero();
      in.S(0, 0) = prediction.covariance(0, 0) + observation.covariance(0, 0);
      break;
    default:
      in.v = observation.z - prediction.z;
      in.S = prediction.covariance + observation.covariance;
      break;
  }
  in.nis = Nis(in.v, in.S, in.dimension);
  return in;
}

void MatchingOptions::Validate() const {
  if (!(std::isfinite(significance) && significance > 0.0 && significance < 1.0)) {
    throw std::invalid_argument("significance must be in (0, 1)");
  }
}

IterativeMatcher::IterativeMatcher(const MatchingOptions& options) : options_(options) {
  options_.Validate();
  gate_[1] = ChiSquareQuantile(options_.significance, 1);
  gate_[2] = ChiSquareQuantile(options_.significance, 2);
}

MatchingResult IterativeMatcher::MatchAndUpdate(const MeasurementPredictor& predictor,
                                                const ObservationBatch& batch,
                                                PoseWithCovariance* state,
                                                PoseMapCrossCovariance* correlations) {
  MatchingResult result;
  result.observations = static_cast<int>(batch.observations.size());
  observation_used_.assign(batch.observations.size(), 0);
  for (const ObservationType type : kTypeOrder) {
    const bool delivered =
        batch.types.empty()
            ? std::any_of(batch.observations.begin(), batch.observations.end(),
                          [type](const Observation& o) { return o.type == type; })
            : std::find(batch.types.begin(), batch.types.end(), type) != batch.types.end();
    if (delivered) IntegrateType(type, predictor, batch, state, correlations, &result);
  }
  return result;
}

void IterativeMatcher::IntegrateType(ObservationType type, const MeasurementPredictor& predictor,
                                     const ObservationBatch& batch, PoseWithCovariance* state,
                                     PoseMapCrossCovariance* correlations, MatchingResult* result) {
  predictions_.clear();
  predictor.PredictVisible(type, *state, batch.view, &predictions_, correlations);
  result->predictions += static_cast<int>(predictions_.size());
  observations_.clear();
  for (int j = 0; j < static_cast<int>(batch.observations.size()); ++j) {
    if (batch.observations[j].type == type) observations_.push_back(j);
  }
  if (predictions_.empty() || observations_.empty()) return;
  if (type == ObservationType::kLine) {  // strongest observation first
    const auto det = [&](int j) {        // |R|, "a measure of its probability mass"
      const Eigen::Matrix2d& R = batch.observations[j].covariance;
      return R(0, 0) * R(1, 1) - R(0, 1) * R(1, 0);
    };
    std::stable_sort(observations_.begin(), observations_.end(),
                     [&](int a, int b) { return det(a) < det(b); });
  }
  prediction_used_.assign(predictions_.size(), 0);
  FindDistractors(type, predictor, batch, *state, correlations);
  bool fresh = true;
  while (true) {
    if (!fresh) {  // (iii) re-prediction of the features not associated so far
      for (std::size_t i = 0; i < predictions_.size(); ++i) {
        if (!prediction_used_[i]) {
          predictions_[i] =
              predictor.Predict(predictions_[i].feature, type, *state, batch.view, correlations);
        }
      }
      for (PredictedMeasurement& d : distractors_) {
        d = predictor.Predict(d.feature, type, *state, batch.view, correlations);
      }
    }
    fresh = false;
    Candidate best;
    const bool found = type == ObservationType::kLine
                           ? FindLinePairing(predictor, batch, *state, &best)
                           : FindPointPairing(batch, &best);
    if (!found) break;  // (i) no pairing left
    const PredictedMeasurement& p = predictions_[best.prediction];
    // N = S - H P H^T: map, mounting and observation terms (the observation's
    // R possibly in its flipped line parameters, see ComputeInnovation).
    const Eigen::Matrix2d N = p.feature_covariance + (best.innovation.S - p.covariance);
    observation_used_[best.observation] = 1;
    prediction_used_[best.prediction] = 1;
    const PairedMapFeature map{p.feature, p.J_z_map, p.map_covariance};
    if (!UpdatePoseEstimate(best.innovation.v, p.J_z_pose, N, best.innovation.dimension, map, state,
                            correlations)) {  // (ii) estimation
      continue;                               // S not positive definite: the pairing is dropped
    }
    result->matches.push_back({p.feature, best.observation, type, best.innovation});
  }
}

bool IterativeMatcher::FindLinePairing(const MeasurementPredictor& predictor,
                                       const ObservationBatch& batch,
                                       const PoseWithCovariance& state, Candidate* best) {
  const double gate = gate_[2];
  for (const int j : observations_) {  // by increasing det(R)
    if (observation_used_[j]) continue;
    const Observation& o = batch.observations[j];
    candidates_.clear();
    for (int i = 0; i < static_cast<int>(predictions_.size()); ++i) {
      if (prediction_used_[i]) continue;
      Innovation in = ComputeInnovation(predictions_[i], o);
      if (in.nis <= gate) candidates_.push_back({i, j, in});  // eq. 4.16
    }
    std::stable_sort(
        candidates_.begin(), candidates_.end(),
        [](const Candidate& a, const Candidate& b) { return a.innovation.nis < b.innovation.nis; });
    for (const Candidate& c : candidates_) {
      if (!options_.use_extension_constraint ||
          predictor.SatisfiesExtensionConstraint(predictions_[c.prediction].feature, o.segments,
                                                 state, batch.view)) {
        *best = c;
        return true;
      }
    }
  }
  return false;
}

void IterativeMatcher::FindDistractors(ObservationType type, const MeasurementPredictor& predictor,
                                       const ObservationBatch& batch,
                                       const PoseWithCovariance& state,
                                       const PoseMapCrossCovariance* correlations) {
  distractors_.clear();
  if (type != ObservationType::kVerticalEdge || !options_.unambiguous_vertical_edges) return;
  SensorView unlimited = batch.view;
  unlimited.perception_radius_m = std::numeric_limits<double>::max();
  predictor.PredictVisible(type, state, unlimited, &distractors_, correlations);
  std::erase_if(distractors_, [&](const PredictedMeasurement& d) {
    return std::any_of(predictions_.begin(), predictions_.end(),
                       [&](const PredictedMeasurement& p) { return p.feature == d.feature; });
  });
}

bool IterativeMatcher::FindPointPairing(const ObservationBatch& batch, Candidate* best) const {
  Candidate unique;
  Candidate any;
  unique.innovation.nis = kInfinity;
  any.innovation.nis = kInfinity;
  const bool strict = options_.unambiguous_vertical_edges && !predictions_.empty() &&
                      predictions_.front().type == ObservationType::kVerticalEdge;
  // How many unused predictions gate each observation (strict mode only).
  // Mapped edges beyond the perception radius count too: the camera sees them.
  std::vector<int> gated_by(strict ? batch.observations.size() : 0, 0);
  const auto count_gated = [&](const PredictedMeasurement& p) {
    for (const int j : observations_) {
      if (!observation_used_[j] &&
          ComputeInnovation(p, batch.observations[j]).nis <= gate_[p.dimension()]) {
        ++gated_by[j];
      }
    }
  };
  for (int i = 0; strict && i < static_cast<int>(predictions_.size()); ++i) {
    if (!prediction_used_[i]) count_gated(predictions_[i]);
  }
  if (strict) std::for_each(distractors_.begin(), distractors_.end(), count_gated);
  for (int i = 0; i < static_cast<int>(predictions_.size()); ++i) {
    if (prediction_used_[i]) continue;
    const double gate = gate_[predictions_[i].dimension()];
    int in_gate = 0;
    Candidate nearest;
    nearest.innovation.nis = kInfinity;
    for (const int j : observations_) {
      if (observation_used_[j]) continue;
      const Innovation in = ComputeInnovation(predictions_[i], batch.observations[j]);
      if (in.nis > gate) continue;  // eq. 4.16
      ++in_gate;
      if (in.nis < nearest.innovation.nis) nearest = {i, j, in};
    }
    if (in_gate == 0) continue;
    const bool mutual = !strict || gated_by[nearest.observation] == 1;
    if (in_gate == 1 && mutual && nearest.innovation.nis < unique.innovation.nis) unique = nearest;
    if (nearest.innovation.nis < any.innovation.nis) any = nearest;
  }
  if (unique.prediction >= 0) {
    *best = unique;
    return true;
  }
  if (!strict && any.prediction >= 0) {
    *best = any;
    return true;
  }
  return false;
}

}  // namespace pavilion::core
