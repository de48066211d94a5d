#pragma once

// The data of global localization (thesis §5.4): the local map of observed
// features, pairings with the global map (the robot's a-priori map), and
// location hypotheses h = (L_h, S_h) (eqs. 5.61-5.62).

#include <span>
#include <vector>

#include "core/localization/global/geometric_constraints.h"
#include "core/localization/measurement_prediction.h"
#include "core/localization/observation.h"
#include "core/odometry/diff_drive.h"

namespace pavilion::core {

// One observed feature of the local map: the observation in its sensor's
// frame, that sensor's view from the robot at the local map's time (the
// mounting pose, possibly compounded with the robot's motion since the
// observation, with that motion's uncertainty as mounting covariance), and its
// constraint geometry in the robot frame.
struct LocalFeature {
  Observation observation;
  SensorView view;
  ConstraintFeature geometry;
};

// The local map L = {l_i} (§5.3): the observations of one or several sensors,
// all relative to the robot at `stamp_s`.
struct LocalMap {
  double stamp_s = 0.0;
  std::vector<LocalFeature> features;
};

// Appends the observations of `batch` to `local`, seen by `batch.view` (whose
// robot_from_sensor must already be relative to the robot at local->stamp_s).
void AddToLocalMap(const ObservationBatch& batch, LocalMap* local);

// A pairing p_ij = {l_i, g_j}: local feature `local` with map feature
// `feature`, or with the star branch (an outlier, §5.4) when `star`.
struct Pairing {
  int local = 0;
  MapFeatureRef feature;
  bool star = true;
};

// A location hypothesis h = (L_h, S_h), eq. 5.62: the robot location L_h at
// the local map's time and the supporting set S_h (one pairing per local
// feature, stars included, in local-feature order).
struct LocationHypothesisData {
  PoseWithCovariance location;
  std::vector<Pairing> support;
  int pairings = 0;                // p': the non-star pairings (§5.5.2)
  double joint_mahalanobis = 0.0;  // sum of the pairings' squared residuals at L_h (§5.5.2)
};

// Scoring of §5.5.2: more paired features first, then the smaller joint
// Mahalanobis distance.
bool BetterHypothesis(const LocationHypothesisData& a, const LocationHypothesisData& b);

// Eq. 5.70: d = (x_i - x_j)^T (P_i + P_j)^-1 (x_i - x_j), heading wrapped.
double HypothesisDistance(const PoseWithCovariance& a, const PoseWithCovariance& b);

// The map's features as the constraints see them, indexed like the map's
// collections (the global map G of §5.3).
struct GlobalMapFeatures {
  std::vector<MapFeatureRef> refs;
  std::vector<ConstraintFeature> geometry;  // parallel to refs
};
GlobalMapFeatures MakeGlobalMapFeatures(const RobotMap& map);

}  // namespace pavilion::core
