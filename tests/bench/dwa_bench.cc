// One cycle of the dynamic window (thesis §6.3.4, nav/reactive/dynamic_window.h):
// Robox-like octagon, 11x11 wheel-speed candidates, a 720-reading 360-degree
// scan (two back-to-back lasers at 0.5 degrees, 8 m) of a 2.4 m wide corridor
// with three people-like clusters, plus 20 ghost points; the robot drives at
// 0.5 m/s along the corridor. BM_DynamicWindowChoose uses the clearance
// look-up table; the baseline BM_DynamicWindowChooseExact the exact geometry
// for every candidate and point. Budget: <= 50 us per Choose() on one core.
// BM_DynamicWindowChooseEscape: the same scan plus a person-like ring touching
// the front 5 mm from the octagon, the robot stopped: escape motions with the
// exact contact and band geometry.
// BM_DynamicWindowChooseBesideVitrine: the same scan plus a 1 m glass vitrine's
// ghost outline (points every 0.25 m, as `pavilion map derive` puts them)
// filled and thickened as the navigation gives it to the window
// (nav::FillGhostBarriers), its near face 6 cm beside the octagon's flank.
// BM_ScanObstaclesInRobot/{0,1}: gathering the window's points
// (nav::ScanObstacles::InRobot) from two back-to-back 180-degree scans of the
// corridor, 20 ghost points, and (/1) the blind zones' map outline
// (nav::MapOutline of the corridor's two 20 m walls and a 0.25 m column, 2 cm
// clearance) with the robot 0.6 m from one wall and beside the column.
// BM_ExploreBearing: a lost robot's choice of bearing (nav::ExploreBearing,
// 16 bearings) among the corridor scan's points within 3 m, no current bearing.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

#include "core/map/robot_map.h"
#include "nav/local/scan_obstacles.h"
#include "nav/reactive/dynamic_window.h"
#include "nav/reactive/explore_direction.h"
#include "nav/reactive/swept_polygon.h"

namespace {

using namespace pavilion;

constexpr double kPi = std::numbers::pi;
constexpr double kHalfWidth_m = 1.2;  // corridor walls at y = ±1.2 m
constexpr double kMaxRange_m = 8.0;
constexpr int kReadings = 720;
constexpr int kGhostPoints = 20;

struct Person {
  Eigen::Vector2d centre;
  double radius_m;
};

core::Polygon2 Octagon() {
  const double corner_m = 0.34 / std::cos(kPi / 8.0);
  core::Polygon2 p;
  for (int k = 0; k < 8; ++k) {
    const double a = kPi / 8.0 + k * kPi / 4.0;
    p.emplace_back(corner_m * std::cos(a), corner_m * std::sin(a));
  }
  return p;
}

// The nearest positive ray parameter hitting the circle, or `best`.
double HitCircle(const Eigen::Vector2d& d, const Person& person, double best) {
  const double b = d.dot(person.centre);
  const double disc = b * b - person.centre.squaredNorm() + person.radius_m * person.radius_m;
  if (disc < 0.0) return best;
  const double t = b - std::sqrt(disc);
  return t > 0.0 && t < best ? t : best;
}

std::vector<Eigen::Vector2d> CorridorScan() {
  const Person people[] = {{{1.3, 0.55}, 0.2}, {{2.2, -0.6}, 0.25}, {{-0.9, 0.4}, 0.2}};
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < kReadings; ++i) {
    const double a = -kPi + i * (2.0 * kPi / kReadings);
    const Eigen::Vector2d d(std::cos(a), std::sin(a));
    double t = d.y() != 0.0 ? kHalfWidth_m / std::abs(d.y()) : kMaxRange_m;
    for (const Person& p : people) t = HitCircle(d, p, t);
    if (t < kMaxRange_m) points.push_back(t * d);
  }
  for (int k = 0; k < kGhostPoints; ++k) points.emplace_back(3.0 + 0.1 * k, 0.9);
  return points;
}

// A ring of radius 0.2 m (1 cm spacing) whose nearest point is 5 mm ahead of the front flat.
std::vector<Eigen::Vector2d> PersonAtFront() {
  constexpr double kRadius_m = 0.2;
  const Eigen::Vector2d centre(0.34 + 0.005 + kRadius_m, 0.0);
  std::vector<Eigen::Vector2d> ring;
  for (double b = 0.0; b < 2.0 * kPi; b += 0.01 / kRadius_m) {
    ring.push_back(centre + kRadius_m * Eigen::Vector2d(-std::cos(b), std::sin(b)));
  }
  return ring;
}

// A 1 x 1 m vitrine whose near face runs along y = -(0.34 + 0.06), filled.
std::vector<Eigen::Vector2d> VitrineBeside() {
  constexpr double kFace_m = 0.34 + 0.06;
  const Eigen::Vector2d corners[4] = {
      {-0.5, -kFace_m}, {0.5, -kFace_m}, {0.5, -kFace_m - 1.0}, {-0.5, -kFace_m - 1.0}};
  std::vector<Eigen::Vector2d> ghosts;
  for (int side = 0; side < 4; ++side) {
    const Eigen::Vector2d& a = corners[side];
    const Eigen::Vector2d& b = corners[(side + 1) % 4];
    for (int k = 0; k < 4; ++k) ghosts.push_back(a + 0.25 * k * (b - a));
  }
  return nav::FillGhostBarriers(ghosts, nav::GhostBarrier{});
}

enum class Scene { kCorridor, kTouched, kBesideVitrine };

void RunChoose(benchmark::State& state, nav::ClearanceGeometry geometry,
               Scene scene = Scene::kCorridor) {
  nav::DynamicWindowOptions options;
  options.clearance_geometry = geometry;
  nav::DynamicWindow dwa(options, Octagon());
  std::vector<Eigen::Vector2d> points = CorridorScan();
  nav::DwaGoal goal;
  goal.target_in_robot = {4.0, 0.2};
  nav::WheelVelocity current{0.5, 0.5};
  if (scene == Scene::kBesideVitrine) {
    const std::vector<Eigen::Vector2d> vitrine = VitrineBeside();
    points.insert(points.end(), vitrine.begin(), vitrine.end());
  }
  if (scene == Scene::kTouched) {
    const std::vector<Eigen::Vector2d> person = PersonAtFront();
    points.insert(points.end(), person.begin(), person.end());
    goal.target_in_robot = {-2.0, 1.0};
    current = {};
  }
  nav::DwaResult result;
  for (auto _ : state) {
    result = dwa.Choose(current, points, goal);
    benchmark::DoNotOptimize(result);
  }
  state.counters["points"] = static_cast<double>(points.size());
  state.counters["in_reach"] = result.points_in_reach;
  state.counters["candidates"] = result.candidates_evaluated;
  state.counters["admissible"] = result.candidates_admissible;
  state.counters["contacts"] = result.contact_points;
  state.counters["band"] = result.band_points;
  state.counters["v_mps"] = 0.5 * (result.command.left_mps + result.command.right_mps);
}

void BM_DynamicWindowChoose(benchmark::State& state) {
  RunChoose(state, nav::ClearanceGeometry::kLookupTable);
}
BENCHMARK(BM_DynamicWindowChoose)->Unit(benchmark::kMicrosecond);

void BM_DynamicWindowChooseExact(benchmark::State& state) {
  RunChoose(state, nav::ClearanceGeometry::kExact);
}
BENCHMARK(BM_DynamicWindowChooseExact)->Unit(benchmark::kMicrosecond);

void BM_DynamicWindowChooseEscape(benchmark::State& state) {
  RunChoose(state, nav::ClearanceGeometry::kLookupTable, Scene::kTouched);
}
BENCHMARK(BM_DynamicWindowChooseEscape)->Unit(benchmark::kMicrosecond);

void BM_DynamicWindowChooseBesideVitrine(benchmark::State& state) {
  RunChoose(state, nav::ClearanceGeometry::kLookupTable, Scene::kBesideVitrine);
}
BENCHMARK(BM_DynamicWindowChooseBesideVitrine)->Unit(benchmark::kMicrosecond);

// The corridor's walls (y = ±1.2 m) in a 180-degree scan from a scanner
// mounted at (mount_x_m, 0) looking along heading_rad, the robot's centre at
// y = offset_y_m and heading along x: Robox's lasers back to back 0.22 m ahead
// of and behind its centre, with blind zones along its flanks.
core::LaserScan HalfScan(const char* id, double mount_x_m, double heading_rad, double offset_y_m) {
  core::LaserScan scan;
  scan.sensor_id = id;
  scan.max_range_m = kMaxRange_m;
  scan.robot_from_sensor = core::Pose2(mount_x_m, 0.0, heading_rad);
  for (int i = 0; i <= kReadings / 2; ++i) {
    const double bearing = -kPi / 2.0 + i * (2.0 * kPi / kReadings);
    const double a = bearing + heading_rad;
    core::LaserReading r;
    r.bearing_rad = bearing;
    const double sy = std::sin(a);
    const double wall = sy > 0.0 ? kHalfWidth_m - offset_y_m : -kHalfWidth_m - offset_y_m;
    const double t = sy != 0.0 ? wall / sy : kMaxRange_m;
    r.valid = t > 0.0 && t < kMaxRange_m;
    r.range_m = r.valid ? t : kMaxRange_m;
    scan.readings.push_back(r);
  }
  return scan;
}

void BM_ScanObstaclesInRobot(benchmark::State& state) {
  const bool outline = state.range(0) != 0;
  constexpr double kOffsetY_m = 0.6;  // the robot 0.6 m from the wall at y = +1.2
  std::vector<Eigen::Vector2d> ghosts;
  for (int k = 0; k < kGhostPoints; ++k) ghosts.emplace_back(3.0 + 0.1 * k, 0.9);
  nav::ScanObstacles obstacles(Octagon(), ghosts);
  if (outline) {
    core::RobotMap map;
    for (const double y : {kHalfWidth_m, -kHalfWidth_m}) {
      core::MapSegment wall;
      wall.line.alpha_rad = y > 0.0 ? kPi / 2.0 : -kPi / 2.0;
      wall.line.r_m = std::abs(y);
      wall.first_endpoint.position_m = {-10.0, y};
      wall.second_endpoint.position_m = {10.0, y};
      map.segments.push_back(wall);
    }
    core::MapPoint column;
    column.point.position_m = {0.0, -0.1};  // its face 0.45 m right of the centre
    column.radius_m = 0.25;
    map.points.push_back(column);
    obstacles.SetMapOutline(nav::MapOutline(map, nav::kOutlineSpacingM, 0.02));
  }
  const core::Pose2 pose(0.0, kHalfWidth_m - kOffsetY_m, 0.0);
  obstacles.AddScan(HalfScan("front", 0.22, 0.0, pose.y_m), pose);
  obstacles.AddScan(HalfScan("rear", -0.22, kPi, pose.y_m), pose);
  std::vector<Eigen::Vector2d> points;
  for (auto _ : state) {
    obstacles.InRobot(pose, pose, 3.0, &points);
    benchmark::DoNotOptimize(points.data());
  }
  state.counters["points"] = static_cast<double>(points.size());
}
BENCHMARK(BM_ScanObstaclesInRobot)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_ExploreBearing(benchmark::State& state) {
  std::vector<Eigen::Vector2d> points;
  for (const Eigen::Vector2d& p : CorridorScan()) {
    if (p.norm() <= 3.0) points.push_back(p);
  }
  const nav::ExploreOptions options;
  const double half_width_m = nav::Circumradius(Octagon()) + 0.02;
  for (auto _ : state) {
    benchmark::DoNotOptimize(nav::ExploreBearing(points, std::nullopt, half_width_m, options));
  }
  state.counters["points"] = static_cast<double>(points.size());
}
BENCHMARK(BM_ExploreBearing)->Unit(benchmark::kMicrosecond);

}  // namespace
