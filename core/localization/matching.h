#pragma once

// Matching and iterative integration of the EKF localization cycle (thesis
// §4.4.1.4 and §4.4.2): innovations, the chi^2 validation gate (eq. 4.16), the
// strongest-observation policy for lines, the uniqueness policy for point
// features, and the iterated scheme "match the best pairing, estimate,
// re-predict the features not associated so far".

#include <Eigen/Core>
#include <vector>

#include "core/localization/measurement_prediction.h"
#include "core/localization/observation.h"
#include "core/odometry/diff_drive.h"

namespace pavilion::core {

// The innovation of one pairing.
struct Innovation {
  int dimension = 2;                            // n: 2, or 1 for a vertical edge
  Eigen::Vector2d v = Eigen::Vector2d::Zero();  // z - z^ (eq. 4.11), angles wrapped
  Eigen::Matrix2d S = Eigen::Matrix2d::Zero();  // S_M + R (eq. 4.12)
  double nis = 0.0;                             // v^T S^-1 v, the left side of eq. 4.16
};

// v and S of a prediction and an observation of the same type (rows beyond
// the dimension are zero). For lines the angle difference is wrapped to
// (-pi, pi]; when the observed and predicted normals point more than pi/2
// apart, the observation is taken in its equivalent parameters (alpha + pi, -r)
// (eq. B.4) so that a line through the sensor (r ~ 0, both signs plausible)
// compares correctly. NIS is infinite when S is singular.
Innovation ComputeInnovation(const PredictedMeasurement& prediction,
                             const Observation& observation);

struct MatchingOptions {
  // alpha of the validation gate: a pairing is accepted when its NIS is at most
  // chi^2_{alpha,n} (eq. 4.16). Thesis experiments of §5.7 use alpha = 0.95;
  // in (0, 1).
  double significance = 0.95;
  // Reject pairings of observed segments with map segments and MS-lines that
  // do not contain them (extension constraint, §5.3.2.3). Only acts on map
  // segments/MS-lines and on observations that carry their segments.
  bool use_extension_constraint = true;
  // Vertical edges pair only without ambiguity either way: the prediction has
  // a single observation in its gate and that observation lies in no other
  // prediction's gate, nor in the gate of a mapped edge the camera sees beyond
  // the perception radius (in the field of view, not occluded: never paired,
  // but the image holds it). The thesis (§4.4.2) then also accepted ambiguous
  // candidates by the smallest Mahalanobis distance, and found that door
  // frames' groups of close edges produced false pairings that made vertical
  // edges "of limited utility" (§4.5.3, §4.6); false: the thesis' rule.
  bool unambiguous_vertical_edges = true;

  void Validate() const;  // throws std::invalid_argument naming the field
};

// One accepted pairing.
struct FeatureMatch {
  MapFeatureRef feature;      // the predicted map feature
  int observation_index = 0;  // into the batch's observations
  ObservationType type = ObservationType::kLine;
  Innovation innovation;  // at the state the pairing was integrated into
};

// What one batch produced.
struct MatchingResult {
  int predictions = 0;                // visible predictions (Table 5.3), all types of the batch
  int observations = 0;               // observations in the batch
  std::vector<FeatureMatch> matches;  // in the order they were integrated
};

// Integrates one sensor's observations, all taken at the time `state` refers
// to, into the pose estimate. Observation types are integrated in the order
// lines, beacons, points, vertical edges: "laser observations are integrated
// first since they typically exhibit far better mutual discriminance" (§4.4.2).
// Within a type, pairings are integrated one at a time by their quality: (i)
// match the current best pairing, (ii) estimate (UpdatePoseEstimate), (iii)
// re-predict the features not associated so far — "the iterated Kalman
// filter" of §4.4.2. Each prediction and each observation is used at most once.
// The visible predictions of a type are decided (Table 5.3) once, at the
// state before that type's first update.
//
// The current best pairing:
// - Lines, the strongest observation policy (§4.4.2): "The quality criterion of
//   a pairing is smallest observational uncertainty – not smallest Mahalanobis
//   distance like in the nearest neighbor standard filter. This renders the
//   matching robust against small and possibly spurious segments which yield
//   small Mahalanobis distances." The pairing taken is that of the observation
//   whose R has the smallest determinant, "a measure of its probability mass",
//   among those with a prediction in their validation gate (eq. 4.16, n = 2);
//   among that observation's gated predictions the one with the smallest NIS
//   that passes the extension constraint (if enabled).
// - Beacons, points and vertical edges, uniqueness (§4.4.2): "Predictions with
//   a single observation in their validation gate are picked first and
//   integrated according to their smallest Mahalanobis distance"; "when there
//   is no unique pairing anymore, also candidates with multiple observations in
//   the validation region are accepted and chosen according to the smallest
//   Mahalanobis distance." Vertical edges: see unambiguous_vertical_edges.
//
// Holds scratch buffers: not thread-safe, one per thread.
class IterativeMatcher {
 public:
  explicit IterativeMatcher(const MatchingOptions& options = {});  // validates the options

  // With `correlations` (see map_cross_covariance.h; at the batch's time
  // stamp) predictions and updates account for the pose-map correlation, and
  // the correlations are updated with the state; without, the thesis' filter.
  MatchingResult MatchAndUpdate(const MeasurementPredictor& predictor,
                                const ObservationBatch& batch, PoseWithCovariance* state,
                                PoseMapCrossCovariance* correlations = nullptr);

  const MatchingOptions& options() const { return options_; }

 private:
  struct Candidate {
    int prediction = -1;
    int observation = -1;
    Innovation innovation;
  };
  // Integrates the observations of one type; appends to `result`.
  void IntegrateType(ObservationType type, const MeasurementPredictor& predictor,
                     const ObservationBatch& batch, PoseWithCovariance* state,
                     PoseMapCrossCovariance* correlations, MatchingResult* result);
  bool FindLinePairing(const MeasurementPredictor& predictor, const ObservationBatch& batch,
                       const PoseWithCovariance& state, Candidate* best);
  // Vertical edges with unambiguous_vertical_edges: the map's edges the camera
  // sees beyond the perception radius (field of view, not occluded), which are
  // never paired but make an observation in their gate ambiguous.
  void FindDistractors(ObservationType type, const MeasurementPredictor& predictor,
                       const ObservationBatch& batch, const PoseWithCovariance& state,
                       const PoseMapCrossCovariance* correlations);
  bool FindPointPairing(const ObservationBatch& batch, Candidate* best) const;

  MatchingOptions options_;
  double gate_[3] = {0.0, 0.0, 0.0};  // chi^2_{alpha,n}, n = 1, 2
  std::vector<PredictedMeasurement> predictions_;
  std::vector<PredictedMeasurement> distractors_;  // see FindDistractors
  std::vector<int> observations_;  // batch indices of the current type, in policy order
  std::vector<char> prediction_used_;
  std::vector<char> observation_used_;
  std::vector<Candidate> candidates_;
};

}  // namespace pavilion::core
