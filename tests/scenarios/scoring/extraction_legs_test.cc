// Visitors' legs do not produce lines (thesis §6.5): leg-sized cylinders
// (10-15 cm across) 0.5-4 m in front of a simulated sick_lms200; segments
// supported mostly by leg readings must be rejected in >= 99 % of scans.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>

#include "core/features/line_extraction.h"
#include "core/random/random_stream.h"
#include "sim/sensors/laser_scanner.h"
#include "sim/world/world.h"

namespace pavilion {
namespace {

TEST(ExtractionLegs, LegSizedCylindersGiveNoLines) {
  sim::WorldDescription d;
  d.name = "legs";
  d.materials["wall"] = sim::Material{0.8, 0.0, {0.7, 0.7, 0.7, 1}, core::LaserResponse::kNormal};
  d.floor = {{-1, -6}, {9, 6}, "wall", {}};
  sim::Wall room;
  room.id = "room";
  room.points_m = {{-0.5, -5}, {8, -5}, {8, 5}, {-0.5, 5}};
  room.closed = true;
  room.thickness_m = 0.2;
  room.height_m = 2.0;
  room.material = "wall";
  d.walls.push_back(room);
  core::RandomStream rng(9, 1);
  const core::LineExtractionOptions options = core::LineExtractionOptions::SickLms200();
  const int kScans = 200;
  int scans_with_leg_lines = 0;
  int leg_readings = 0;
  for (int k = 0; k < kScans; ++k) {
    sim::World world(d, sim::WorldOptions{});
    // Three people, each two legs 0.2 m apart, 0.5-4 m ahead.
    for (int p = 0; p < 3; ++p) {
      const double range = rng.Uniform(0.5, 4.0);
      const double bearing = rng.Uniform(-1.2, 1.2);
      const Eigen::Vector2d c(range * std::cos(bearing), range * std::sin(bearing));
      for (int leg = 0; leg < 2; ++leg) {
        sim::BodySpec s;
        s.id = "leg_" + std::to_string(p) + "_" + std::to_string(leg);
        s.shape.radius_m = rng.Uniform(0.05, 0.075);
        s.shape.height_m = 0.9;
        s.mass_kg = 10.0;
        s.pose = {c.x(), c.y() + (leg == 0 ? -0.1 : 0.1), 0.0};
        s.material = "wall";
        world.AddBody(s);
      }
    }
    sim::LaserScanner scanner("front", sim::LaserScannerOptions::Profile("sick_lms200"),
                              core::Pose2{}, 0.5, core::RandomStream(11, k));
    core::LaserScanTruth truth;
    const core::LaserScan scan = scanner.ScanFrom(world, core::Pose2{}, 0.0, -1, &truth);
    const std::vector<core::Segment> segments = core::ExtractLines(scan, options);
    bool leg_line = false;
    for (const core::Segment& s : segments) {
      int legs = 0;
      for (int i = s.first_index; i <= s.last_index; ++i) {
        const int e = truth.element[i];
        legs += e >= 0 && world.elements()[e].dynamic;
      }
      leg_line |= 2 * legs > s.last_index - s.first_index + 1;
    }
    for (int e : truth.element) leg_readings += e >= 0 && world.elements()[e].dynamic;
    scans_with_leg_lines += leg_line;
  }
  std::printf("scans with a line on legs: %d of %d; leg readings per scan %.1f\n",
              scans_with_leg_lines, kScans, static_cast<double>(leg_readings) / kScans);
  EXPECT_GT(leg_readings, kScans * 10);  // the legs are seen
  EXPECT_LE(scans_with_leg_lines, kScans / 100);
}

}  // namespace
}  // namespace pavilion
