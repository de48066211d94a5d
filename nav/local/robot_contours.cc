#include "nav/local/robot_contours.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "nav/local/scan_obstacles.h"

namespace pavilion::nav {
namespace {

// A bound on one contour's points (a 2 m radius at 5 mm spacing needs 2514).
constexpr double kMaxContourPoints = 1e5;

void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

bool InRange(double value, double lo, double hi) {
  return std::isfinite(value) && value >= lo && value <= hi;
}

// Distance (m) from the convex footprint to `centre`, 0 inside it.
double HullDistance(const Eigen::Vector2d& centre, std::span<const Eigen::Vector2d> footprint) {
  Require(footprint.size() >= 3, "own_footprint must have at least 3 vertices");
  Require(centre.allFinite(), "contour centre must be finite");
  return PolygonClearance(footprint, std::span<const Eigen::Vector2d>(&centre, 1));
}

}  // namespace

void RobotContourOptions::Validate() const {
  Require(InRange(marker_offset_m, 0.0, 2.0),
          "RobotContourOptions.marker_offset_m must be in [0, 2] m");
  Require(InRange(contour_radius_m, 0.0, 2.0) && contour_radius_m > 0.0,
          "RobotContourOptions.contour_radius_m must be in (0, 2] m");
  Require(InRange(point_spacing_m, 0.005, 1.0),
          "RobotContourOptions.point_spacing_m must be in [0.005, 1] m");
  Require(InRange(max_range_m, 0.0, 100.0) && max_range_m > 0.0,
          "RobotContourOptions.max_range_m must be in (0, 100] m");
  Require(InRange(pair_tolerance_m, 0.0, 0.5),
          "RobotContourOptions.pair_tolerance_m must be in [0, 0.5] m");
  try {
    beacons.Validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("RobotContourOptions.beacons.") + e.what());
  }
}

namespace {

// One robot's two markers (RobotContourOptions::pair_tolerance_m): each the
// other's only partner at twice the marker offset; both then imply the
// pair's midpoint.
void PairMarkers(const RobotContourOptions& options, std::vector<SeenRobot>* seen) {
  if (options.pair_tolerance_m <= 0.0) return;
  const std::size_t n = seen->size();
  std::vector<int> partner(n, -1), partners(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      const double apart_m = ((*seen)[i].marker_in_robot - (*seen)[j].marker_in_robot).norm();
      if (std::abs(apart_m - 2.0 * options.marker_offset_m) > options.pair_tolerance_m) continue;
      partner[i] = static_cast<int>(j);
      partner[j] = static_cast<int>(i);
      ++partners[i];
      ++partners[j];
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    const int j = partner[i];
    if (partners[i] != 1 || partners[static_cast<std::size_t>(j)] != 1) continue;
    (*seen)[i].centre_in_robot =
        0.5 * ((*seen)[i].marker_in_robot + (*seen)[static_cast<std::size_t>(j)].marker_in_robot);
  }
}

}  // namespace

std::vector<SeenRobot> SeeRobots(const core::LaserScan& scan, const RobotContourOptions& options) {
  options.Validate();
  std::vector<SeenRobot> seen;
  for (const core::Beacon& beacon : core::ExtractBeacons(scan, options.beacons)) {
    if (beacon.range_m > options.max_range_m) continue;
    // The line of sight from the laser, in the robot frame.
    const double sight_rad = scan.robot_from_sensor.theta_rad + beacon.bearing_rad;
    const Eigen::Vector2d sight(std::cos(sight_rad), std::sin(sight_rad));
    SeenRobot robot;
    robot.marker_in_robot = scan.robot_from_sensor.translation() + beacon.range_m * sight;
    robot.centre_in_robot = robot.marker_in_robot + options.marker_offset_m * sight;
    seen.push_back(robot);
  }
  PairMarkers(options, &seen);
  return seen;
}

void AppendContour(const Eigen::Vector2d& centre, double radius_m, double spacing_m,
                   std::vector<Eigen::Vector2d>* points) {
  Require(std::isfinite(radius_m) && radius_m >= 0.0, "contour radius_m must be >= 0");
  Require(std::isfinite(spacing_m) && spacing_m > 0.0, "contour spacing_m must be > 0");
  if (radius_m == 0.0) {
    points->push_back(centre);
    return;
  }
  // The chord between neighbours is shorter than the arc 2 pi r / n <= spacing.
  const double circumference_m = 2.0 * std::numbers::pi * radius_m;
  const double count = std::ceil(circumference_m / spacing_m);
  Require(count <= kMaxContourPoints, "contour radius_m / spacing_m needs too many points");
  const int n = std::max(3, static_cast<int>(count));
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * std::numbers::pi * k / n;
    points->push_back(centre + radius_m * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
}

std::vector<SeenRobot> Unexplained(std::span<const SeenRobot> seen,
                                   std::span<const Eigen::Vector2d> known_centres_in_robot,
                                   double tolerance_m) {
  Require(std::isfinite(tolerance_m) && tolerance_m >= 0.0, "tolerance_m must be >= 0");
  std::vector<SeenRobot> unexplained;
  for (const SeenRobot& robot : seen) {
    const bool known = std::any_of(known_centres_in_robot.begin(), known_centres_in_robot.end(),
                                   [&](const Eigen::Vector2d& c) {
                                     return (c - robot.centre_in_robot).norm() <= tolerance_m;
                                   });
    if (!known) unexplained.push_back(robot);
  }
  return unexplained;
}

double ClipRadius(const Eigen::Vector2d& centre, double radius_m,
                  std::span<const Eigen::Vector2d> own_footprint, double margin_m) {
  Require(std::isfinite(radius_m) && radius_m >= 0.0, "radius_m must be >= 0");
  Require(std::isfinite(margin_m) && margin_m >= 0.0, "margin_m must be >= 0");
  const double room_m = HullDistance(centre, own_footprint) - margin_m;
  return std::clamp(room_m, 0.0, radius_m);
}

bool ContourOverlapsHull(const Eigen::Vector2d& centre, double radius_m,
                         std::span<const Eigen::Vector2d> own_footprint, double margin_m) {
  Require(std::isfinite(radius_m) && radius_m >= 0.0, "radius_m must be >= 0");
  Require(std::isfinite(margin_m) && margin_m >= 0.0, "margin_m must be >= 0");
  return HullDistance(centre, own_footprint) < radius_m + margin_m;
}

}  // namespace pavilion::nav
