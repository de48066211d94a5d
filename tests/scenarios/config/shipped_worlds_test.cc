// Checks the shipped worlds against what the thesis says of the places they
// rebuild (chapters 4, 6 and 7), through the real loader and Bullet world.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <string>

#include "scenarios/config/data_paths.h"
#include "scenarios/config/world_loader.h"
#include "sim/world/world.h"

namespace pavilion::scenarios {
namespace {

constexpr double kBeamHeightM = 0.5;  // scan plane assumed in the world files

sim::WorldDescription Load(const std::string& name) {
  return LoadWorldFile(ResolveWorldPath(name));
}

int CountPrefix(const std::map<std::string, sim::Place>& places, const std::string& prefix) {
  int n = 0;
  for (const auto& [name, place] : places) n += name.starts_with(prefix);
  return n;
}

bool FreeAt(const core::PlanarSection& s, const Eigen::Vector2d& p, double r) {
  for (const auto& seg : s.segments) {
    const Eigen::Vector2d ab = seg.b_m - seg.a_m;
    const double t = std::clamp((p - seg.a_m).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    if ((seg.a_m + t * ab - p).norm() < r) return false;
  }
  for (const auto& c : s.circles) {
    if ((c.center_m - p).norm() < c.radius_m + r) return false;
  }
  return true;
}

// Expo.02 hall (§6.3.1, §6.5): 15 stations, ten docks on the right, a bottom wall
// whose segments differ by less than 5°, glass and low objects the beam misses.
TEST(ShippedWorldsTest, ExpoHallFollowsTheThesis) {
  const sim::WorldDescription d = Load("expo_hall");
  EXPECT_EQ(CountPrefix(d.places, "station_"), 15);
  EXPECT_EQ(CountPrefix(d.places, "dock_"), 10);
  ASSERT_TRUE(d.places.contains("entrance"));
  ASSERT_TRUE(d.places.contains("exit"));
  EXPECT_LT(d.places.at("entrance").pose->y_m, d.places.at("exit").pose->y_m);  // bottom, top

  // The bottom wall: the first four segments of wall_east.
  const sim::Wall* east = nullptr;
  for (const auto& w : d.walls) {
    if (w.id == "wall_east") east = &w;
  }
  ASSERT_NE(east, nullptr);
  double lo = 1e9, hi = -1e9;
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector2d dir = east->points_m[i + 1] - east->points_m[i];
    const double heading_deg = std::atan2(dir.y(), dir.x()) * 180.0 / std::numbers::pi;
    lo = std::min(lo, heading_deg);
    hi = std::max(hi, heading_deg);
  }
  EXPECT_GT(hi - lo, 0.5);  // not one straight wall
  EXPECT_LT(hi - lo, 5.0);

  sim::World world(d, {});
  const core::PlanarSection beam = world.SectionAt(kBeamHeightM);
  int glass = 0, benches_seen = 0, docks_seen = 0;
  for (const auto& seg : beam.segments) {
    const auto& e = beam.elements[seg.element];
    glass += e.laser == core::LaserResponse::kTransparent;
    benches_seen += e.id.starts_with("bench");
    docks_seen += e.id.starts_with("dock");
  }
  EXPECT_GT(glass, 0);
  EXPECT_EQ(benches_seen, 0);
  EXPECT_EQ(docks_seen, 0);
  // Benches and docks are still solid: they appear lower down.
  int low = 0;
  for (const auto& seg : world.SectionAt(0.2).segments) {
    low += world.elements()[seg.element].id.starts_with("bench");
  }
  EXPECT_GT(low, 0);
  // Every station pose stands in free space with room for a robot (0.35 m).
  for (const auto& [name, place] : d.places) {
    if (!name.starts_with("station_") || !place.pose) continue;
    EXPECT_TRUE(FreeAt(world.SectionAt(0.05), place.pose->translation(), 0.35)) << name;
  }
}

// Institute floor (Fig. 4.8): 50 × 30 m, twelve offices with doors, the rooms
// of the thesis' tour, and tour places in free space.
TEST(ShippedWorldsTest, OfficeFloorHasTheTourRooms) {
  const sim::WorldDescription d = Load("office_floor");
  EXPECT_EQ(CountPrefix(d.places, "office_"), 12);
  for (const char* room : {"lab", "elevator", "seminar_room", "coffee_room", "mail_room"}) {
    EXPECT_TRUE(d.places.contains(room)) << room;
  }
  EXPECT_GE(d.doors.size(), 12u);
  int open = 0, closed = 0;
  for (const auto& door : d.doors) (door.open ? open : closed)++;
  EXPECT_GT(open, 0);
  EXPECT_GT(closed, 0);
  sim::World world(d, {});
  Eigen::Vector2d lo, hi;
  ASSERT_TRUE(world.SectionAt(kBeamHeightM).Bounds(&lo, &hi));
  EXPECT_GE(lo.minCoeff(), -0.5);
  EXPECT_LE(hi.x(), 50.5);
  EXPECT_LE(hi.y(), 30.5);
  EXPECT_GT(hi.x() - lo.x(), 45.0);
  const core::PlanarSection floor_level = world.SectionAt(0.05);
  for (const auto& [name, place] : d.places) {
    if (!place.pose) continue;
    EXPECT_TRUE(FreeAt(floor_level, place.pose->translation(), 0.3)) << name;
  }
}

// The small lab of Fig. 7.8: the exploration start (0, 0) is free space.
TEST(ShippedWorldsTest, SmallLabStartIsFree) {
  const sim::WorldDescription d = Load("small_lab");
  ASSERT_TRUE(d.places.contains("start"));
  EXPECT_NEAR(d.places.at("start").pose->translation().norm(), 0.0, 1e-12);
  sim::World world(d, {});
  EXPECT_TRUE(FreeAt(world.SectionAt(0.05), {0.0, 0.0}, 0.3));
}

}  // namespace
}  // namespace pavilion::scenarios
