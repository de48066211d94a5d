#include "core/features/scene_description.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

namespace pavilion::core {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

int IndexOf(const Eigen::Vector2d& p) {
  return static_cast<int>(std::lround(std::atan2(p.y(), p.x()) / (0.5 * kDeg))) + 360;
}

// A segment between two points seen counterclockwise from the origin (p at
// the lower bearing), on its exact supporting line with r >= 0 and the given
// (alpha, r) standard deviations.
Segment SegmentBetween(const Eigen::Vector2d& p, const Eigen::Vector2d& q, double sa = 0.002,
                       double sr = 0.005) {
  const Eigen::Vector2d t = (q - p).normalized();
  Eigen::Vector2d n(-t.y(), t.x());
  double r = n.dot(p);
  if (r < 0.0) {
    n = -n;
    r = -r;
  }
  Line line;
  line.alpha_rad = std::atan2(n.y(), n.x());
  line.r_m = r;
  line.covariance << sa * sa, 0.0, 0.0, sr * sr;
  const int first = IndexOf(p);
  const int last = IndexOf(q);
  return MakeSegment(line, std::atan2(p.y(), p.x()), std::atan2(q.y(), q.x()), 0.0,
                     last - first + 1, first, last);
}

SceneDescription Describe(const std::vector<Segment>& segments, SceneOptions options = {}) {
  return DescribeScene(segments, {}, options);
}

// Concave room corner at (3, 2): walls x = 3 and y = 2, endpoints a little
// short of the corner as the extractor leaves them (eqs. 3.24-3.26, 3.35).
TEST(SceneDescriptionTest, RoomCornerIsConcave) {
  const std::vector<Segment> s = {SegmentBetween({3, -2}, {3, 1.97}),
                                  SegmentBetween({2.97, 2}, {-2, 2})};
  const SceneDescription scene = Describe(s);
  ASSERT_EQ(scene.symbols, "c");
  const SceneSymbol& c = scene.elements[0];
  EXPECT_NEAR(c.intersection_m.x(), 3.0, 1e-9);  // eq. 3.26
  EXPECT_NEAR(c.intersection_m.y(), 2.0, 1e-9);
  EXPECT_EQ(c.lambda_first, -1.0);  // sweep over E_1 heads towards C
  EXPECT_EQ(c.lambda_second, 1.0);  // sweep over E_2 heads away from C
  EXPECT_NEAR(c.direction.x(), 3.0 / std::sqrt(13.0), 1e-9);
  EXPECT_EQ(c.first_segment, 0);
  EXPECT_EQ(c.second_segment, 1);
}

// The corner exactly at the endpoints (d_i = 0) is still a concave corner.
TEST(SceneDescriptionTest, CornerAtEndpointsExactly) {
  const std::vector<Segment> s = {SegmentBetween({3, -2}, {3, 2}), SegmentBetween({3, 2}, {-2, 2})};
  EXPECT_EQ(Describe(s).symbols, "c");
}

// A box corner pointing at the robot (eq. 3.36).
TEST(SceneDescriptionTest, ProtrudingCornerIsConvex) {
  const std::vector<Segment> s = {SegmentBetween({3, -1}, {2.02, -0.02}),
                                  SegmentBetween({2.02, 0.02}, {3, 1})};
  EXPECT_EQ(Describe(s).symbols, "e");
}

// A clockwise scanner sees the mirrored scene in the same order: still "c".
TEST(SceneDescriptionTest, ClockwiseScanMirrors) {
  // Mirror y -> -y of the room corner; scanning clockwise meets x = 3 first.
  std::vector<Segment> s = {SegmentBetween({3, -1.97}, {3, 2}),
                            SegmentBetween({-2, -2}, {2.97, -2})};
  // Reverse each segment's endpoints to the clockwise sweep order.
  for (Segment& seg : s) std::swap(seg.first_endpoint, seg.last_endpoint);
  SceneOptions cw;
  cw.counterclockwise = false;
  EXPECT_EQ(Describe(s, cw).symbols, "c");
}

// A door in a wall: same supporting line (3.16) and d_EE > w_r gives G
// (3.31); a crack narrower than the robot gives no symbol.
TEST(SceneDescriptionTest, GapBetweenCollinearSegments) {
  const std::vector<Segment> door = {SegmentBetween({3, -2}, {3, -0.45}),
                                     SegmentBetween({3, 0.45}, {3, 2})};
  const SceneDescription scene = Describe(door);
  ASSERT_EQ(scene.symbols, "G");
  EXPECT_NEAR(scene.elements[0].location_m.x(), 3.0, 1e-9);
  EXPECT_NEAR(scene.elements[0].location_m.y(), 0.0, 1e-9);
  const std::vector<Segment> crack = {SegmentBetween({3, -2}, {3, -0.1}),
                                      SegmentBetween({3, 0.1}, {3, 2})};
  EXPECT_EQ(Describe(crack).symbols, "");
  // Wider robot: the same door is no longer a gap for it.
  SceneOptions wide;
  wide.robot_size_m = 1.0;
  EXPECT_EQ(Describe(door, wide).symbols, "");
}

// An occluder in front of a wall: the beam jumps from the wall to the box and
// back without passing an intersection, lambda_i = lambda_i+1, so both depth
// jumps are hidden corners (eq. 3.32) - for a parallel box front (C at
// infinity) and for tilted ones (C at a finite point, either side).
TEST(SceneDescriptionTest, OcclusionDepthJumpsAreHiddenCorners) {
  for (double tilt : {0.0, 0.1, -0.1}) {
    const std::vector<Segment> s = {SegmentBetween({4, -3}, {4, -0.6}),
                                    SegmentBetween({2 - 0.5 * tilt, -0.3}, {2 + 0.5 * tilt, 0.3}),
                                    SegmentBetween({4, 0.6}, {4, 3})};
    const SceneDescription scene = Describe(s);
    EXPECT_EQ(scene.symbols, "HH") << "tilt " << tilt;
    if (tilt != 0.0) {
      EXPECT_EQ(scene.elements[0].lambda_first, scene.elements[0].lambda_second);
      EXPECT_TRUE(std::isfinite(scene.elements[0].intersection_m.x()));
    }
  }
}

// A corridor ahead: antiparallel walls meet at infinity, r_C > R_S: opening
// (3.33). Converging walls meeting 20 m ahead: O within R_S = 8 m, an
// aperture (3.34) once R_S exceeds r_C, and O again with lambda_i = 1 ...
TEST(SceneDescriptionTest, OpeningAndAperture) {
  const std::vector<Segment> corridor = {SegmentBetween({0.5, -1}, {5, -1}),
                                         SegmentBetween({5, 1}, {0.5, 1})};
  EXPECT_EQ(Describe(corridor).symbols, "O");

  const double slope = 1.0 / 20.0;  // walls y = -+(1 - x/20) meet at (20, 0)
  const std::vector<Segment> converging = {
      SegmentBetween({0.5, -(1 - 0.5 * slope)}, {5, -(1 - 5 * slope)}),
      SegmentBetween({5, 1 - 5 * slope}, {0.5, 1 - 0.5 * slope})};
  const SceneDescription near_sighted = Describe(converging);
  ASSERT_EQ(near_sighted.symbols, "O");
  EXPECT_NEAR(near_sighted.elements[0].intersection_m.x(), 20.0, 1e-6);
  SceneOptions far;
  far.perception_radius_m = 30.0;
  EXPECT_EQ(Describe(converging, far).symbols, "A");
  // ... and an aperture narrower than the robot is a concave corner (3.35).
  far.robot_size_m = 2.0;
  EXPECT_EQ(Describe(converging, far).symbols, "c");
}

// A closed room seen by a 360-degree scanner: four concave corners, the last
// from the pair (S_4, S_1).
TEST(SceneDescriptionTest, ClosedRoomGivesFourConcaveCorners) {
  const double e = 0.02;
  const std::vector<Segment> s = {
      SegmentBetween({-3 + e, -2}, {3 - e, -2}), SegmentBetween({3, -2 + e}, {3, 2 - e}),
      SegmentBetween({3 - e, 2}, {-3 + e, 2}), SegmentBetween({-3, 2 - e}, {-3, -2 + e})};
  SceneOptions closed;
  closed.closed = true;
  EXPECT_EQ(Describe(s, closed).symbols, "cccc");
  EXPECT_EQ(Describe(s).symbols, "ccc");
}

// Beacons enter the string in angular order (extension 'B').
TEST(SceneDescriptionTest, BeaconsInAngularOrder) {
  const std::vector<Segment> s = {SegmentBetween({3, -2}, {3, 1.97}),
                                  SegmentBetween({2.97, 2}, {-2, 2})};
  Beacon before;
  before.range_m = 3.0;
  before.bearing_rad = -10 * kDeg;
  before.polar_covariance << 1e-4, 0.0, 0.0, 1e-5;
  before.first_index = before.last_index = 340;
  Beacon after = before;
  after.bearing_rad = 80 * kDeg;
  after.first_index = after.last_index = 520;
  const SceneDescription scene = DescribeScene(s, {after, before}, SceneOptions{});
  EXPECT_EQ(scene.symbols, "BcB");
  EXPECT_EQ(scene.elements[0].beacon, 1);
  EXPECT_NEAR(scene.elements[0].determinant, 1e-9, 1e-15);
  EXPECT_NEAR(scene.elements[2].direction.y(), std::sin(80 * kDeg), 1e-9);
  SceneOptions no_beacons;
  no_beacons.include_beacons = false;
  EXPECT_EQ(DescribeScene(s, {before}, no_beacons).symbols, "c");
}

// Eq. 3.37: the pair's determinant is that of the more uncertain line, so the
// weight (confidence) falls when that line gets more uncertain and does not
// depend on the better line; eq. 3.38: a gap depends on l_i only.
TEST(SceneDescriptionTest, WeightsFollowTheMoreUncertainLine) {
  double previous = std::numeric_limits<double>::infinity();
  for (double sr : {0.005, 0.01, 0.02, 0.04}) {
    const std::vector<Segment> s = {SegmentBetween({3, -2}, {3, 1.97}, 0.002, 0.005),
                                    SegmentBetween({2.97, 2}, {-2, 2}, 0.004, sr)};
    const SceneSymbol c = Describe(s).elements.at(0);
    const double expected = std::max(0.002 * 0.002 * 0.005 * 0.005, 0.004 * 0.004 * sr * sr);
    EXPECT_NEAR(c.determinant / expected, 1.0, 1e-9);
    EXPECT_NEAR(c.weight * c.determinant, 1.0, 1e-12);
    EXPECT_LT(c.weight, previous);
    previous = c.weight;
  }
  // The less uncertain line does not change the weight.
  const auto weight_with_first = [](double sa) {
    const std::vector<Segment> s = {SegmentBetween({3, -2}, {3, 1.97}, sa, 0.005),
                                    SegmentBetween({2.97, 2}, {-2, 2}, 0.004, 0.02)};
    return Describe(s).elements.at(0).weight;
  };
  EXPECT_DOUBLE_EQ(weight_with_first(0.001), weight_with_first(0.003));
  // Gap: |C_li| only.
  const auto gap_weight = [](double sa1, double sa2) {
    const std::vector<Segment> s = {SegmentBetween({3, -2}, {3, -0.45}, sa1, 0.005),
                                    SegmentBetween({3, 0.45}, {3, 2}, sa2, 0.005)};
    const SceneDescription scene = Describe(s);
    EXPECT_EQ(scene.symbols, "G");
    return scene.elements.at(0).weight;
  };
  EXPECT_DOUBLE_EQ(gap_weight(0.002, 0.002), gap_weight(0.002, 0.004));
  EXPECT_GT(gap_weight(0.002, 0.002), gap_weight(0.004, 0.002));
}

// Eqs. 3.39-3.40: v_h leans towards the confident symbol, v_l towards the
// uncertain one; with equal weights they coincide.
TEST(SceneDescriptionTest, ConfidenceVectors) {
  const auto scene_with = [](double sr_right) {
    // Corner ahead-left (bearing ~34 deg) from precise walls, and a door in the
    // right wall y = -2 (bearing ~-56 deg) whose first piece has sr_right.
    const std::vector<Segment> s = {SegmentBetween({0.5, -2}, {1.0, -2}, 0.002, sr_right),
                                    SegmentBetween({2.0, -2}, {2.97, -2}, 0.002, sr_right),
                                    SegmentBetween({3, -1.97}, {3, 1.97}, 0.002, 0.005),
                                    SegmentBetween({2.97, 2}, {-2, 2}, 0.002, 0.005)};
    return Describe(s);
  };
  const SceneDescription uncertain_door = scene_with(0.05);
  ASSERT_EQ(uncertain_door.symbols, "Gcc");
  const Eigen::Vector2d door_dir = uncertain_door.elements[0].direction;
  const Eigen::Vector2d corner_dir = uncertain_door.elements[2].direction;
  const Eigen::Vector2d vh = uncertain_door.highest_confidence;
  const Eigen::Vector2d vl = uncertain_door.least_confidence;
  EXPECT_GT(vh.normalized().dot(corner_dir), vl.normalized().dot(corner_dir));
  EXPECT_GT(vl.normalized().dot(door_dir), vh.normalized().dot(door_dir));
  // The gap and the corner next to it share the uncertain line (3.37-3.38).
  EXPECT_LT(uncertain_door.elements[0].weight, uncertain_door.elements[2].weight);
  EXPECT_LT(uncertain_door.elements[1].weight, uncertain_door.elements[2].weight);
  // By hand (3.39-3.40).
  Eigen::Vector2d sum_wv = Eigen::Vector2d::Zero();
  Eigen::Vector2d sum_vw = Eigen::Vector2d::Zero();
  double sw = 0.0;
  double siw = 0.0;
  for (const auto& e : uncertain_door.elements) {
    sum_wv += e.weight * e.direction;
    sum_vw += e.direction / e.weight;
    sw += e.weight;
    siw += 1.0 / e.weight;
  }
  EXPECT_TRUE(vh.isApprox(sum_wv / sw, 1e-12));
  EXPECT_TRUE(vl.isApprox(sum_vw / siw, 1e-12));
  // Equal uncertainty everywhere: v_h = v_l.
  const SceneDescription equal = scene_with(0.005);
  EXPECT_TRUE(equal.highest_confidence.isApprox(equal.least_confidence, 1e-12));
}

TEST(SceneDescriptionTest, ToStringAndEdgeCases) {
  EXPECT_EQ(Describe({}).symbols, "");
  EXPECT_EQ(Describe({SegmentBetween({3, -1}, {3, 1})}).symbols, "");
  const std::vector<Segment> s = {SegmentBetween({3, -2}, {3, 1.97}),
                                  SegmentBetween({2.97, 2}, {-2, 2})};
  const std::string text = Describe(s).ToString();
  EXPECT_NE(text.find("\"c\""), std::string::npos);
  EXPECT_NE(text.find("v_h="), std::string::npos);
  SceneOptions bad;
  bad.perception_radius_m = 0.0;
  EXPECT_THROW(bad.Validate(), std::invalid_argument);
  bad = {};
  bad.significance = 0.0;
  EXPECT_THROW(bad.Validate(), std::invalid_argument);
}

}  // namespace
}  // namespace pavilion::core
