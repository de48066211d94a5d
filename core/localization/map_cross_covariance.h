#pragma once

// The map's part of the localization error: Cov(pose error, map feature error)
// for the features the filter has used — the "consider" states of a
// Schmidt-Kalman filter.
//
// Why: the thesis adds the map feature's covariance to the innovation
// covariance of every pairing (eq. 4.9, grad h_g M grad h_g^T), as if each
// cycle met a freshly drawn map error. A hand-measured map's error is one
// draw, the same in every cycle: a robot re-observing the same walls 900
// times averages their observation noise away but never their tape-measure
// error, yet the filter, treating that error as independent per cycle,
// shrinks the pose covariance far below the error the map leaves (a pooled
// NEES of about 30 instead of 3 on the office tour with a 5 mm map). Keeping
// the cross-covariance C_j = Cov(e, m_j) of pose error e and each used
// feature's parameter error m_j (lines: (alpha, r) of the supporting line;
// points and beacons: (x, y)) makes the update account for the correlation
// exactly to first order, while the map itself is neither estimated nor
// changed (a prior map stays the reference of every robot; mapping is SLAM's
// job). Map features' errors are independent of each other a priori and stay
// so, because the map estimate is never updated.
//
// The cross-covariances are kept at one time: the latest odometry node
// (Localizer). An odometry step x' = f(x, u) + noise gives C_j' = grad f_x C_j
// (Transform); moving them back to an observation's time stamp inside the
// odometry buffer uses the inverse of the steps' product, which exists since
// every step's Jacobian (eq. 2.11) has determinant 1.

#include <Eigen/Core>
#include <array>
#include <vector>

#include "core/localization/measurement_prediction.h"
#include "core/map/robot_map.h"

namespace pavilion::core {

using PoseMapCross = Eigen::Matrix<double, 3, 2>;

class PoseMapCrossCovariance {
 public:
  // Sized for every feature of `map` (not kept: only the counts are read).
  explicit PoseMapCrossCovariance(const RobotMap& map);

  // Forgets every correlation (a new, map-independent prior: Initialize).
  void Clear();

  // C_j of a feature; zero for features not used since the last Clear().
  const PoseMapCross& Get(MapFeatureRef feature) const;
  void Set(MapFeatureRef feature, const PoseMapCross& cross);

  // C_j <- A C_j for every feature in use: an odometry step's grad f_x, the
  // product of several, or its inverse.
  void Transform(const Eigen::Matrix3d& A);

  // Features with a (possibly) non-zero C_j, in the order they were first used.
  const std::vector<MapFeatureRef>& features() const { return used_; }

 private:
  static int Slot(MapFeatureType type) { return static_cast<int>(type); }

  std::array<std::vector<PoseMapCross>, 5> cross_;  // indexed by MapFeatureType
  std::array<std::vector<char>, 5> in_use_;
  std::vector<MapFeatureRef> used_;
};

}  // namespace pavilion::core
