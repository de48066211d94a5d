#include "core/localization/global/location_hypothesis.h"

#include <Eigen/LU>
#include <limits>

namespace pavilion::core {

void AddToLocalMap(const ObservationBatch& batch, LocalMap* local) {
  for (const Observation& o : batch.observations) {
    local->features.push_back(
        LocalFeature{o, batch.view, ObservationConstraintFeature(o, batch.view)});
  }
}

bool BetterHypothesis(const LocationHypothesisData& a, const LocationHypothesisData& b) {
  if (a.pairings != b.pairings) return a.pairings > b.pairings;
  return a.joint_mahalanobis < b.joint_mahalanobis;
}

double HypothesisDistance(const PoseWithCovariance& a, const PoseWithCovariance& b) {
  const Eigen::Vector3d e(a.pose.x_m - b.pose.x_m, a.pose.y_m - b.pose.y_m,
                          NormalizeAngle(a.pose.theta_rad - b.pose.theta_rad));
  const Eigen::Matrix3d sum = a.covariance + b.covariance;
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(sum);
  if (!lu.isInvertible()) return e.isZero() ? 0.0 : std::numeric_limits<double>::infinity();
  return e.dot(lu.solve(e));
}

GlobalMapFeatures MakeGlobalMapFeatures(const RobotMap& map) {
  GlobalMapFeatures g;
  auto add = [&](MapFeatureType type, std::size_t count) {
    for (std::size_t i = 0; i < count; ++i) {
      g.refs.push_back(MapFeatureRef{type, static_cast<int>(i)});
      g.geometry.push_back(MapConstraintFeature(map, type, static_cast<int>(i)));
    }
  };
  add(MapFeatureType::kLine, map.lines.size());
  add(MapFeatureType::kSegment, map.segments.size());
  add(MapFeatureType::kMultiSegmentLine, map.multi_segment_lines.size());
  add(MapFeatureType::kPoint, map.points.size());
  add(MapFeatureType::kBeacon, map.beacons.size());
  return g;
}

}  // namespace pavilion::core
