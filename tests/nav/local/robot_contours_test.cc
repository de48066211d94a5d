// Robots seeing robots (nav/local/robot_contours.h, thesis §6.3.5.1): markers
// from the reflector flag, the implied centre behind them, the contour of
// ghost points, markers explained by known poses, and the hull clipping of
// the §6.5 deadlock resolution.
#include "nav/local/robot_contours.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/types/pose2.h"
#include "core/types/sensor_data.h"
#include "nav/local/scan_obstacles.h"

namespace pavilion::nav {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kResolutionRad = 0.5 * kPi / 180.0;  // SICK LMS 200, 0.5° steps
constexpr double kWallM = 5.0;                        // range of the plain readings
constexpr double kExact = 1e-9;                       // the synthetic readings carry no noise

// A 180° scan of plain readings at kWallM, from a laser mounted at `mount`.
core::LaserScan Scan(const core::Pose2& mount) {
  core::LaserScan scan;
  scan.robot_from_sensor = mount;
  for (int i = 0; i <= 360; ++i) {
    core::LaserReading r;
    r.bearing_rad = -kPi / 2.0 + i * kResolutionRad;
    r.range_m = kWallM;
    r.valid = true;
    scan.readings.push_back(r);
  }
  return scan;
}

// Flags the 2 * half + 1 readings centred on reading `centre` as a reflector
// at `range_m`: a marker seen at that reading's bearing.
void AddMarker(core::LaserScan* scan, int centre, int half, double range_m) {
  for (int i = centre - half; i <= centre + half; ++i) {
    scan->readings[i].range_m = range_m;
    scan->readings[i].reflector = true;
  }
}

// An axis-aligned square footprint of half width `half_m`, counter-clockwise.
std::vector<Eigen::Vector2d> Square(double half_m) {
  return {{-half_m, -half_m}, {half_m, -half_m}, {half_m, half_m}, {-half_m, half_m}};
}

// A marker at bearing 30° and 2 m from a rear-facing laser is placed through
// the mount, and the centre lies marker_offset_m farther along the sight line.
TEST(RobotContoursTest, SeesMarkerAndCentreBehindIt) {
  const core::Pose2 mount{-0.05, 0.0, kPi};  // rear laser, 5 cm behind the centre
  core::LaserScan scan = Scan(mount);
  AddMarker(&scan, 180 + 60, 2, 2.0);  // reading 240: bearing 30°
  const RobotContourOptions options;
  const std::vector<SeenRobot> seen = SeeRobots(scan, options);
  ASSERT_EQ(seen.size(), 1u);
  const double sight = kPi + kPi / 6.0;  // 30° in the laser, turned by the mount
  const Eigen::Vector2d dir(std::cos(sight), std::sin(sight));
  const Eigen::Vector2d marker = Eigen::Vector2d(-0.05, 0.0) + 2.0 * dir;
  EXPECT_NEAR((seen[0].marker_in_robot - marker).norm(), 0.0, kExact);
  EXPECT_NEAR((seen[0].centre_in_robot - (marker + 0.34 * dir)).norm(), 0.0, kExact);
  // The centre is 0.34 m behind the marker and farther from the laser.
  EXPECT_NEAR((seen[0].centre_in_robot - seen[0].marker_in_robot).norm(), 0.34, kExact);
}

// Two markers give two robots in scan order; one beyond max_range_m none.
TEST(RobotContoursTest, SeesEveryMarkerWithinRange) {
  core::LaserScan scan = Scan(core::Pose2{0.05, 0.0, 0.0});
  AddMarker(&scan, 100, 1, 1.5);
  AddMarker(&scan, 200, 1, 3.0);
  AddMarker(&scan, 300, 1, 7.0);  // beyond the default 6 m
  const std::vector<SeenRobot> seen = SeeRobots(scan, RobotContourOptions{});
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_NEAR((seen[0].marker_in_robot - Eigen::Vector2d(0.05, 0.0)).norm(), 1.5, kExact);
  EXPECT_NEAR((seen[1].marker_in_robot - Eigen::Vector2d(0.05, 0.0)).norm(), 3.0, kExact);
  EXPECT_TRUE(SeeRobots(Scan(core::Pose2{}), RobotContourOptions{}).empty());
}

// A robot seen head-on shows both markers, 0.68 m apart: its centre is
// their midpoint (where the robot is), not 0.34 m behind either. A third
// marker nowhere near them keeps its centre behind it; with pairing off,
// every centre is behind its marker.
TEST(RobotContoursTest, APairOfMarkersPlacesTheRobotBetweenThem) {
  const core::Pose2 mount{0.0, 0.0, 0.0};
  core::LaserScan scan = Scan(mount);
  // The other robot 2 m ahead, facing this one: markers at (2, +-0.34).
  const double half_rad = std::atan2(0.34, 2.0);
  const double range_m = std::hypot(2.0, 0.34);
  const int left = 180 + static_cast<int>(std::lround(half_rad / kResolutionRad));
  const int right = 180 - static_cast<int>(std::lround(half_rad / kResolutionRad));
  AddMarker(&scan, left, 1, range_m);
  AddMarker(&scan, right, 1, range_m);
  AddMarker(&scan, 30, 1, 2.5);  // another robot's single marker, far to the right
  RobotContourOptions options;
  const std::vector<SeenRobot> seen = SeeRobots(scan, options);
  ASSERT_EQ(seen.size(), 3u);
  // In scan order: the far one, then the pair (right, left).
  const Eigen::Vector2d between = 0.5 * (seen[1].marker_in_robot + seen[2].marker_in_robot);
  EXPECT_NEAR(between.x(), 2.0, 0.01);
  EXPECT_NEAR(between.y(), 0.0, 0.01);
  EXPECT_NEAR((seen[1].centre_in_robot - between).norm(), 0.0, kExact);
  EXPECT_NEAR((seen[2].centre_in_robot - between).norm(), 0.0, kExact);
  EXPECT_NEAR((seen[0].centre_in_robot - seen[0].marker_in_robot).norm(), 0.34, kExact);
  EXPECT_GT(seen[0].centre_in_robot.norm(), seen[0].marker_in_robot.norm());
  options.pair_tolerance_m = 0.0;
  for (const SeenRobot& r : SeeRobots(scan, options)) {
    EXPECT_NEAR((r.centre_in_robot - r.marker_in_robot).norm(), 0.34, kExact);
  }
}

// Three markers each 0.68 m from another are no unambiguous pair: the
// centres stay behind their markers.
TEST(RobotContoursTest, AmbiguousPairsKeepTheCentresBehindTheMarkers) {
  core::LaserScan scan = Scan(core::Pose2{});
  // Markers at (2, -0.68), (2, 0) and (2, 0.68) (bearing, range).
  for (double y : {-0.68, 0.0, 0.68}) {
    const int at = 180 + static_cast<int>(std::lround(std::atan2(y, 2.0) / kResolutionRad));
    AddMarker(&scan, at, 1, std::hypot(2.0, y));
  }
  const std::vector<SeenRobot> seen = SeeRobots(scan, RobotContourOptions{});
  ASSERT_EQ(seen.size(), 3u);
  // The middle one has two partners; the outer ones one each, but their
  // partner has two: none is paired.
  for (const SeenRobot& r : seen) {
    EXPECT_NEAR((r.centre_in_robot - r.marker_in_robot).norm(), 0.34, kExact);
  }
}

// The contour is a circle of the given radius, neighbours (including the
// last and the first) at most the spacing apart, appended in the same order
// on every call.
TEST(RobotContoursTest, ContourKeepsItsSpacing) {
  const Eigen::Vector2d centre(1.0, -2.0);
  std::vector<Eigen::Vector2d> points{Eigen::Vector2d(9.0, 9.0)};  // kept
  AppendContour(centre, 0.42, 0.03, &points);
  ASSERT_EQ(points.size(), 1u + static_cast<std::size_t>(std::ceil(2.0 * kPi * 0.42 / 0.03)));
  EXPECT_EQ(points[0], Eigen::Vector2d(9.0, 9.0));
  for (std::size_t i = 1; i < points.size(); ++i) {
    EXPECT_NEAR((points[i] - centre).norm(), 0.42, kExact);
    const Eigen::Vector2d& next = i + 1 < points.size() ? points[i + 1] : points[1];
    EXPECT_LE((next - points[i]).norm(), 0.03);
  }
  std::vector<Eigen::Vector2d> again{Eigen::Vector2d(9.0, 9.0)};
  AppendContour(centre, 0.42, 0.03, &again);
  EXPECT_EQ(points, again);
  std::vector<Eigen::Vector2d> dot;
  AppendContour(centre, 0.0, 0.03, &dot);
  EXPECT_EQ(dot, std::vector<Eigen::Vector2d>{centre});
  EXPECT_THROW(AppendContour(centre, 0.42, 0.0, &dot), std::invalid_argument);
  EXPECT_THROW(AppendContour(centre, -0.1, 0.03, &dot), std::invalid_argument);
}

// A marker whose centre lies within tolerance of a known robot is explained;
// the others stay, in order.
TEST(RobotContoursTest, KnownRobotsExplainTheirMarkers) {
  const std::vector<SeenRobot> seen{
      {{1.0, 0.0}, {1.34, 0.0}}, {{0.0, 2.0}, {0.0, 2.34}}, {{-1.0, 0.0}, {-1.34, 0.0}}};
  const std::vector<Eigen::Vector2d> known{{1.40, 0.05}, {5.0, 5.0}};
  const std::vector<SeenRobot> left = Unexplained(seen, known, 0.1);
  ASSERT_EQ(left.size(), 2u);
  EXPECT_EQ(left[0].centre_in_robot, Eigen::Vector2d(0.0, 2.34));
  EXPECT_EQ(left[1].centre_in_robot, Eigen::Vector2d(-1.34, 0.0));
  EXPECT_EQ(Unexplained(seen, {}, 0.1).size(), 3u);
  EXPECT_EQ(Unexplained(seen, known, 0.01).size(), 3u);  // 7.8 cm off: too far
}

// A contour 0.5 m ahead of a square of half width 0.3 is clipped to
// 0.5 - 0.3 - margin, after which it no longer overlaps and every ghost point
// keeps the margin; a centre inside the hull clips to 0, a far one not at all.
TEST(RobotContoursTest, ClipsContourOutsideOwnHull) {
  const std::vector<Eigen::Vector2d> square = Square(0.3);
  const Eigen::Vector2d ahead(0.5, 0.0);
  const double margin = 0.02;
  const double clipped = ClipRadius(ahead, 0.42, square, margin);
  EXPECT_NEAR(clipped, 0.5 - 0.3 - margin, kExact);
  EXPECT_TRUE(ContourOverlapsHull(ahead, 0.42, square, margin));
  EXPECT_FALSE(ContourOverlapsHull(ahead, clipped, square, margin));
  std::vector<Eigen::Vector2d> contour;
  AppendContour(ahead, clipped, 0.03, &contour);
  EXPECT_GE(PolygonClearance(square, contour), margin - kExact);

  EXPECT_EQ(ClipRadius({0.1, 0.1}, 0.42, square, margin), 0.0);
  EXPECT_TRUE(ContourOverlapsHull({0.1, 0.1}, 0.42, square, margin));
  EXPECT_EQ(ClipRadius({2.0, 0.0}, 0.42, square, margin), 0.42);
  EXPECT_FALSE(ContourOverlapsHull({2.0, 0.0}, 0.42, square, margin));
  EXPECT_THROW(ClipRadius(ahead, 0.42, std::vector<Eigen::Vector2d>{}, margin),
               std::invalid_argument);
}

// Validate names the offending field, including the beacon options'.
TEST(RobotContoursTest, ValidateNamesTheField) {
  const auto message = [](const RobotContourOptions& o) {
    try {
      o.Validate();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(message(RobotContourOptions{}), "");
  RobotContourOptions o;
  o.marker_offset_m = -0.1;
  EXPECT_NE(message(o).find("marker_offset_m"), std::string::npos);
  o = {};
  o.contour_radius_m = 0.0;
  EXPECT_NE(message(o).find("contour_radius_m"), std::string::npos);
  o = {};
  o.point_spacing_m = std::nan("");
  EXPECT_NE(message(o).find("point_spacing_m"), std::string::npos);
  o = {};
  o.max_range_m = 0.0;
  EXPECT_NE(message(o).find("max_range_m"), std::string::npos);
  o = {};
  o.beacons.min_points = 0;
  EXPECT_NE(message(o).find("beacons.min_points"), std::string::npos);
}

}  // namespace
}  // namespace pavilion::nav
