// Robot sees robot (thesis §6.3.5.1): Robox's scanners sit in a recess of its
// base, so another Robox's laser at the same height "underestimates the true
// vehicle size": it measures the recess, about 0.10 m behind the hull, while
// the retro-reflective markers standing out at the sides carry the reflector
// flag. Checked with both laser backends (Bullet rays and the planar caster)
// and on the world's section at the beam height.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "core/random/random_stream.h"
#include "scenarios/config/robot_loader.h"
#include "scenarios/config/robot_setup.h"
#include "sim/raycast/laser_hit_finder.h"
#include "sim/raycast/planar_caster.h"
#include "sim/sensors/laser_scanner.h"
#include "sim/world/world.h"
#include "tests/support/floor_world.h"

namespace pavilion::sim {
namespace {

constexpr double kPi = std::numbers::pi;
// Robox's geometry as robot.urdf states it, written out independently of the
// loader: regular octagons (flats facing the axes), half the width across flats.
constexpr double kHullApothemM = 0.34;    // 0.68 m base
constexpr double kRecessApothemM = 0.24;  // 0.48 m recess, 0.40..0.60 m
constexpr double kRecessDepthM = kHullApothemM - kRecessApothemM;
constexpr double kMarkerAxisYM = 0.34;  // robot.yaml markers, radius 0.025 m
constexpr double kMarkerRadiusM = 0.025;
constexpr double kApartM = 1.5;  // base origins, facing each other
// Noise off, the readings are the geometric range quantized to 1 mm: half a
// step, plus rounding of the poses (the robots are not stepped).
constexpr double kRangeTolM = 0.5e-3 + 1e-6;

// Distance along a unit 2D ray from `o` to where it enters the regular octagon
// of apothem `a` centred at the origin (flats facing the axes); nullopt if missed.
std::optional<double> EnterOctagon(const Eigen::Vector2d& o, const Eigen::Vector2d& d, double a) {
  double t_in = -std::numeric_limits<double>::infinity();
  double t_out = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector2d n(std::cos(k * kPi / 4), std::sin(k * kPi / 4));
    const double denom = n.dot(d), dist = a - n.dot(o);
    if (denom == 0.0) {
      if (dist < 0.0) return std::nullopt;
      continue;
    }
    const double t = dist / denom;
    if (denom < 0.0) t_in = std::max(t_in, t);
    if (denom > 0.0) t_out = std::min(t_out, t);
  }
  if (t_in > t_out || t_in <= 0.0) return std::nullopt;
  return t_in;
}

int ElementIndex(const World& world, const std::string& id) {
  const auto& elements = world.elements();
  for (std::size_t i = 0; i < elements.size(); ++i) {
    if (elements[i].id == id) return static_cast<int>(i);
  }
  return -1;
}

// Two Robox facing each other kApartM apart: "a" at the origin looking along
// +x, "b" looking back at it.
struct TwoRobox {
  TwoRobox() {
    WorldDescription d = pavilion::testing::FloorWorld(10, false);
    config = scenarios::WithWorldMaterials(
        scenarios::LoadRobotFile(PAVILION_SOURCE_DIR "/robots/robox/robot.yaml"), &d);
    world = std::make_unique<World>(d, WorldOptions{});
    a = world->AddRobot(config.description, config.systematic, {"a", {0.0, 0.0, 0.0}});
    b = world->AddRobot(config.description, config.systematic, {"b", {kApartM, 0.0, kPi}});
  }
  RobotConfig config;
  std::unique_ptr<World> world;
  int a = -1, b = -1;
};

// The front scanner of robot "a", noise and surface effects off (the
// reflector flag is still reported).
LaserScanner FrontScanner(const RobotConfig& config) {
  const LaserMount& mount = config.lasers.front();
  LaserScannerOptions options = mount.options;
  options.noise = false;
  options.effects = false;
  return LaserScanner(mount.id, options, mount.robot_from_sensor, mount.z_m,
                      core::RandomStream(20261201, 1));
}

// Confirms the configuration the test relies on: the front laser at 0.50 m,
// 0.22 m ahead of the base origin, in the recess band.
TEST(RobotSeesRobotTest, FrontLaserIsInTheRecess) {
  const TwoRobox scene;
  const LaserMount& mount = scene.config.lasers.front();
  EXPECT_NEAR(mount.z_m, 0.50, 1e-12);
  EXPECT_NEAR(mount.robot_from_sensor.x_m, 0.22, 1e-12);
  EXPECT_LT(mount.robot_from_sensor.x_m, kRecessApothemM);
}

// Confirms World::SectionAt cuts a robot by its collision geometry at the
// height: at 0.50 m Robox's chassis is the 0.48 m recess octagon, at 0.30 m
// and 0.70 m the 0.68 m hull.
TEST(RobotSeesRobotTest, SectionAtScannerHeightIsTheRecess) {
  const TwoRobox scene;
  const int chassis = ElementIndex(*scene.world, "b");
  ASSERT_GE(chassis, 0);
  const Eigen::Vector2d centre(kApartM, 0.0);
  for (const auto& [z, apothem] : {std::pair{0.30, kHullApothemM}, std::pair{0.50, kRecessApothemM},
                                   std::pair{0.70, kHullApothemM}}) {
    const core::PlanarSection section = scene.world->SectionAt(z);
    int corners = 0;
    for (const auto& seg : section.segments) {
      if (seg.element != chassis) continue;
      ++corners;
      EXPECT_NEAR((seg.a_m - centre).norm(), apothem / std::cos(kPi / 8), 1e-6) << z;
    }
    EXPECT_EQ(corners, 8) << z;
  }
}

// Confirms, for both backends, that robot "a"'s front scanner measures robot
// "b" at its recess — farther than its hull by the recess depth head-on —
// never its own body, and that b's markers, standing out of the recess at its
// sides, are seen with the reflector flag while nothing else is.
TEST(RobotSeesRobotTest, LaserMeasuresTheRecessAndFlagsTheMarkers) {
  TwoRobox scene;
  World& world = *scene.world;
  const int chassis_b = ElementIndex(world, "b");
  const int marker_left_b = ElementIndex(world, "b/left");
  const int marker_right_b = ElementIndex(world, "b/right");
  ASSERT_GE(chassis_b, 0);
  ASSERT_GE(marker_left_b, 0);
  ASSERT_GE(marker_right_b, 0);
  const LaserMount& mount = scene.config.lasers.front();
  const core::Pose2 world_from_a = world.robot_state(scene.a).pose;
  const core::Pose2 world_from_b = world.robot_state(scene.b).pose;
  const core::Pose2 b_from_sensor = world_from_b.Inverse() * world_from_a * mount.robot_from_sensor;

  PlanarCaster planar(&world, PlanarCasterOptions{});
  const WorldHitFinder bullet(world);
  const LaserHitFinder* finders[] = {&bullet, &planar.SliceAt(mount.z_m)};
  const char* names[] = {"bullet", "planar"};
  for (int f = 0; f < 2; ++f) {
    SCOPED_TRACE(names[f]);
    LaserScanner scanner = FrontScanner(scene.config);
    core::LaserScanTruth truth;
    const core::LaserScan scan =
        scanner.ScanFrom(*finders[f], world_from_a, 0.0, world.robot_group(scene.a), &truth);
    int chassis_hits = 0, marker_hits[2] = {0, 0};
    double head_on_range_m = 0.0;
    for (std::size_t i = 0; i < scan.readings.size(); ++i) {
      const core::LaserReading& r = scan.readings[i];
      const int element = truth.element[i];
      ASSERT_TRUE(element < 0 || world.elements()[element].group != world.robot_group(scene.a))
          << "reading " << i << " hits robot a itself";
      if (element == marker_left_b || element == marker_right_b) {
        ++marker_hits[element == marker_left_b ? 0 : 1];
        EXPECT_TRUE(r.valid) << i;
        EXPECT_TRUE(r.reflector) << i;
        continue;
      }
      EXPECT_FALSE(r.reflector) << i;
      if (element != chassis_b) continue;
      ++chassis_hits;
      // The beam in b's frame, against b's recess and hull octagons.
      const double bearing = b_from_sensor.theta_rad + r.bearing_rad;
      const Eigen::Vector2d o(b_from_sensor.x_m, b_from_sensor.y_m);
      const Eigen::Vector2d dir(std::cos(bearing), std::sin(bearing));
      const std::optional<double> recess = EnterOctagon(o, dir, kRecessApothemM);
      const std::optional<double> hull = EnterOctagon(o, dir, kHullApothemM);
      ASSERT_TRUE(recess && hull) << i;
      EXPECT_TRUE(r.valid) << i;
      EXPECT_NEAR(r.range_m, *recess, kRangeTolM) << i;
      EXPECT_GT(r.range_m, *hull + 0.5 * kRecessDepthM) << i;  // the size is underestimated
      if (std::abs(r.bearing_rad) < 1e-9) head_on_range_m = r.range_m;
    }
    // The recess's front flat alone spans 0.2 m at ≈ 1.04 m: ≥ 20 readings at 0.5°.
    EXPECT_GE(chassis_hits, 20);
    // Head on: the recess, kRecessDepthM behind the hull's front face.
    const double hull_head_on_m = kApartM - kHullApothemM - mount.robot_from_sensor.x_m;
    EXPECT_NEAR(head_on_range_m, hull_head_on_m + kRecessDepthM, kRangeTolM);
    // Each marker (5 cm wide at ≈ 1.3 m, ≈ 2.2°) gives a few flagged readings.
    EXPECT_GE(marker_hits[0], 2);
    EXPECT_GE(marker_hits[1], 2);
  }
  // The markers stand out of the recess: their outer faces are
  // kHullApothemM - kRecessApothemM + kMarkerRadiusM beyond it.
  EXPECT_GT(kMarkerAxisYM + kMarkerRadiusM - kRecessApothemM, kRecessDepthM);
}

}  // namespace
}  // namespace pavilion::sim
