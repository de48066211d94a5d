#include "core/localization/map_cross_covariance.h"

#include <stdexcept>

namespace pavilion::core {

PoseMapCrossCovariance::PoseMapCrossCovariance(const RobotMap& map) {
  const std::array<std::size_t, 5> counts = {map.lines.size(), map.segments.size(),
                                             map.multi_segment_lines.size(), map.points.size(),
                                             map.beacons.size()};
  static_assert(static_cast<int>(MapFeatureType::kLine) == 0 &&
                static_cast<int>(MapFeatureType::kSegment) == 1 &&
                static_cast<int>(MapFeatureType::kMultiSegmentLine) == 2 &&
                static_cast<int>(MapFeatureType::kPoint) == 3 &&
                static_cast<int>(MapFeatureType::kBeacon) == 4);
  for (std::size_t t = 0; t < counts.size(); ++t) {
    cross_[t].assign(counts[t], PoseMapCross::Zero());
    in_use_[t].assign(counts[t], 0);
  }
}

void PoseMapCrossCovariance::Clear() {
  for (const MapFeatureRef f : used_) {
    cross_[Slot(f.type)][f.index].setZero();
    in_use_[Slot(f.type)][f.index] = 0;
  }
  used_.clear();
}

const PoseMapCross& PoseMapCrossCovariance::Get(MapFeatureRef feature) const {
  return cross_[Slot(feature.type)].at(feature.index);
}

void PoseMapCrossCovariance::Set(MapFeatureRef feature, const PoseMapCross& cross) {
  char& in_use = in_use_[Slot(feature.type)].at(feature.index);
  if (!in_use) {
    in_use = 1;
    used_.push_back(feature);
  }
  cross_[Slot(feature.type)][feature.index] = cross;
}

void PoseMapCrossCovariance::Transform(const Eigen::Matrix3d& A) {
  for (const MapFeatureRef f : used_) {
    PoseMapCross& c = cross_[Slot(f.type)][f.index];
    c = (A * c).eval();
  }
}

}  // namespace pavilion::core
