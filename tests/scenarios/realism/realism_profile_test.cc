// The `realism:` profile (issue 20): what it changes in the robots, the map
// and the world, and that `ideal` changes nothing.
#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "core/geometry/segment2.h"
#include "scenarios/config/input_error.h"
#include "scenarios/config/scenario.h"
#include "scenarios/maps/map_derivation.h"
#include "scenarios/realism/robot_realism.h"
#include "scenarios/realism/world_realism.h"
#include "scenarios/run/scenario_runner.h"
#include "sim/world/world.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

Scenario OfficeTour(std::vector<std::string> sets, std::uint64_t seed = 1) {
  ScenarioOverrides overrides;
  overrides.seed = seed;
  overrides.assignments = std::move(sets);
  return LoadScenarioFile(std::string(PAVILION_SOURCE_DIR) + "/scenarios/office_tour.yaml",
                          overrides);
}

const sim::RobotConfig& Robot(const Scenario& s) { return s.robots.front().config; }

TEST(RealismProfileTest, IdealChangesNothing) {
  const Scenario plain = OfficeTour({});
  const Scenario ideal = OfficeTour({"realism=ideal"});
  EXPECT_FALSE(plain.realism.realistic);
  EXPECT_FALSE(ideal.realism.realistic);
  for (const Scenario* s : {&plain, &ideal}) {
    EXPECT_EQ(Robot(*s).systematic.wheel_radius_ratio, 1.0);
    EXPECT_EQ(Robot(*s).systematic.mean_radius_factor, 1.0);
    EXPECT_FALSE(Robot(*s).encoders.noise);
    for (const sim::LaserMount& m : Robot(*s).lasers) {
      EXPECT_FALSE(m.options.systematic.Any()) << m.id;
      EXPECT_EQ(m.options.range_sigma_m, 0.01);
      EXPECT_EQ(m.options.timestamp_bias_s, 0.0);
    }
  }
}

TEST(RealismProfileTest, RealisticBuildsARealRobotFromTheSeed) {
  const Scenario a = OfficeTour({"realism=realistic"}, 1);
  const Scenario b = OfficeTour({"realism=realistic"}, 1);
  const Scenario c = OfficeTour({"realism=realistic"}, 2);
  ASSERT_TRUE(a.realism.realistic);
  const sim::RobotConfig& r = Robot(a);
  EXPECT_NE(r.systematic.wheel_radius_ratio, 1.0);
  EXPECT_NEAR(r.systematic.wheel_radius_ratio, 1.0, 5 * a.realism.wheel_radius_ratio_sigma);
  EXPECT_TRUE(r.encoders.noise);
  EXPECT_EQ(r.encoders.k_left_m, a.realism.wheel_noise_k_m);
  ASSERT_EQ(r.lasers.size(), 2u);
  std::set<std::uint64_t> seeds;
  for (std::size_t k = 0; k < r.lasers.size(); ++k) {
    const sim::LaserSystematicErrors& e = r.lasers[k].options.systematic;
    EXPECT_TRUE(e.Any());
    EXPECT_NEAR(e.mount_error.x_m, 0.0, 5 * a.realism.laser_mount_sigma_m);
    EXPECT_EQ(e.surface_seed, SurfaceBiasSeed(1));  // shared by every laser of the run
    EXPECT_EQ(e.correlated_sigma_m, a.realism.laser_correlated_sigma_m);
    EXPECT_EQ(r.lasers[k].options.range_sigma_m, a.realism.laser_range_sigma_m);
    // A latency of its own (the stamps lag or lead the encoders'), and jitter.
    EXPECT_NE(r.lasers[k].options.timestamp_bias_s, 0.0);
    EXPECT_LT(std::abs(r.lasers[k].options.timestamp_bias_s), 5 * a.realism.laser_latency_sigma_s);
    EXPECT_EQ(e.stamp_jitter_s, a.realism.laser_stamp_jitter_s);
    seeds.insert(e.seed);
    // The same seed draws the same robot; another seed another one.
    EXPECT_EQ(e.mount_error.x_m, Robot(b).lasers[k].options.systematic.mount_error.x_m);
    EXPECT_NE(e.mount_error.x_m, Robot(c).lasers[k].options.systematic.mount_error.x_m);
  }
  EXPECT_EQ(seeds.size(), 2u);  // each laser its own streams
}

// One magnitude changed leaves the other draws as they were (streams by name).
TEST(RealismProfileTest, AMagnitudeChangesOnlyItsOwnDraws) {
  const Scenario a = OfficeTour({"realism=realistic"});
  const Scenario b = OfficeTour({"realism.profile=realistic", "realism.laser_mount_sigma_m=0.006"});
  EXPECT_EQ(Robot(a).systematic.wheelbase_factor, Robot(b).systematic.wheelbase_factor);
  const auto& ea = Robot(a).lasers[0].options.systematic;
  const auto& eb = Robot(b).lasers[0].options.systematic;
  EXPECT_DOUBLE_EQ(eb.mount_error.x_m, 2.0 * ea.mount_error.x_m);
  EXPECT_EQ(eb.mount_error.theta_rad, ea.mount_error.theta_rad);
  EXPECT_EQ(eb.seed, ea.seed);
}

TEST(RealismProfileTest, BadInputNamesTheKey) {
  try {
    OfficeTour({"realism=harsh"});
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("realism"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("ideal, realistic"), std::string::npos) << e.what();
  }
  try {
    OfficeTour({"realism.profile=realistic", "realism.clutter_per_m=5"});
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("realism.clutter_per_m"), std::string::npos) << e.what();
  }
}

// The survey's wall errors: each line moved and turned by its own end
// errors (2 cm each: about 1.4 cm at its middle); the recorded covariance states it.
TEST(RealismProfileTest, WallOffsetsMoveWholeWalls) {
  const Scenario s = OfficeTour({});
  const sim::World world(s.world, s.physics);
  MapDerivationOptions exact;
  exact.noise_sigma_m = 0.0;
  MapDerivationOptions offset = exact;
  offset.wall_offset_sigma_m = 0.02;
  const core::RobotMap a = DeriveRobotMap(world, exact);
  const core::RobotMap b = DeriveRobotMap(world, offset);
  ASSERT_EQ(a.segments.size(), b.segments.size());
  ASSERT_GT(a.segments.size(), 20u);
  double sum2 = 0.0;
  int turned = 0;
  for (std::size_t k = 0; k < a.segments.size(); ++k) {
    const core::MapSegment& sa = a.segments[k];
    const core::MapSegment& sb = b.segments[k];
    // The middle of the wall moves along the normal by (e_first + e_last) / 2.
    const Eigen::Vector2d mid =
        0.5 * (sa.first_endpoint.position_m + sa.second_endpoint.position_m);
    const double moved = sb.line.normal().dot(mid) - sb.line.r_m;
    sum2 += moved * moved;
    if (std::abs(sb.line.alpha_rad - sa.line.alpha_rad) > 1e-4) ++turned;
    EXPECT_GT(sb.line.covariance(1, 1), sa.line.covariance(1, 1)) << sa.id;
    EXPECT_GT(sb.line.covariance(0, 0), sa.line.covariance(0, 0)) << sa.id;
  }
  const double rms = std::sqrt(sum2 / a.segments.size());
  // 30-odd draws of sigma 2 cm / sqrt(2): the sample sigma within 40 %.
  EXPECT_NEAR(rms, 0.02 / std::sqrt(2.0), 0.006) << a.segments.size() << " segments";
  EXPECT_GT(turned, static_cast<int>(a.segments.size()) / 2);
}

// Clutter stands against inner wall faces, off the map's roads, never on
// another object; doors only open; the same seed the same world.
TEST(RealismProfileTest, ClutterStandsAgainstWallsOffTheRoads) {
  const Scenario s = OfficeTour({"realism=realistic"});
  const sim::World survey(s.world, s.physics);
  MapDerivationOptions options;
  const core::RobotMap map = DeriveRobotMap(survey, options);
  ClutterKeepOut keep_out;
  AddRoads(map, &keep_out);
  const RealWorldChanges a = DrawRealWorld(s.realism, 1, survey, s.world, keep_out);
  const RealWorldChanges b = DrawRealWorld(s.realism, 1, survey, s.world, keep_out);
  ASSERT_GT(a.boxes.size() + a.cylinders.size(), 10u);
  EXPECT_EQ(a.boxes.size(), b.boxes.size());
  for (const sim::Box& box : a.boxes) {
    const Eigen::Vector2d c = box.pose.translation();
    for (const auto& [p, q] : keep_out.roads_m) {
      EXPECT_GE(core::PointSegmentDistance(c, p, q), keep_out.clearance_m) << box.id;
    }
    // Against a wall: a ray from the centre backwards meets one within its depth and a gap.
    const Eigen::Vector2d back(std::sin(box.pose.theta_rad), -std::cos(box.pose.theta_rad));
    const double reach = 0.5 * box.size_m.y() + 0.06;
    const Eigen::Vector3d from(c.x(), c.y(), 0.5);
    const sim::RayHit toward_a =
        survey.CastRay(from, from + reach * Eigen::Vector3d(back.x(), back.y(), 0));
    const sim::RayHit toward_b =
        survey.CastRay(from, from - reach * Eigen::Vector3d(back.x(), back.y(), 0));
    EXPECT_TRUE(toward_a.hit || toward_b.hit) << box.id << " stands free of any wall";
  }
  for (const std::string& id : a.opened_doors) {
    for (const sim::Door& d : s.world.doors) {
      if (d.id == id) {
        EXPECT_FALSE(d.open) << id;
      }
    }
  }
  // Twice the density, about twice the objects (the free faces limit it).
  RealismProfile dense = s.realism;
  dense.clutter_per_m *= 2.0;
  const RealWorldChanges c = DrawRealWorld(dense, 1, survey, s.world, keep_out);
  EXPECT_GT(c.boxes.size() + c.cylinders.size(), 1.4 * (a.boxes.size() + a.cylinders.size()));
  // Carpet on about a quarter of the floor's 4 m squares, each 0.1-0.5 %.
  const sim::Floor& floor = s.world.floor;
  const double squares = std::ceil((floor.max_m.x() - floor.min_m.x()) / 4.0) *
                         std::ceil((floor.max_m.y() - floor.min_m.y()) / 4.0);
  EXPECT_NEAR(a.carpets.size() / squares, s.realism.carpet_fraction, 0.12) << squares;
  for (const sim::FloorPatch& p : a.carpets) {
    EXPECT_GE(p.travel_scale_error, 0.2 * s.realism.carpet_travel_error);
    EXPECT_LE(p.travel_scale_error, s.realism.carpet_travel_error);
  }
  RealismProfile none = s.realism;
  none.clutter_per_m = 0.0;
  EXPECT_TRUE(DrawRealWorld(none, 1, survey, s.world, keep_out).boxes.empty());
}

// The floor's relief is a draw of its own: its maximum slope scales the same
// waves, and turning it off or changing it leaves the clutter, the doors and
// the carpet as they were. The ideal profile's floor stays flat.
TEST(RealismProfileTest, TheFloorReliefIsADrawOfItsOwn) {
  const Scenario s = OfficeTour({"realism=realistic"});
  const sim::World survey(s.world, s.physics);
  const ClutterKeepOut keep_out;
  const RealWorldChanges a = DrawRealWorld(s.realism, 1, survey, s.world, keep_out);
  ASSERT_FALSE(a.relief.flat());
  const auto same_world = [&](const RealWorldChanges& b) {
    ASSERT_EQ(a.boxes.size(), b.boxes.size());
    for (std::size_t k = 0; k < a.boxes.size(); ++k) {
      EXPECT_EQ(a.boxes[k].pose, b.boxes[k].pose) << a.boxes[k].id;
    }
    EXPECT_EQ(a.opened_doors, b.opened_doors);
    ASSERT_EQ(a.carpets.size(), b.carpets.size());
    for (std::size_t k = 0; k < a.carpets.size(); ++k) {
      EXPECT_EQ(a.carpets[k].travel_scale_error, b.carpets[k].travel_scale_error);
    }
  };
  RealismProfile half = s.realism;
  half.floor_max_slope_rad *= 0.5;
  const RealWorldChanges h = DrawRealWorld(half, 1, survey, s.world, keep_out);
  same_world(h);
  ASSERT_EQ(h.relief.waves().size(), a.relief.waves().size());
  const double ratio = std::tan(half.floor_max_slope_rad) / std::tan(s.realism.floor_max_slope_rad);
  for (std::size_t k = 0; k < a.relief.waves().size(); ++k) {
    EXPECT_EQ(h.relief.waves()[k].wavevector_radpm, a.relief.waves()[k].wavevector_radpm);
    EXPECT_NEAR(h.relief.waves()[k].amplitude_m, ratio * a.relief.waves()[k].amplitude_m, 1e-15);
  }
  RealismProfile flat = s.realism;
  flat.floor_max_slope_rad = 0.0;
  const RealWorldChanges f = DrawRealWorld(flat, 1, survey, s.world, keep_out);
  same_world(f);
  EXPECT_TRUE(f.relief.flat());
  // Applied, the description's floor carries it.
  sim::WorldDescription d = s.world;
  ApplyRealWorld(a, &d);
  EXPECT_EQ(d.floor.relief.HeightAt({1.0, 2.0}), a.relief.HeightAt({1.0, 2.0}));
  EXPECT_TRUE(DrawRealWorld(OfficeTour({}).realism, 1, survey, s.world, keep_out).relief.flat());
  try {
    OfficeTour({"realism.profile=realistic", "realism.floor_max_slope_deg=5"});
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("realism.floor_max_slope_deg"), std::string::npos)
        << e.what();
  }
}

// A realistic run builds its world from the surveyed one plus clutter and open
// doors, and says so in its metrics; an ideal run's metrics have no such block.
TEST(RealismProfileTest, ARealisticRunReportsWhatItAdded) {
  const std::filesystem::path dir = pavilion::testing::TestDir();
  ScenarioOverrides overrides;
  overrides.duration_s = 5.0;
  for (const char* profile : {"ideal", "realistic"}) {
    overrides.assignments = {std::string("realism=") + profile};
    const Scenario s = LoadScenarioFile(
        std::string(PAVILION_SOURCE_DIR) + "/scenarios/office_tour.yaml", overrides);
    const RunMetrics m = RunScenario(s, RunOptions{(dir / profile).string(), false}).metrics;
    if (std::string(profile) == "ideal") {
      EXPECT_FALSE(m.realism.has_value());
      continue;
    }
    ASSERT_TRUE(m.realism.has_value());
    EXPECT_GT(m.realism->clutter_objects, 10);
    EXPECT_GT(m.realism->carpet_squares, 0);
    EXPECT_EQ(m.robots.front().collisions, 0);
  }
}

}  // namespace
}  // namespace pavilion::scenarios
