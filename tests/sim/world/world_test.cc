#include "sim/world/world.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "core/geometry/polygon.h"
#include "sim/world/contact_tracker.h"

namespace pavilion::sim {
namespace {

constexpr double kG = 9.81;

// A 10 m × 10 m room (inner faces at 0.1 and 9.9), a showcase box, a low bench
// (0.4 m), a glass panel, a column and a door.
WorldDescription TestRoom() {
  WorldDescription w;
  w.name = "test_room";
  w.materials["concrete"] = Material{0.8, 0.0, {0.7, 0.7, 0.7, 1}, core::LaserResponse::kNormal};
  w.materials["glass"] =
      Material{0.5, 0.0, {0.6, 0.8, 0.9, 0.3}, core::LaserResponse::kTransparent};
  w.materials["floor"] = Material{0.8, 0.0, {0.5, 0.5, 0.5, 1}, core::LaserResponse::kNormal};
  w.floor = {{-1, -1}, {11, 11}, "floor", {}};
  Wall room;
  room.id = "room";
  room.points_m = {{0, 0}, {10, 0}, {10, 10}, {0, 10}};
  room.closed = true;
  room.thickness_m = 0.2;
  room.height_m = 2.0;
  room.material = "concrete";
  w.walls.push_back(room);
  w.boxes.push_back({"showcase", {7, 7, 0}, {1, 1, 1.5}, 0.0, "concrete"});
  w.boxes.push_back({"bench", {2, 8, 0}, {1.5, 0.4, 0.4}, 0.0, "concrete"});
  w.boxes.push_back({"glass_panel", {5, 8, 0}, {2, 0.02, 2}, 0.0, "glass"});
  w.cylinders.push_back({"column", {8, 2}, 0.3, 3.0, 0.0, "concrete"});
  Door door;
  door.id = "door";
  door.hinge_m = {3, 3};
  door.closed_yaw_rad = 0.0;
  door.open_yaw_rad = std::numbers::pi / 2;
  door.width_m = 0.9;
  door.material = "concrete";
  w.doors.push_back(door);
  return w;
}

BodySpec Visitor(const std::string& id, core::Pose2 pose, bool driven) {
  BodySpec s;
  s.id = id;
  s.shape.type = BodyShapeType::kCylinder;
  s.shape.radius_m = 0.25;
  s.shape.height_m = 1.7;
  s.mass_kg = 70.0;
  s.pose = pose;
  s.material = "concrete";
  s.driven = driven;
  return s;
}

int SegmentsOf(const core::PlanarSection& s, const std::string& id) {
  int n = 0;
  for (const auto& seg : s.segments) n += s.elements[seg.element].id == id;
  return n;
}

// The section holds what spans the cut height: the bench only below 0.4 m, glass
// flagged transparent, the column as a circle, walls as inner and outer loops.
TEST(WorldTest, SectionFollowsHeightsAndMaterials) {
  World world(TestRoom(), {});
  const core::PlanarSection high = world.SectionAt(0.5);
  EXPECT_EQ(SegmentsOf(high, "room"), 8);
  EXPECT_EQ(SegmentsOf(high, "showcase"), 4);
  EXPECT_EQ(SegmentsOf(high, "bench"), 0);
  EXPECT_EQ(SegmentsOf(high, "glass_panel"), 4);
  EXPECT_EQ(SegmentsOf(high, "door"), 4);
  ASSERT_EQ(high.circles.size(), 1u);
  EXPECT_DOUBLE_EQ(high.circles[0].radius_m, 0.3);
  for (const auto& seg : high.segments) {
    const auto& e = high.elements[seg.element];
    EXPECT_EQ(e.laser == core::LaserResponse::kTransparent, e.id == "glass_panel");
  }
  EXPECT_EQ(SegmentsOf(world.SectionAt(0.3), "bench"), 4);
  EXPECT_EQ(SegmentsOf(world.SectionAt(2.5), "room"), 0);
  EXPECT_EQ(world.SectionAt(2.5).circles.size(), 1u);  // the 3 m column
  // Wall length: outer 4 × 10.2, inner 4 × 9.8.
  double room_length = 0.0;
  for (const auto& seg : high.segments) {
    if (high.elements[seg.element].id == "room") room_length += (seg.b_m - seg.a_m).norm();
  }
  EXPECT_NEAR(room_length, 4 * 10.2 + 4 * 9.8, 1e-9);
}

// Opening a door swings its panel: its section moves from along x to along y.
TEST(WorldTest, DoorsSwingOpenAndClosed) {
  World world(TestRoom(), {});
  auto door_extent = [&]() {
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(1e9), hi = -lo;
    const core::PlanarSection s = world.SectionAt(1.0);
    for (const auto& seg : s.segments) {
      if (s.elements[seg.element].id != "door") continue;
      lo = lo.cwiseMin(seg.a_m);
      hi = hi.cwiseMax(seg.a_m);
    }
    return Eigen::Vector2d(hi - lo);
  };
  EXPECT_NEAR(door_extent().x(), 0.9, 1e-9);
  world.SetDoorOpen("door", true);
  EXPECT_NEAR(door_extent().y(), 0.9, 1e-9);
  EXPECT_NEAR(door_extent().x(), 0.04, 1e-9);
  EXPECT_THROW(world.SetDoorOpen("nope", true), std::out_of_range);
}

// A driven body holds its commanded velocity in free space: 1 m/s for 2 s.
TEST(WorldTest, DrivenBodyFollowsCommandedVelocity) {
  World world(TestRoom(), {});
  const int b = world.AddBody(Visitor("v", {2, 5, 0}, true));
  world.SetPlanarVelocity(b, {1.0, 0.0}, 0.5);
  for (int i = 0; i < 400; ++i) world.Step();
  const BodyState s = world.body_state(b);
  EXPECT_NEAR(s.pose.x_m, 4.0, 0.01);
  EXPECT_NEAR(s.pose.y_m, 5.0, 1e-3);
  EXPECT_NEAR(s.pose.theta_rad, 1.0, 0.01);
  EXPECT_NEAR(s.z_m, 0.85, 0.002);
  EXPECT_LT(s.tilt_rad, 1e-6);
  EXPECT_DOUBLE_EQ(world.time_s(), 2.0);
}

// A body driven into a wall stops at the wall's face and a contact with the
// wall is reported once.
TEST(WorldTest, WallsStopBodiesAndContactsAreReported) {
  World world(TestRoom(), {});
  const int b = world.AddBody(Visitor("v", {2, 5, 0}, true));
  world.SetPlanarVelocity(b, {1.0, 0.0}, 0.0);
  int begins = 0, touches = 0;
  for (int i = 0; i < 2000; ++i) {
    world.Step();
    for (const ContactChange& c : world.TakeContactChanges()) {
      ASSERT_NE(c.phase, ContactPhase::kEnd);
      EXPECT_EQ(world.elements()[c.a].id, "room");
      EXPECT_EQ(world.elements()[c.b].id, "v");
      EXPECT_NEAR(c.point_m.x(), 9.9, 0.02);
      if (c.phase == ContactPhase::kBegin) {
        ++begins;
        EXPECT_LT(c.distance_m, kContactDistanceM);
      } else {
        ++touches;  // a blow: it pressed into the wall or an impulse stopped it
        EXPECT_TRUE(c.distance_m <= 0.0 || c.impulse_ns > 0.0);
        EXPECT_TRUE(c.touched);
      }
    }
  }
  EXPECT_EQ(begins, 1);
  EXPECT_EQ(touches, 1);
  EXPECT_NEAR(world.body_state(b).pose.x_m, 9.9 - 0.25, 0.02);
  EXPECT_LT(world.body_state(b).tilt_rad, 1e-6);
}

// A body sliding past a wall 3 mm from it comes within contact distance and
// leaves without touching: the episode begins and ends, no touch, and its end
// carries the smallest gap. The same body 3 mm into the wall's path touches.
TEST(WorldTest, APassWithinContactDistanceIsNoTouch) {
  for (const double gap_m : {0.003, -0.003}) {
    World world(TestRoom(), {});
    // The room's left face is at x = 0.1; the visitor's radius is 0.25.
    const int b = world.AddBody(Visitor("v", {0.1 + 0.25 + std::max(gap_m, 0.01), 2, 0}, true));
    int begins = 0, touches = 0, ends = 0;
    double end_distance = 1.0;
    bool end_touched = true;
    for (int i = 0; i < 1200; ++i) {
      // Drift to the gap, slide along the wall for a second, then leave.
      const double vx = i < 200 ? -(std::max(gap_m, 0.01) - gap_m) : (i < 600 ? 0.0 : 0.5);
      world.SetPlanarVelocity(b, {vx, i < 600 ? 1.0 : 0.0}, 0.0);
      world.Step();
      for (const ContactChange& c : world.TakeContactChanges()) {
        begins += c.phase == ContactPhase::kBegin;
        touches += c.phase == ContactPhase::kTouch;
        if (c.phase == ContactPhase::kEnd) {
          ++ends;
          end_distance = c.distance_m;
          end_touched = c.touched;
        }
      }
    }
    SCOPED_TRACE(gap_m);
    EXPECT_EQ(begins, 1);
    EXPECT_EQ(ends, 1);
    EXPECT_EQ(touches, gap_m > 0 ? 0 : 1);
    EXPECT_EQ(end_touched, gap_m < 0);
    if (gap_m > 0) {
      EXPECT_NEAR(end_distance, gap_m, 0.001);
    }
  }
}

// A pushed upright body slides and stops after v²/(2 μ g), friction
// coefficients combined by their product (0.8 × 0.8) as Bullet does; the step
// discretization changes the distance by at most v·dt.
TEST(WorldTest, PushedBodySlidesFrictionDistance) {
  World world(TestRoom(), {});
  const int b = world.AddBody(Visitor("v", {2, 5, 0}, false));
  for (int i = 0; i < 100; ++i) world.Step();  // settle
  const double x0 = world.body_state(b).pose.x_m;
  world.ApplyImpulse(b, {70.0, 0.0});  // 1 m/s
  for (int i = 0; i < 400; ++i) world.Step();
  const double mu = 0.8 * 0.8;
  const double expected = 1.0 / (2.0 * mu * kG);
  EXPECT_NEAR(world.body_state(b).pose.x_m - x0, expected, 1.0 * world.step_s() + 1e-3);
  EXPECT_LT(world.body_state(b).velocity_mps.norm(), 1e-3);
}

// Teleporting puts a body at the pose, at rest.
TEST(WorldTest, TeleportMovesBodyAtRest) {
  World world(TestRoom(), {});
  const int b = world.AddBody(Visitor("v", {2, 5, 0}, false));
  world.ApplyImpulse(b, {70.0, 0.0});
  world.Step();
  world.Teleport(b, {6, 3, 1.0});
  world.Step();
  const BodyState s = world.body_state(b);
  EXPECT_NEAR(s.pose.x_m, 6.0, 1e-3);
  EXPECT_NEAR(s.pose.y_m, 3.0, 1e-3);
  EXPECT_NEAR(s.pose.theta_rad, 1.0, 1e-6);
}

// Two worlds given the same calls produce bit-identical states, with bodies
// colliding with each other and with walls.
TEST(WorldTest, SteppingIsDeterministic) {
  auto run = [] {
    World world(TestRoom(), {});
    for (int k = 0; k < 6; ++k) {
      std::string id = "v";
      id += std::to_string(k);
      const int b = world.AddBody(Visitor(id, {2.0 + k, 5.0, 0.0}, true));
      world.SetPlanarVelocity(b, {std::cos(k * 1.3), std::sin(k * 1.3)}, 0.0);
    }
    for (int i = 0; i < 3000; ++i) world.Step();
    std::vector<double> out;
    for (int b = 0; b < world.body_count(); ++b) {
      const BodyState s = world.body_state(b);
      out.insert(out.end(), {s.pose.x_m, s.pose.y_m, s.pose.theta_rad});
    }
    return out;
  };
  const std::vector<double> a = run();
  const std::vector<double> b = run();
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]) << i;
}

// A mesh element (an ASCII STL unit cube scaled by 2 and yawed) is cut into a
// counter-clockwise 2 m square, and bodies collide with it.
TEST(WorldTest, MeshesAreCutAndCollide) {
  const auto dir = std::filesystem::temp_directory_path() / "pavilion_world_test";
  std::filesystem::create_directories(dir);
  const std::string stl = (dir / "cube.stl").string();
  {
    // Unit cube [0,1]^3, outward-facing triangles.
    const double v[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                            {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
    const int f[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                          {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
    std::ofstream out(stl);
    out << "solid cube\n";
    for (const auto& t : f) {
      out << " facet normal 0 0 0\n  outer loop\n";
      for (int k : t) out << "   vertex " << v[k][0] << " " << v[k][1] << " " << v[k][2] << "\n";
      out << "  endloop\n endfacet\n";
    }
    out << "endsolid cube\n";
  }
  WorldDescription d = TestRoom();
  Mesh m;
  m.id = "sculpture";
  m.file = stl;
  m.position_m = {4, 4, 0};
  m.yaw_rad = 0.3;
  m.scale = {2, 2, 2};
  m.material = "concrete";
  d.meshes.push_back(m);
  World world(d, {});
  const core::PlanarSection s = world.SectionAt(1.0);
  double length = 0.0;
  for (const auto& seg : s.segments) {
    if (s.elements[seg.element].id != "sculpture") continue;
    length += (seg.b_m - seg.a_m).norm();
    // Solid on the left: the square's centre is left of every segment.
    const Eigen::Vector2d centre =
        Eigen::Vector2d(4, 4) +
        Eigen::Vector2d(std::cos(0.3) - std::sin(0.3), std::sin(0.3) + std::cos(0.3));
    const Eigen::Vector2d d1 = seg.b_m - seg.a_m, d2 = centre - seg.a_m;
    EXPECT_GT(d1.x() * d2.y() - d1.y() * d2.x(), 0.0);
  }
  EXPECT_NEAR(length, 8.0, 1e-9);
  EXPECT_EQ(SegmentsOf(world.SectionAt(2.5), "sculpture"), 0);
  // A body driven down at the cube stops on its upper face, which crosses
  // x = 4.5 at y ≈ 6.25, so the body's centre stays near 6.25 + 0.25.
  const int b = world.AddBody(Visitor("v", {4.5, 7.5, 0}, true));
  world.SetPlanarVelocity(b, {0.0, -1.0}, 0.0);
  for (int i = 0; i < 600; ++i) world.Step();
  EXPECT_GT(world.body_state(b).pose.y_m, 6.3);
  EXPECT_LT(world.body_state(b).pose.y_m, 6.7);
}

}  // namespace
}  // namespace pavilion::sim
