#include "scenarios/metrics/robot_proximity.h"

#include <algorithm>
#include <cmath>

#include "core/geometry/segment2.h"
#include "nav/reactive/swept_polygon.h"

namespace pavilion::scenarios {
namespace {

// Relative and absolute slack (m) on the edge boxes' gap against rounding in
// the point-to-segment distances it bounds.
constexpr double kBoxGapSlack = 1e-12;
constexpr double kBoxGapSlackM = 1e-12;

void Place(const core::Polygon2& outline, const core::Pose2& pose, core::Polygon2* out) {
  out->resize(outline.size());
  for (std::size_t i = 0; i < outline.size(); ++i) (*out)[i] = pose * outline[i];
}

// Index of the pair (a, b), a < b, among n robots.
std::size_t PairIndex(int a, int b, int n) { return static_cast<std::size_t>(a * n + b); }

}  // namespace

double ConvexPolygonDistance(const core::Polygon2& a, const core::Polygon2& b) {
  for (const Eigen::Vector2d& v : a) {
    if (core::Contains(b, v)) return 0.0;
  }
  for (const Eigen::Vector2d& v : b) {
    if (core::Contains(a, v)) return 0.0;
  }
  double d = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Eigen::Vector2d& a0 = a[i];
    const Eigen::Vector2d& a1 = a[(i + 1) % a.size()];
    const Eigen::Vector2d a_lo = a0.cwiseMin(a1);
    const Eigen::Vector2d a_hi = a0.cwiseMax(a1);
    for (std::size_t j = 0; j < b.size(); ++j) {
      const Eigen::Vector2d& b0 = b[j];
      const Eigen::Vector2d& b1 = b[(j + 1) % b.size()];
      // Two edges whose boxes lie apart cannot cross, and no point of one is
      // nearer the other than the boxes' gap: beyond the nearest so far
      // (with slack for rounding), the pair cannot change the result.
      const Eigen::Vector2d gap = (b0.cwiseMin(b1) - a_hi).cwiseMax(a_lo - b0.cwiseMax(b1));
      const double box_gap = gap.cwiseMax(0.0).norm();
      if (box_gap > d * (1.0 + kBoxGapSlack) + kBoxGapSlackM) continue;
      if (core::SegmentsCross(a0, a1, b0, b1)) return 0.0;
      d = std::min(
          {d, core::PointSegmentDistance(a0, b0, b1), core::PointSegmentDistance(b0, a0, a1)});
    }
  }
  return d;
}

RobotProximity::RobotProximity(std::vector<core::Polygon2> footprints, double near_m)
    : footprints_(std::move(footprints)),
      near_m_(near_m),
      near_(footprints_.size() * footprints_.size(), 0),
      robots_(footprints_.size()) {
  for (const core::Polygon2& f : footprints_) radii_m_.push_back(nav::Circumradius(f));
}

void RobotProximity::WatchStations(std::vector<Eigen::Vector2d> stations, double radius_m) {
  stations_ = std::move(stations);
  station_shared_.assign(stations_.size(), 0);
  station_radius_m_ = radius_m;
}

void RobotProximity::Update(double dt_s, std::span<const core::Pose2> poses,
                            std::vector<NearMiss>* began, std::vector<StationConflict>* conflicts) {
  const int n = static_cast<int>(footprints_.size());
  for (std::size_t s = 0; s < stations_.size(); ++s) {
    int at = 0;
    for (const core::Pose2& p : poses) {
      at += (p.translation() - stations_[s]).norm() <= station_radius_m_ ? 1 : 0;
    }
    if (at >= 2 && !station_shared_[s]) {
      ++fleet_.station_conflicts;
      if (conflicts) {
        StationConflict c{static_cast<int>(s), {}};
        for (std::size_t k = 0; k < poses.size(); ++k) {
          if ((poses[k].translation() - stations_[s]).norm() <= station_radius_m_) {
            c.robots.push_back(static_cast<int>(k));
          }
        }
        conflicts->push_back(std::move(c));
      }
    }
    station_shared_[s] = at >= 2 ? 1 : 0;
  }
  for (int a = 0; a < n; ++a) {
    for (int b = a + 1; b < n; ++b) {
      const double centres_m = (poses[a].translation() - poses[b].translation()).norm();
      const double bound_m = centres_m - radii_m_[a] - radii_m_[b];
      char& near = near_[PairIndex(a, b, n)];
      // Far apart: neither a new minimum of interest nor near (a lower bound).
      if (bound_m > near_m_ + kNearHysteresisM && !near &&
          bound_m > std::max(robots_[a].min_distance_m, robots_[b].min_distance_m)) {
        continue;
      }
      Place(footprints_[a], poses[a], &scratch_a_);
      Place(footprints_[b], poses[b], &scratch_b_);
      const double d = ConvexPolygonDistance(scratch_a_, scratch_b_);
      for (ProximityFigures* f : {&robots_[a], &robots_[b], &fleet_}) {
        f->min_distance_m = std::min(f->min_distance_m, d);
      }
      if (!near && d < near_m_) {
        near = 1;
        ++robots_[a].near_misses;
        ++robots_[b].near_misses;
        ++fleet_.near_misses;
        began->push_back({a, b, d});
      } else if (near && d > near_m_ + kNearHysteresisM) {
        near = 0;
      }
      if (near) {
        robots_[a].time_near_s += dt_s;
        robots_[b].time_near_s += dt_s;
        fleet_.time_near_s += dt_s;
      }
    }
  }
}

}  // namespace pavilion::scenarios
