// The invariants of core::RobotMap (thesis §4.3, §6.3.1; eq. B.4 for lines).
#include "core/map/robot_map.h"

#include <gtest/gtest.h>

#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

namespace pavilion::core {
namespace {

Eigen::Matrix2d Cov(double a, double b, double c) {
  Eigen::Matrix2d m;
  m << a, b, b, c;
  return m;
}

// A wall y = 2 seen from below, a column, two nodes and an edge.
RobotMap ValidMap() {
  RobotMap m;
  m.name = "room";
  m.beam_height_m = 0.5;
  const Line wall{std::numbers::pi / 2.0, 2.0, Cov(1e-6, 0, 1e-5)};
  m.segments.push_back(
      {"wall", wall, {{1.0, 2.0}, Cov(1e-5, 0, 1e-5)}, {{-1.0, 2.0}, Cov(1e-5, 0, 1e-5)}});
  m.points.push_back({"column", {{0.0, 1.0}, Cov(1e-5, 0, 1e-5)}, 0.2});
  m.nodes.push_back({"a", {0, 0, 0}, true});
  m.nodes.push_back({"b", {1, 0, 0}, false});
  m.edges.push_back({"a", "b", 1.0});
  return m;
}

// Expects ValidateRobotMap to throw a message containing `part`.
void ExpectInvalid(const RobotMap& map, const std::string& part) {
  try {
    ValidateRobotMap(map);
    ADD_FAILURE() << "accepted; expected: " << part;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

// Positive definite means symmetric, finite, positive diagonal, positive determinant.
TEST(RobotMapTest, PositiveDefiniteCovariances) {
  EXPECT_TRUE(IsPositiveDefinite(Cov(1, 0.5, 1)));
  EXPECT_TRUE(IsPositiveDefinite(Cov(1e-10, 0, 1e-10)));
  EXPECT_FALSE(IsPositiveDefinite(Cov(1, 1, 1)));  // singular
  EXPECT_FALSE(IsPositiveDefinite(Cov(1, 2, 1)));  // indefinite
  EXPECT_FALSE(IsPositiveDefinite(Cov(0, 0, 1)));  // zero variance
  EXPECT_FALSE(IsPositiveDefinite(Cov(-1, 0, -1)));
  Eigen::Matrix2d asymmetric = Cov(1, 0, 1);
  asymmetric(0, 1) = 0.1;
  EXPECT_FALSE(IsPositiveDefinite(asymmetric));
  EXPECT_FALSE(IsPositiveDefinite(Cov(std::numeric_limits<double>::quiet_NaN(), 0, 1)));
}

// The valid map passes; each broken invariant is named.
TEST(RobotMapTest, ValidateNamesTheBrokenInvariant) {
  EXPECT_NO_THROW(ValidateRobotMap(ValidMap()));

  RobotMap m = ValidMap();
  m.segments[0].line.r_m = 0.0;
  ExpectInvalid(m, "segment 'wall': r:");

  m = ValidMap();
  m.segments[0].line.covariance = Cov(1e-6, 1e-5, 1e-5);
  ExpectInvalid(m, "segment 'wall': cov:");

  m = ValidMap();
  m.segments[0].first_endpoint.position_m.y() = 2.01;
  ExpectInvalid(m, "segment 'wall': from:");

  m = ValidMap();
  std::swap(m.segments[0].first_endpoint, m.segments[0].second_endpoint);
  ExpectInvalid(m, "segment 'wall': to:");

  m = ValidMap();
  m.points[0].id = m.segments[0].id;  // "wall" again
  ExpectInvalid(m, "point 'wall': id:");

  m = ValidMap();
  m.points[0].radius_m = -0.1;
  ExpectInvalid(m, "point 'column': radius:");

  m = ValidMap();
  m.edges[0].to = std::string(1, 'c');
  ExpectInvalid(m, "unknown node 'c'");

  m = ValidMap();
  m.edges.push_back({"b", "a", 2.0});
  ExpectInvalid(m, "duplicate edge");

  m = ValidMap();
  m.edges[0].weight = 0.0;
  ExpectInvalid(m, "weight");

  m = ValidMap();
  m.nodes[1].pose.theta_rad = std::numeric_limits<double>::infinity();
  ExpectInvalid(m, "node 'b': pose:");

  m = ValidMap();
  m.segments[0].line.alpha_rad = -std::numbers::pi;  // outside (-pi, pi]
  ExpectInvalid(m, "alpha");
}

}  // namespace
}  // namespace pavilion::core
