#pragma once

// Field-by-field comparison of two robot maps for tests: exact (a file round
// trip) or within the precision a map file prints (a shipped map against a
// fresh derivation).
#include <gtest/gtest.h>

#include <cmath>

#include "core/map/robot_map.h"

namespace pavilion::testing {

struct MapTolerance {
  double position_m = 0.0;      // positions, r, edge weights
  double angle_rad = 0.0;       // alpha, node headings
  double covariance_rel = 0.0;  // relative, as Eigen's isApprox
};

// A map file prints 1 µm, 1 nrad and 6 significant digits (docs/map_format.md).
inline constexpr MapTolerance kMapFilePrecision{2e-6, 2e-9, 1e-5};

inline void ExpectCovarianceNear(const Eigen::Matrix2d& a, const Eigen::Matrix2d& b,
                                 double relative) {
  if (relative == 0.0) {
    EXPECT_EQ(a, b);
  } else {
    EXPECT_TRUE(a.isApprox(b, relative)) << a << "\nvs\n" << b;
  }
}

inline void ExpectSamePoint(const core::Point2Uncertain& a, const core::Point2Uncertain& b,
                            const MapTolerance& tol = {}) {
  EXPECT_LE((a.position_m - b.position_m).norm(), tol.position_m);
  ExpectCovarianceNear(a.covariance, b.covariance, tol.covariance_rel);
}

inline void ExpectSameLine(const core::Line& a, const core::Line& b, const MapTolerance& tol = {}) {
  EXPECT_LE(std::abs(a.alpha_rad - b.alpha_rad), tol.angle_rad);
  EXPECT_LE(std::abs(a.r_m - b.r_m), tol.position_m);
  ExpectCovarianceNear(a.covariance, b.covariance, tol.covariance_rel);
}

inline void ExpectSameMap(const core::RobotMap& a, const core::RobotMap& b,
                          const MapTolerance& tol = {}) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.description, b.description);
  EXPECT_EQ(a.beam_height_m, b.beam_height_m);
  ASSERT_EQ(a.lines.size(), b.lines.size());
  for (std::size_t i = 0; i < a.lines.size(); ++i) {
    EXPECT_EQ(a.lines[i].id, b.lines[i].id);
    ExpectSameLine(a.lines[i].line, b.lines[i].line, tol);
  }
  ASSERT_EQ(a.segments.size(), b.segments.size());
  for (std::size_t i = 0; i < a.segments.size(); ++i) {
    EXPECT_EQ(a.segments[i].id, b.segments[i].id);
    ExpectSameLine(a.segments[i].line, b.segments[i].line, tol);
    ExpectSamePoint(a.segments[i].first_endpoint, b.segments[i].first_endpoint, tol);
    ExpectSamePoint(a.segments[i].second_endpoint, b.segments[i].second_endpoint, tol);
  }
  ASSERT_EQ(a.multi_segment_lines.size(), b.multi_segment_lines.size());
  for (std::size_t i = 0; i < a.multi_segment_lines.size(); ++i) {
    const auto& x = a.multi_segment_lines[i];
    const auto& y = b.multi_segment_lines[i];
    EXPECT_EQ(x.id, y.id);
    ExpectSameLine(x.line, y.line, tol);
    ASSERT_EQ(x.segments.size(), y.segments.size());
    for (std::size_t k = 0; k < x.segments.size(); ++k) {
      ExpectSamePoint(x.segments[k].first, y.segments[k].first, tol);
      ExpectSamePoint(x.segments[k].second, y.segments[k].second, tol);
    }
  }
  ASSERT_EQ(a.points.size(), b.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) {
    EXPECT_EQ(a.points[i].id, b.points[i].id);
    ExpectSamePoint(a.points[i].point, b.points[i].point, tol);
    EXPECT_LE(std::abs(a.points[i].radius_m - b.points[i].radius_m), tol.position_m);
  }
  ASSERT_EQ(a.beacons.size(), b.beacons.size());
  for (std::size_t i = 0; i < a.beacons.size(); ++i) {
    EXPECT_EQ(a.beacons[i].id, b.beacons[i].id);
    ExpectSamePoint(a.beacons[i].point, b.beacons[i].point, tol);
    EXPECT_LE(std::abs(a.beacons[i].radius_m - b.beacons[i].radius_m), tol.position_m);
  }
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    EXPECT_EQ(a.nodes[i].id, b.nodes[i].id);
    EXPECT_EQ(a.nodes[i].station, b.nodes[i].station);
    EXPECT_LE((a.nodes[i].pose.translation() - b.nodes[i].pose.translation()).norm(),
              tol.position_m);
    EXPECT_LE(std::abs(a.nodes[i].pose.theta_rad - b.nodes[i].pose.theta_rad), tol.angle_rad);
  }
  ASSERT_EQ(a.edges.size(), b.edges.size());
  for (std::size_t i = 0; i < a.edges.size(); ++i) {
    EXPECT_EQ(a.edges[i].from, b.edges[i].from);
    EXPECT_EQ(a.edges[i].to, b.edges[i].to);
    EXPECT_LE(std::abs(a.edges[i].weight - b.edges[i].weight), tol.position_m);
  }
  ASSERT_EQ(a.ghost_points.size(), b.ghost_points.size());
  for (std::size_t i = 0; i < a.ghost_points.size(); ++i) {
    EXPECT_EQ(a.ghost_points[i].id, b.ghost_points[i].id);
    EXPECT_LE((a.ghost_points[i].position_m - b.ghost_points[i].position_m).norm(), tol.position_m);
  }
}

}  // namespace pavilion::testing
