// The planar laser caster's corner cases against hand-computed geometry:
// ranges, normals and elements of segments and circles, parallel rays, rays
// starting on or inside a circle, the casting robot's ignored group,
// transparent elements, doors re-sliced when they move, tilted bodies, and
// agreement of whole scans with the Bullet hit finder.
#include "sim/raycast/planar_caster.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/random/random_stream.h"
#include "sim/sensors/laser_scanner.h"
#include "tests/support/world_robot.h"

namespace pavilion::sim {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kBeamM = 0.3;
constexpr double kExactM = 1e-12;  // double-precision arithmetic on metre-sized inputs

Material MaterialWith(core::LaserResponse response) {
  Material m;
  m.laser = response;
  return m;
}

// A 6 m × 4 m room (inner faces x = 0.05 and 5.95, y = 0.05 and 3.95), a
// column at (4, 2) r 0.3, a glass pane at x = 2, and a door in the top wall.
WorldDescription Room() {
  WorldDescription w;
  w.name = "room";
  w.materials["paint"] = MaterialWith(core::LaserResponse::kNormal);
  w.materials["glass"] = MaterialWith(core::LaserResponse::kTransparent);
  w.floor = {{-1, -1}, {7, 5}, "paint", {}};
  Wall room;
  room.id = "room";
  room.points_m = {{0, 0}, {6, 0}, {6, 4}, {0, 4}};
  room.closed = true;
  room.thickness_m = 0.1;
  room.height_m = 2.0;
  room.material = "paint";
  w.walls.push_back(room);
  Box pane;
  pane.id = "pane";
  pane.pose = {2.0, 1.0, 0.0};
  pane.size_m = {0.02, 1.0, 1.5};
  pane.material = "glass";
  w.boxes.push_back(pane);
  Cylinder column;
  column.id = "column";
  column.position_m = {4.0, 2.0};
  column.radius_m = 0.3;
  column.height_m = 2.0;
  column.material = "paint";
  w.cylinders.push_back(column);
  Door door;
  door.id = "door";
  door.hinge_m = {1.0, 3.5};
  door.closed_yaw_rad = 0.0;
  door.open_yaw_rad = kPi / 2;
  door.width_m = 0.8;
  door.thickness_m = 0.04;
  door.material = "paint";
  w.doors.push_back(door);
  return w;
}

int ElementIndex(const World& world, const std::string& id) {
  const auto& elements = world.elements();
  for (std::size_t i = 0; i < elements.size(); ++i) {
    if (elements[i].id == id) return static_cast<int>(i);
  }
  return -1;
}

Eigen::Vector2d Dir(double angle_rad) { return {std::cos(angle_rad), std::sin(angle_rad)}; }

// A ray straight at a wall face meets it at the analytic range with the face's normal.
TEST(PlanarCasterTest, HitsWallFaceAtAnalyticRangeAndNormal) {
  World world(Room(), {});
  PlanarCaster caster(&world, {});
  const PlanarSlice& slice = caster.SliceAt(kBeamM);
  const RayHit hit = slice.Cast({1.0, 0.5, kBeamM}, Dir(-kPi / 2), 8.0, -1);
  ASSERT_TRUE(hit.hit);
  EXPECT_NEAR(hit.distance_m, 0.45, kExactM);
  EXPECT_EQ(hit.element, ElementIndex(world, "room"));
  EXPECT_NEAR(hit.normal.y(), 1.0, kExactM);
  EXPECT_NEAR(hit.point_m.z(), kBeamM, 0.0);
  // An oblique ray: range 0.45 / sin(30°).
  const RayHit oblique = slice.Cast({1.0, 0.5, kBeamM}, Dir(-kPi / 6), 8.0, -1);
  ASSERT_TRUE(oblique.hit);
  EXPECT_NEAR(oblique.distance_m, 0.9, kExactM);
}

// A ray parallel to a face, along it, does not hit that face; it meets the
// wall that closes the room.
TEST(PlanarCasterTest, RayAlongAFaceHitsTheWallAhead) {
  World world(Room(), {});
  PlanarCaster caster(&world, {});
  const PlanarSlice& slice = caster.SliceAt(kBeamM);
  // 0.05 is the bottom wall's inner face.
  const RayHit along = slice.Cast({1.0, 0.05, kBeamM}, Dir(0.0), 8.0, -1);
  ASSERT_TRUE(along.hit);
  EXPECT_NEAR(along.distance_m, 4.95, kExactM);
  EXPECT_NEAR(along.normal.x(), -1.0, kExactM);
}

// Circles: a head-on hit at centre distance minus radius, a tangent miss, no
// hit from inside or from the circle's boundary outwards.
TEST(PlanarCasterTest, CircleHitsMissesAndRaysFromInside) {
  World world(Room(), {});
  PlanarCaster caster(&world, {});
  const PlanarSlice& slice = caster.SliceAt(kBeamM);
  const int column = ElementIndex(world, "column");
  const RayHit head_on = slice.Cast({2.5, 2.0, kBeamM}, Dir(0.0), 8.0, -1);
  ASSERT_TRUE(head_on.hit);
  EXPECT_EQ(head_on.element, column);
  EXPECT_NEAR(head_on.distance_m, 1.2, kExactM);
  EXPECT_NEAR(head_on.normal.x(), -1.0, kExactM);
  // Off the centre by 0.2: range 1.5 − √(0.09 − 0.04).
  const RayHit off = slice.Cast({2.5, 2.2, kBeamM}, Dir(0.0), 8.0, -1);
  ASSERT_TRUE(off.hit);
  EXPECT_NEAR(off.distance_m, 1.5 - std::sqrt(0.05), kExactM);
  // Just past the tangent: the wall behind.
  const RayHit past = slice.Cast({2.5, 2.3 + 1e-9, kBeamM}, Dir(0.0), 8.0, -1);
  ASSERT_TRUE(past.hit);
  EXPECT_EQ(past.element, ElementIndex(world, "room"));
  // From inside the column, and from its boundary outwards: not the column.
  for (const double x : {4.0, 4.3}) {
    const Eigen::Vector3d from(x, 2.0, kBeamM);
    const RayHit inside = slice.Cast(from, Dir(0.0), 8.0, -1);
    ASSERT_TRUE(inside.hit);
    EXPECT_EQ(inside.element, ElementIndex(world, "room"));
    EXPECT_NEAR(inside.distance_m, 5.95 - from.x(), kExactM);
  }
  // Short of the column: no hit within the range.
  EXPECT_FALSE(slice.Cast({2.5, 2.0, kBeamM}, Dir(0.0), 1.1, -1).hit);
}

// Transparent elements are not seen (the glass pane at x = 2).
TEST(PlanarCasterTest, TransparentElementsAreSkipped) {
  World world(Room(), {});
  PlanarCaster caster(&world, {});
  const PlanarSlice& slice = caster.SliceAt(kBeamM);
  const RayHit hit = slice.Cast({1.0, 1.0, kBeamM}, Dir(0.0), 8.0, -1);
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.element, ElementIndex(world, "room"));
  EXPECT_NEAR(hit.distance_m, 4.95, kExactM);
}

// A door is re-sliced when it swings: closed it blocks the ray, open it does not.
TEST(PlanarCasterTest, DoorIsResliceWhenItMoves) {
  World world(Room(), {});
  PlanarCaster caster(&world, {});
  // The closed door panel spans x in [1, 1.8] around y = 3.5.
  const Eigen::Vector3d from(1.4, 2.5, kBeamM);
  const RayHit closed = caster.SliceAt(kBeamM).Cast(from, Dir(kPi / 2), 8.0, -1);
  ASSERT_TRUE(closed.hit);
  EXPECT_EQ(closed.element, ElementIndex(world, "door"));
  world.SetDoorOpen("door", true);
  caster.Update();
  const RayHit open = caster.SliceAt(kBeamM).Cast(from, Dir(kPi / 2), 8.0, -1);
  ASSERT_TRUE(open.hit);
  EXPECT_EQ(open.element, ElementIndex(world, "room"));
  EXPECT_NEAR(open.distance_m, 3.95 - 2.5, kExactM);
}

pavilion::testing::WorldRobot Robot(const std::string& id, const core::Pose2& pose) {
  pavilion::testing::WorldRobot spec;
  spec.id = id;
  RobotDescription& m = spec.model;
  m.material = "paint";
  m.footprint_m = {{-0.2, -0.2}, {0.2, -0.2}, {0.2, 0.2}, {-0.2, 0.2}};
  m.chassis_height_m = 0.5;
  m.chassis_base_z_m = 0.05;
  m.chassis_mass_kg = 20.0;
  m.left_wheel = {"left", 0.05, 0.03, 0.5, {0.0, 0.15}};
  m.right_wheel = {"right", 0.05, 0.03, 0.5, {0.0, -0.15}};
  m.casters = {{"front", {0.15, 0.0}, 0.02}};
  spec.pose = pose;
  return spec;
}

// The casting robot's own parts are ignored; another robot's are not.
TEST(PlanarCasterTest, IgnoresTheCastingRobotsGroup) {
  World world(Room(), {});
  const int a = pavilion::testing::AddRobot(world, Robot("a", {1.0, 1.0, 0.0}));
  pavilion::testing::AddRobot(world, Robot("b", {3.0, 1.0, 0.0}));
  PlanarCaster caster(&world, {});
  const PlanarSlice& slice = caster.SliceAt(kBeamM);
  const Eigen::Vector3d from(1.0, 1.0, kBeamM);  // inside robot a
  const RayHit own_ignored = slice.Cast(from, Dir(0.0), 8.0, world.robot_group(a));
  ASSERT_TRUE(own_ignored.hit);
  EXPECT_EQ(own_ignored.element, ElementIndex(world, "b"));
  EXPECT_NEAR(own_ignored.distance_m, 1.8, 1e-9);
  // Cast backwards from outside robot a towards it, without ignoring: it is hit.
  const RayHit other = slice.Cast({1.5, 1.0, kBeamM}, Dir(kPi), 8.0, -1);
  ASSERT_TRUE(other.hit);
  EXPECT_EQ(other.element, ElementIndex(world, "a"));
  EXPECT_NEAR(other.distance_m, 0.3, 1e-9);
}

// Two robots whose outlines share grid cells (0.05 m apart): a ray skips the
// run of its own robot's segments in a cell and still tests the other's,
// whichever of the two runs comes first.
TEST(PlanarCasterTest, RobotsSharingACellEachSeeTheOther) {
  World world(Room(), {});
  const int a = pavilion::testing::AddRobot(world, Robot("a", {1.0, 1.0, 0.0}));
  const int b = pavilion::testing::AddRobot(world, Robot("b", {1.45, 1.0, 0.0}));
  PlanarCaster caster(&world, {});
  const PlanarSlice& slice = caster.SliceAt(kBeamM);
  const RayHit from_a = slice.Cast({1.0, 1.0, kBeamM}, Dir(0.0), 8.0, world.robot_group(a));
  ASSERT_TRUE(from_a.hit);
  EXPECT_EQ(from_a.element, ElementIndex(world, "b"));
  EXPECT_NEAR(from_a.distance_m, 0.25, 1e-9);
  const RayHit from_b = slice.Cast({1.45, 1.0, kBeamM}, Dir(kPi), 8.0, world.robot_group(b));
  ASSERT_TRUE(from_b.hit);
  EXPECT_EQ(from_b.element, ElementIndex(world, "a"));
  EXPECT_NEAR(from_b.distance_m, 0.25, 1e-9);
  // Beside the other robot, out of its own: the closed door 2.48 m on.
  const RayHit along = slice.Cast({1.0, 1.0, kBeamM}, Dir(kPi / 2), 8.0, world.robot_group(a));
  ASSERT_TRUE(along.hit);
  EXPECT_EQ(along.element, ElementIndex(world, "door"));
  EXPECT_NEAR(along.distance_m, 2.48, 1e-9);
}

// The moving bodies' grid is refilled every tick, clearing only the cells the
// last fill used: a robot that moved away leaves nothing in its old cells,
// and is found in its new ones, again after it comes back.
TEST(PlanarCasterTest, AMovedRobotLeavesNoTraceInItsOldCells) {
  World world(Room(), {});
  const int b = pavilion::testing::AddRobot(world, Robot("b", {3.0, 1.0, 0.0}));
  PlanarCaster caster(&world, {});
  const PlanarSlice& slice = caster.SliceAt(kBeamM);
  const int robot = ElementIndex(world, "b");
  const int room = ElementIndex(world, "room");
  const Eigen::Vector3d low(1.0, 1.0, kBeamM);   // looks along y = 1
  const Eigen::Vector3d high(1.0, 3.0, kBeamM);  // looks along y = 3
  EXPECT_EQ(slice.Cast(low, Dir(0.0), 8.0, -1).element, robot);
  for (int round = 0; round < 2; ++round) {
    world.TeleportRobot(b, {3.0, 3.0, 0.0});
    caster.Refresh();
    const RayHit old_cells = slice.Cast(low, Dir(0.0), 8.0, -1);
    ASSERT_TRUE(old_cells.hit);
    EXPECT_EQ(old_cells.element, room);
    EXPECT_NEAR(old_cells.distance_m, 5.95 - 1.0, kExactM);
    const RayHit new_cells = slice.Cast(high, Dir(0.0), 8.0, -1);
    EXPECT_EQ(new_cells.element, robot);
    EXPECT_NEAR(new_cells.distance_m, 1.8, 1e-9);
    world.TeleportRobot(b, {3.0, 1.0, 0.0});
    caster.Refresh();
    const RayHit vacated = slice.Cast(high, Dir(0.0), 8.0, -1);
    EXPECT_EQ(vacated.element, room);
    EXPECT_NEAR(vacated.distance_m, 5.95 - 1.0, kExactM);
    const RayHit back = slice.Cast(low, Dir(0.0), 8.0, -1);
    EXPECT_EQ(back.element, robot);
    EXPECT_NEAR(back.distance_m, 1.8, 1e-9);
  }
}

// The planar caster's short rays agree with its long ones (ShortRaysAgree:
// the scanner's mixed-pixel probes stop early on it): a ray cut to any range
// beyond the full ray's hit finds the same hit to the bit, and one cut short
// of it finds nothing nearer than the full ray's.
TEST(PlanarCasterTest, ARayCutShortFindsTheSameHitToTheBit) {
  World world(Room(), {});
  pavilion::testing::AddRobot(world, Robot("b", {3.0, 1.0, 0.3}));
  PlanarCaster caster(&world, {});
  const PlanarSlice& slice = caster.SliceAt(kBeamM);
  EXPECT_TRUE(slice.ShortRaysAgree());
  EXPECT_FALSE(WorldHitFinder(world).ShortRaysAgree());
  core::RandomStream random(5, 0);
  int compared = 0;
  for (int k = 0; k < 5000; ++k) {
    const Eigen::Vector3d from(random.Uniform(0.2, 5.8), random.Uniform(0.2, 3.8), kBeamM);
    const Eigen::Vector2d dir = Dir(random.Uniform(-kPi, kPi));
    const RayHit full = slice.Cast(from, dir, 8.0, -1);
    if (!full.hit) continue;
    const double beyond = full.distance_m + random.Uniform(1e-9, 0.3);
    const RayHit cut = slice.Cast(from, dir, beyond, -1);
    ASSERT_TRUE(cut.hit) << k;
    EXPECT_EQ(cut.distance_m, full.distance_m) << k;
    EXPECT_EQ(cut.point_m, full.point_m) << k;
    EXPECT_EQ(cut.normal, full.normal) << k;
    EXPECT_EQ(cut.element, full.element) << k;
    EXPECT_FALSE(slice.Cast(from, dir, full.distance_m * (1.0 - 1e-9), -1).hit) << k;
    ++compared;
  }
  EXPECT_GT(compared, 4000);
}

// A box body is cut over [bottom, top) of its faces, as the static section
// cuts boxes: just below its top four segments, at the top nothing, and
// nothing is left uncut. (Tilted chassis cut through their sides are checked
// against Bullet in planar_caster_conformance_test: the robots settle tilted.)
TEST(PlanarCasterTest, BoxBodyIsCutUpToItsTopFace) {
  World world(Room(), {});
  BodySpec crate;
  crate.id = "crate";
  crate.shape.type = BodyShapeType::kBox;
  crate.shape.box_size_m = {0.4, 0.4, 0.4};
  crate.pose = {3.0, 1.0, 0.0};
  crate.material = "paint";
  crate.upright = false;
  world.AddBody(crate);
  PlanarCaster caster(&world, {});
  EXPECT_TRUE(caster.SliceAt(kBeamM).Covers({3.0, 1.0}, 8.0, -1));
  for (const auto& [height, segments] : {std::pair{0.4 - 1e-12, 4u}, std::pair{0.4, 0u}}) {
    std::vector<UncutElement> uncut;
    core::PlanarSection section;
    world.AppendDynamicSection(height, 0.01, &section, &uncut);
    EXPECT_TRUE(uncut.empty());
    EXPECT_EQ(section.segments.size(), segments) << height;
  }
  const RayHit hit = caster.SliceAt(kBeamM).Cast({1.0, 1.0, kBeamM}, Dir(0.0), 8.0, -1);
  ASSERT_TRUE(hit.hit);
  EXPECT_EQ(hit.element, ElementIndex(world, "crate"));
  EXPECT_NEAR(hit.distance_m, 1.8, kExactM);
}

// A cylinder tipping over is cut as an ellipse (semi-axes r and r / cos tilt)
// once its tilt passes max_tilt_rad: rays from all around meet it where
// Bullet's do, and nothing is left uncut, so scans beside it need no fallback.
TEST(PlanarCasterTest, ATiltedCylinderIsCutAsAnEllipse) {
  World world(Room(), {});
  BodySpec pole;
  pole.id = "pole";
  pole.shape.type = BodyShapeType::kCylinder;
  pole.shape.radius_m = 0.1;
  pole.shape.height_m = 1.2;
  pole.mass_kg = 5.0;
  pole.pose = {3.0, 2.0, 0.0};
  pole.material = "paint";
  pole.upright = false;
  const int body = world.AddBody(pole);
  world.ApplyImpulse(body, {4.0, 1.0});
  constexpr double kMinTiltRad = 5.0 * kPi / 180.0;
  for (int i = 0; i < 400 && world.body_state(body).tilt_rad < kMinTiltRad; ++i) world.Step();
  const double tilt = world.body_state(body).tilt_rad;
  ASSERT_GT(tilt, kMinTiltRad);
  ASSERT_LT(tilt, 30.0 * kPi / 180.0);
  constexpr double kHeightM = 0.5;  // crosses the pole's side only
  PlanarCaster caster(&world, {});
  const PlanarSlice& slice = caster.SliceAt(kHeightM);
  EXPECT_TRUE(slice.Covers({3.0, 2.0}, 8.0, -1));
  core::PlanarSection section;
  std::vector<UncutElement> uncut;
  world.AppendDynamicSection(kHeightM, caster.options().max_tilt_rad, &section, &uncut);
  ASSERT_EQ(section.circles.size(), 1u);
  EXPECT_NEAR(section.circles[0].squash, std::cos(tilt), 1e-9);
  const WorldHitFinder bullet(world);
  const Eigen::Vector2d centre = section.circles[0].center_m;
  int hits = 0;
  for (int k = 0; k < 72; ++k) {  // from 1.2 m all around, aimed across the ellipse
    const double around = k * 2.0 * kPi / 72.0;
    const Eigen::Vector3d origin(centre.x() + 1.2 * std::cos(around),
                                 centre.y() + 1.2 * std::sin(around), kHeightM);
    for (const double aside : {-0.12, -0.06, 0.0, 0.06, 0.12}) {
      const Eigen::Vector2d d = Dir(around + kPi + aside);
      const RayHit p = slice.Cast(origin, d, 8.0, -1);
      const RayHit b = bullet.Cast(origin, d, 8.0, -1);
      ASSERT_EQ(p.hit, b.hit) << k << " " << aside;
      EXPECT_EQ(p.element, b.element) << k << " " << aside;
      EXPECT_NEAR(p.distance_m, b.distance_m, 1e-4) << k << " " << aside;
      if (p.element == ElementIndex(world, "pole")) {
        ++hits;
        // The caster's normal is the cut curve's, in the plane; Bullet's is
        // the surface's, tilted with the cylinder: its horizontal part agrees.
        const Eigen::Vector2d bullet_normal = b.normal.head<2>().normalized();
        EXPECT_GT(p.normal.head<2>().dot(bullet_normal), 0.9999) << k << " " << aside;
      }
    }
  }
  EXPECT_GT(hits, 72 * 2);
}

// Whole scans with every error model give the same readings through either
// hit finder (same draws from the same stream), for a scanner in the room.
TEST(PlanarCasterTest, ScansMatchTheBulletHitFinder) {
  World world(Room(), {});
  pavilion::testing::AddRobot(world, Robot("b", {3.0, 1.0, 0.4}));
  for (int i = 0; i < 10; ++i) world.Step();  // Bullet's broadphase learns the robot's bounds
  PlanarCaster caster(&world, {});
  LaserScannerOptions options = LaserScannerOptions::Profile("sick_lms200");
  const core::Pose2 pose{1.0, 2.0, 0.3};
  LaserScanner a("l", options, {}, kBeamM, core::RandomStream(5, 6));
  LaserScanner b = a;
  core::LaserScanTruth ta, tb;
  const core::LaserScan sa = a.ScanFrom(caster.SliceAt(kBeamM), pose, 0.0, -1, &ta);
  const core::LaserScan sb = b.ScanFrom(WorldHitFinder(world), pose, 0.0, -1, &tb);
  ASSERT_EQ(sa.readings.size(), sb.readings.size());
  for (std::size_t i = 0; i < sa.readings.size(); ++i) {
    EXPECT_EQ(ta.element[i], tb.element[i]) << i;
    EXPECT_NEAR(ta.true_range_m[i], tb.true_range_m[i], 1e-9) << i;
    EXPECT_EQ(sa.readings[i].valid, sb.readings[i].valid) << i;
    EXPECT_NEAR(sa.readings[i].range_m, sb.readings[i].range_m, 1.0001e-3) << i;
  }
}

}  // namespace
}  // namespace pavilion::sim
