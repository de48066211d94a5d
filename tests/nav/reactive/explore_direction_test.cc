#include "nav/reactive/explore_direction.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "core/geometry/polygon.h"
#include "tests/support/pygmalion_outline.h"

namespace pavilion::nav {
namespace {

constexpr double kPi = std::numbers::pi;

// A wall of points at x = `at_m`, from y = -half_m to +half_m, every 2 cm.
std::vector<Eigen::Vector2d> WallAhead(double at_m, double half_m) {
  std::vector<Eigen::Vector2d> points;
  for (double y = -half_m; y <= half_m + 1e-9; y += 0.02) points.emplace_back(at_m, y);
  return points;
}

TEST(FreeTravel, StopsWhereTheCorridorsRoundFrontTouchesAPoint) {
  const std::vector<Eigen::Vector2d> one = {{2.0, 0.3}};
  // Half-width 0.5: the disc touches the point 0.4 along before it (3-4-5).
  EXPECT_NEAR(FreeTravel(one, 0.0, 0.5, 3.0), 2.0 - 0.4, 1e-12);
  // Outside the corridor, behind the origin, or beyond the reach: free.
  EXPECT_DOUBLE_EQ(FreeTravel(one, 0.0, 0.25, 3.0), 3.0);
  EXPECT_DOUBLE_EQ(FreeTravel(one, kPi, 0.5, 3.0), 3.0);
  EXPECT_DOUBLE_EQ(FreeTravel(one, 0.0, 0.5, 1.0), 1.0);
  // A point already within the half-width gives no travel at all.
  const std::vector<Eigen::Vector2d> close = {{0.1, 0.0}};
  EXPECT_DOUBLE_EQ(FreeTravel(close, 0.0, 0.5, 3.0), 0.0);
}

// Pygmalion's outline: a 45 cm square, the wheel hubs bulging 4 cm from its
// sides on the wheel axis.
std::vector<Eigen::Vector2d> HubbedSquare() {
  return {{-0.225, -0.225}, {0.0, -0.2665}, {0.225, -0.225},
          {0.225, 0.225},   {0.0, 0.2665},  {-0.225, 0.225}};
}

// A door post's face pressed 1.7 cm into the right hub, its points on both
// sides of the wheel axis (computer2000 seed 1, 34,030 s; as
// DynamicWindowTest.CreepsOffAPostCornerPressingAHubWithAContactSlack).
TEST(StraightPolygonTravel, LetsAHubSlideOffAPostCornerWithinTheContactSlack) {
  const std::vector<Eigen::Vector2d> post = {{-0.021, -0.248}, {-0.007, -0.248}, {0.004, -0.261},
                                             {0.016, -0.259},  {0.039, -0.269},  {0.062, -0.280}};
  const std::vector<Eigen::Vector2d> outline = pavilion::testing::PygmalionWheeledOutline();
  // Inside now: no travel either way.
  EXPECT_DOUBLE_EQ(StraightPolygonTravel(post, outline, false, 0.0, 3.0), 0.0);
  EXPECT_DOUBLE_EQ(StraightPolygonTravel(post, outline, true, 0.0, 3.0), 0.0);
  // With the creep's 4 mm of slack the hub slides on, off the face: the
  // point 1.6 cm beside the wheel axis gets 3.2 mm deeper passing the
  // 16-gon's lowest vertex, the others less.
  EXPECT_DOUBLE_EQ(StraightPolygonTravel(post, outline, false, 0.0, 3.0, 0.004), 3.0);
  // A point 3 cm ahead of the axis and 2 cm inside the hub would pass its
  // vertex 6 mm deeper: it blocks driving on, not backing away from it.
  const std::vector<Eigen::Vector2d> deep = {{0.03, -0.24}};
  EXPECT_DOUBLE_EQ(StraightPolygonTravel(deep, outline, false, 0.0, 3.0, 0.004), 0.0);
  EXPECT_DOUBLE_EQ(StraightPolygonTravel(deep, outline, true, 0.0, 3.0, 0.004), 3.0);
}

TEST(StraightPolygonTravel, LetsAPointBesideTheHubPassWhereTheBoxDoesNot) {
  // A door post 1.8 cm beside the left hub, on either side of it, and a wall
  // 1 m ahead of the origin.
  const std::vector<Eigen::Vector2d> points = {{0.01, 0.2845}, {-0.006, 0.2846}, {1.0, 0.1}};
  const std::vector<Eigen::Vector2d> outline = HubbedSquare();
  // The box of the extents with the 2 cm margin holds the post: no travel
  // either way.
  EXPECT_DOUBLE_EQ(StraightFreeTravel(points, outline, false, 0.02, 3.0), 0.0);
  EXPECT_DOUBLE_EQ(StraightFreeTravel(points, outline, true, 0.02, 3.0), 0.0);
  // The outline grown by 5 mm passes it: on to the wall's 0.225 + 0.005 m
  // before it, back the full reach. With the 2 cm margin the post is inside.
  EXPECT_NEAR(StraightPolygonTravel(points, outline, false, 0.005, 3.0), 1.0 - 0.23, 1e-9);
  EXPECT_DOUBLE_EQ(StraightPolygonTravel(points, outline, true, 0.005, 3.0), 3.0);
  EXPECT_DOUBLE_EQ(StraightPolygonTravel(points, outline, true, 0.02, 3.0), 0.0);
  // A point in front of the hub's edge is met where that edge reaches it.
  const std::vector<Eigen::Vector2d> ahead = {{0.5, 0.24}};
  const double edge_x = 0.225 * (0.2665 - 0.24) / (0.2665 - 0.225);  // edge at y = 0.24
  EXPECT_NEAR(StraightPolygonTravel(ahead, outline, false, 0.0, 3.0), 0.5 - edge_x, 1e-9);
}

TEST(StraightFreeTravel, MeasuresFromTheOutlinesFrontOrRearWithinItsWidth) {
  // A 0.6 m x 0.4 m box robot, its rear 0.2 m behind the origin.
  const std::vector<Eigen::Vector2d> box = {{-0.2, -0.2}, {0.4, -0.2}, {0.4, 0.2}, {-0.2, 0.2}};
  const std::vector<Eigen::Vector2d> ahead = {{1.0, 0.15}};
  EXPECT_NEAR(StraightFreeTravel(ahead, box, false, 0.02, 3.0), 1.0 - 0.42, 1e-12);
  EXPECT_DOUBLE_EQ(StraightFreeTravel(ahead, box, true, 0.02, 3.0), 3.0);  // behind it
  const std::vector<Eigen::Vector2d> behind = {{-1.0, -0.21}};
  EXPECT_NEAR(StraightFreeTravel(behind, box, true, 0.02, 3.0), 1.0 - 0.22, 1e-12);
  // Outside the width grown by the margin: free; beside the robot: blocked.
  EXPECT_DOUBLE_EQ(StraightFreeTravel(behind, box, true, 0.0, 3.0), 3.0);
  const std::vector<Eigen::Vector2d> beside = {{0.1, 0.21}};
  EXPECT_DOUBLE_EQ(StraightFreeTravel(beside, box, false, 0.02, 3.0), 0.0);
}

TEST(ExploreBearing, TurnsAwayFromAWallToTheFreestSide) {
  ExploreOptions options;
  // A wall 1 m ahead, 4 m wide, and a second one 1.5 m to the left: the
  // freest bearing of the fan points right or back, and a tie goes to the
  // smaller turn.
  std::vector<Eigen::Vector2d> points = WallAhead(1.0, 2.0);
  for (double x = -2.0; x <= 2.0; x += 0.02) points.emplace_back(x, 1.5);
  const std::optional<double> bearing = ExploreBearing(points, std::nullopt, 0.45, options);
  ASSERT_TRUE(bearing.has_value());
  EXPECT_LT(*bearing, -kPi / 4.0);  // right of the robot
  EXPECT_GE(FreeTravel(points, *bearing, 0.45, options.reach_m), options.reach_m - 1e-9);
  // Nothing around: straight ahead.
  EXPECT_DOUBLE_EQ(*ExploreBearing({}, std::nullopt, 0.45, options), 0.0);
}

TEST(ExploreBearing, KeepsItsBearingWhileItStaysFree) {
  ExploreOptions options;
  // Open ahead and to the left; the robot already heads left and keeps it,
  // though ahead is as free.
  const std::optional<double> left = ExploreBearing({}, kPi / 2.0, 0.45, options);
  ASSERT_TRUE(left.has_value());
  EXPECT_DOUBLE_EQ(*left, kPi / 2.0);
  // A wall closer than keep_free_m along the current bearing: a new one.
  const std::vector<Eigen::Vector2d> wall = WallAhead(1.2, 0.5);
  const std::optional<double> next = ExploreBearing(wall, 0.0, 0.45, options);
  ASSERT_TRUE(next.has_value());
  EXPECT_GT(std::abs(*next), 0.1);
  EXPECT_GE(FreeTravel(wall, *next, 0.45, options.reach_m), options.keep_free_m);
}

TEST(ExploreBearing, StandsWhenEveryBearingIsShut) {
  ExploreOptions options;
  // A ring of points 0.9 m around the robot: free travel 0.45 m everywhere,
  // less than min_free_m.
  std::vector<Eigen::Vector2d> ring;
  for (int k = 0; k < 360; ++k) {
    const double a = 2.0 * kPi * k / 360.0;
    ring.emplace_back(0.9 * std::cos(a), 0.9 * std::sin(a));
  }
  EXPECT_FALSE(ExploreBearing(ring, std::nullopt, 0.45, options).has_value());
  EXPECT_FALSE(ExploreBearing(ring, 0.0, 0.45, options).has_value());
}

TEST(ExploreOptions, ValidateNamesTheField) {
  ExploreOptions options;
  options.keep_free_m = 0.1;  // below min_free_m
  try {
    options.Validate();
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("keep_free_m"), std::string::npos);
  }
}

}  // namespace
}  // namespace pavilion::nav
