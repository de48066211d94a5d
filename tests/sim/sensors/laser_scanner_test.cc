#include "sim/sensors/laser_scanner.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "tests/support/world_robot.h"

namespace pavilion::sim {
namespace {

using core::LaserResponse;
using core::Pose2;

constexpr double kPi = std::numbers::pi;
constexpr double kMountHeightM = 0.3;
constexpr std::uint64_t kSeed = 20240611;

Material MaterialWith(LaserResponse response) {
  Material m;
  m.laser = response;
  return m;
}

// A world with one material per laser response and a large floor, no walls.
WorldDescription EmptyWorld() {
  WorldDescription w;
  w.name = "laser_test";
  w.materials["paint"] = MaterialWith(LaserResponse::kNormal);
  w.materials["reflector"] = MaterialWith(LaserResponse::kRetroReflective);
  w.materials["velvet"] = MaterialWith(LaserResponse::kDark);
  w.materials["chrome"] = MaterialWith(LaserResponse::kSpecular);
  w.materials["glass"] = MaterialWith(LaserResponse::kTransparent);
  w.floor = {{-30, -30}, {30, 30}, "paint", {}};
  return w;
}

Wall WallOf(const std::string& id, std::vector<Eigen::Vector2d> points, bool closed,
            const std::string& material) {
  Wall wall;
  wall.id = id;
  wall.points_m = std::move(points);
  wall.closed = closed;
  wall.thickness_m = 0.1;
  wall.height_m = 2.0;
  wall.material = material;
  return wall;
}

// A straight wall whose face towards the origin is the line x = face_x_m.
Wall WallFacingOrigin(const std::string& id, double face_x_m, const std::string& material) {
  const double centre_x = face_x_m + 0.05;  // half of the 0.1 m thickness
  return WallOf(id, {{centre_x, -20.0}, {centre_x, 20.0}}, false, material);
}

// A 6 m × 4 m room: the polyline is the wall centre line, so with 0.1 m
// thickness the inner faces are x = 0.05, x = 5.95, y = 0.05, y = 3.95.
constexpr double kRoomMinX = 0.05, kRoomMaxX = 5.95, kRoomMinY = 0.05, kRoomMaxY = 3.95;
WorldDescription Room() {
  WorldDescription w = EmptyWorld();
  w.walls.push_back(WallOf("room", {{0, 0}, {6, 0}, {6, 4}, {0, 4}}, true, "paint"));
  return w;
}

// The world's laser rays meet the static geometry exactly (baked triangles,
// walls without collision margin): only floating-point error remains (m).
constexpr double kRayCastTolM = 1e-9;

// Tolerance of a noise-free reading of a wall against its analytic range:
// half the quantization step (the issue asks for 1 mm with noise off).
double WallTolerance(double resolution_m, double /*cos_incidence*/) {
  return 0.5 * resolution_m + kRayCastTolM;
}

struct AnalyticHit {
  double range_m = std::numeric_limits<double>::infinity();
  double cos_incidence = 1.0;
};

// The ray from a point inside the room along `angle_rad` to the room's inner faces.
AnalyticHit RoomHit(const Eigen::Vector2d& from, double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  AnalyticHit hit;
  auto face = [&](double t, double cos_incidence) {
    if (t < hit.range_m) hit = {t, cos_incidence};
  };
  if (c > 0) face((kRoomMaxX - from.x()) / c, c);
  if (c < 0) face((kRoomMinX - from.x()) / c, -c);
  if (s > 0) face((kRoomMaxY - from.y()) / s, s);
  if (s < 0) face((kRoomMinY - from.y()) / s, -s);
  return hit;
}

int ElementIndex(const World& world, const std::string& id) {
  const auto& elements = world.elements();
  for (std::size_t i = 0; i < elements.size(); ++i) {
    if (elements[i].id == id) return static_cast<int>(i);
  }
  return -1;
}

LaserScannerOptions Exact(LaserScannerOptions o) {
  o.noise = false;
  o.effects = false;
  return o;
}

LaserScanner MakeScanner(const LaserScannerOptions& options, Pose2 robot_from_sensor = {},
                         std::uint64_t stream_id = 1) {
  return LaserScanner("laser", options, robot_from_sensor, kMountHeightM,
                      core::RandomStream(kSeed, stream_id));
}

// The robot-to-sensor mount used in the room tests.
const Pose2 kMount{0.15, 0.05, 0.1};

// With noise and effects off every reading is the geometric range of its ray
// (the truth), quantized, and that is the range to the room's inner faces.
TEST(LaserScannerTest, NoiseFreeRangesMatchAnalyticRoom) {
  World world(Room(), {});
  const int room = ElementIndex(world, "room");
  for (const std::string profile : {"sick_lms200", "acuity_accurange"}) {
    LaserScanner scanner = MakeScanner(Exact(LaserScannerOptions::Profile(profile)), kMount);
    const Pose2 world_from_robot{2.2, 1.7, 0.4};
    core::LaserScanTruth truth;
    const core::LaserScan scan = scanner.ScanFrom(world, world_from_robot, 5.0, -1, &truth);
    const Pose2 world_from_sensor = world_from_robot * kMount;
    ASSERT_EQ(scan.readings.size(), static_cast<std::size_t>(scanner.options().beams));
    for (std::size_t i = 0; i < scan.readings.size(); ++i) {
      const core::LaserReading& r = scan.readings[i];
      const AnalyticHit expected =
          RoomHit(world_from_sensor.translation(), world_from_sensor.theta_rad + r.bearing_rad);
      const double q = scanner.options().range_resolution_m;
      ASSERT_TRUE(r.valid) << profile << " " << i;
      EXPECT_NEAR(r.range_m, truth.true_range_m[i], 0.5 * q + 1e-12) << profile << " " << i;
      EXPECT_NEAR(r.range_m, expected.range_m, WallTolerance(q, expected.cos_incidence))
          << profile << " " << i;
      EXPECT_NEAR(truth.true_range_m[i], expected.range_m,
                  WallTolerance(0.0, expected.cos_incidence))
          << profile << " " << i;
      EXPECT_EQ(truth.element[i], room);
      EXPECT_FALSE(r.reflector);
      EXPECT_EQ(truth.world_from_sensor[i], world_from_sensor);
    }
  }
}

// SICK LMS 200 noise over 1,000 scans: ≥ 99.7% of readings within 3σ of the
// analytic range (plus the noise-free tolerance), and about the geometric range
// of each ray zero mean and variance σ² + q²/12, within five standard errors.
TEST(LaserScannerTest, Lms200NoiseIsGaussianWithConfiguredSigma) {
  World world(Room(), {});
  const LaserScannerOptions options = LaserScannerOptions::Profile("sick_lms200");
  LaserScanner scanner = MakeScanner(options, kMount);
  const Pose2 world_from_robot{2.2, 1.7, 0.4};
  const Pose2 world_from_sensor = world_from_robot * kMount;
  std::vector<AnalyticHit> expected;
  for (int i = 0; i < options.beams; ++i) {
    expected.push_back(RoomHit(world_from_sensor.translation(),
                               world_from_sensor.theta_rad + scanner.bearing_rad(i)));
  }
  const double sigma = options.range_sigma_m;
  const double q = options.range_resolution_m;
  const int kScans = 1000;
  long n = 0, within = 0;
  double sum = 0.0, sum_sq = 0.0;
  for (int s = 0; s < kScans; ++s) {
    core::LaserScanTruth truth;
    const core::LaserScan scan = scanner.ScanFrom(world, world_from_robot, 0.1 * s, -1, &truth);
    for (int i = 0; i < options.beams; ++i) {
      const core::LaserReading& r = scan.readings[i];
      ASSERT_TRUE(r.valid);
      ++n;
      within += std::abs(r.range_m - expected[i].range_m) <=
                3.0 * sigma + WallTolerance(q, expected[i].cos_incidence);
      const double e = r.range_m - truth.true_range_m[i];
      sum += e;
      sum_sq += e * e;
    }
  }
  EXPECT_GE(static_cast<double>(within) / n, 0.997);
  const double mean = sum / n;
  const double variance = sum_sq / n - mean * mean;
  const double expected_variance = sigma * sigma + q * q / 12.0;
  EXPECT_NEAR(mean, 0.0, 5.0 * sigma / std::sqrt(n));
  EXPECT_NEAR(variance, expected_variance, 5.0 * std::sqrt(2.0 / n) * expected_variance);
}

// Timing of the readings. LMS 200: two interlaced 75 Hz mirror turns, even
// readings (0°, 1°, ...) in the first, odd ones (0.5°, 1.5°, ...) a turn later;
// the last reading (179.5°) comes 1 + 179.5/360 turns after the first. Acuity:
// one reading per millisecond over one turn (§2.2.1.4).
TEST(LaserScannerTest, ReadingTimesFollowTheMirror) {
  const LaserScanner lms = MakeScanner(LaserScannerOptions::Profile("sick_lms200"));
  const double turn_s = 1.0 / kLms200MirrorRateHz;
  double last = 0.0;
  for (int i = 0; i < 361; ++i) {
    EXPECT_NEAR(lms.bearing_rad(i), -kPi / 2 + i * kPi / 360, 1e-12);
    const double expected = turn_s * ((i % 2) + i * 0.5 / 360.0);
    EXPECT_NEAR(lms.time_offset_s(i), expected, 1e-12) << i;
    if (i % 2 == 0) {
      EXPECT_LE(lms.time_offset_s(i), turn_s / 2 + 1e-12);
    } else {
      EXPECT_GE(lms.time_offset_s(i), turn_s);
    }
    last = std::max(last, lms.time_offset_s(i));
  }
  EXPECT_NEAR(last, lms.time_offset_s(359), 1e-15);
  EXPECT_NEAR(last, lms.options().sweep_s, 1e-15);
  EXPECT_NEAR(last, 0.01998, 1e-5);

  const LaserScanner acuity = MakeScanner(LaserScannerOptions::Profile("acuity_accurange"));
  for (int i = 0; i < 360; ++i) {
    EXPECT_NEAR(acuity.bearing_rad(i), -kPi + i * kPi / 180, 1e-12);  // 1°, no overlap at ±π
    EXPECT_NEAR(acuity.time_offset_s(i), 0.001 * i, 1e-12);
  }

  // A custom non-interlaced scanner: i·sweep/(beams-1).
  LaserScannerOptions custom = LaserScannerOptions::Profile("custom");
  custom.interlaced_turns = 1;
  custom.beams = 181;
  custom.sweep_s = 0.05;
  const LaserScanner plain = MakeScanner(custom);
  for (int i = 0; i < 181; ++i) EXPECT_NEAR(plain.time_offset_s(i), 0.05 * i / 180, 1e-15);
}

// Pose of a robot spinning at `omega` and driving at `v` along x from `start`.
Pose2 MovingPose(const Pose2& start, double v, double omega, double t) {
  return {start.x_m + v * t, start.y_m, core::NormalizeAngle(start.theta_rad + omega * t)};
}

// Runs one sweep cast tick by tick (5 ms) for a moving robot.
void CastSweep(LaserScanner& scanner, const World& world, const Pose2& start, double v,
               double omega, double sweep_start_s) {
  const double tick_s = 0.005;
  scanner.BeginSweep(sweep_start_s);
  for (int k = 0; !scanner.SweepComplete(); ++k) {
    ASSERT_LT(k, 1000);
    const double t0 = k * tick_s, t1 = (k + 1) * tick_s;
    scanner.Cast(world, t0, MovingPose(start, v, omega, t0), t1, MovingPose(start, v, omega, t1),
                 -1);
  }
}

// A robot spinning at 1 rad/s while scanning: each reading is cast from the
// pose at its own time (the distortion of §2.2.1.4), so the first and last
// readings' true headings differ by ω·(t_last − t_first), and each measured
// range is the geometric range from its own pose, not from the start pose.
TEST(LaserScannerTest, SpinningRobotGetsDistortedScan) {
  World world(Room(), {});
  const double omega = 1.0;
  const Pose2 start{3.0, 2.0, 0.3};
  for (const std::string profile : {"sick_lms200", "acuity_accurange"}) {
    LaserScanner scanner = MakeScanner(Exact(LaserScannerOptions::Profile(profile)), kMount);
    const double sweep_start_s = 0.0125;
    CastSweep(scanner, world, start, 0.0, omega, sweep_start_s);
    const core::LaserScan& scan = scanner.scan();
    const core::LaserScanTruth& truth = scanner.truth();
    int first = 0, last = 0;
    for (int i = 0; i < scanner.options().beams; ++i) {
      const double t = sweep_start_s + scanner.time_offset_s(i);
      const Pose2 expected = MovingPose(start, 0.0, omega, t) * kMount;
      const Pose2& actual = truth.world_from_sensor[i];
      EXPECT_NEAR(actual.x_m, expected.x_m, 1e-9) << profile << " " << i;
      EXPECT_NEAR(actual.y_m, expected.y_m, 1e-9);
      EXPECT_NEAR(core::NormalizeAngle(actual.theta_rad - expected.theta_rad), 0.0, 1e-9);
      EXPECT_EQ(scan.readings[i].time_offset_s, scanner.time_offset_s(i));
      const AnalyticHit geometric =
          RoomHit(actual.translation(), actual.theta_rad + scan.readings[i].bearing_rad);
      EXPECT_NEAR(scan.readings[i].range_m, geometric.range_m,
                  WallTolerance(scanner.options().range_resolution_m, geometric.cos_incidence))
          << profile << " " << i;
      if (scanner.time_offset_s(i) > scanner.time_offset_s(last)) last = i;
      if (scanner.time_offset_s(i) < scanner.time_offset_s(first)) first = i;
    }
    const double dt = scanner.time_offset_s(last) - scanner.time_offset_s(first);
    EXPECT_NEAR(dt, scanner.options().sweep_s, 1e-12);
    EXPECT_NEAR(core::NormalizeAngle(truth.world_from_sensor[last].theta_rad -
                                     truth.world_from_sensor[first].theta_rad),
                omega * dt, 1e-9)
        << profile;
    // The same sweep from the start pose alone differs where rays meet walls obliquely.
    const core::LaserScan still = scanner.ScanFrom(world, start, sweep_start_s, -1, nullptr);
    double largest_m = 0.0;
    for (std::size_t i = 0; i < still.readings.size(); ++i) {
      largest_m =
          std::max(largest_m, std::abs(still.readings[i].range_m - scan.readings[i].range_m));
    }
    EXPECT_GT(largest_m, profile == "sick_lms200" ? 0.02 : 0.5) << profile;
  }
}

// A robot driving at 1 m/s during the 0.36 s Acuity sweep: the true sensor
// positions move by v·t along the sweep, and ranges follow them.
TEST(LaserScannerTest, DrivingRobotReadingsFollowInterpolatedPose) {
  World world(Room(), {});
  LaserScanner scanner = MakeScanner(Exact(LaserScannerOptions::Profile("acuity_accurange")));
  const Pose2 start{1.5, 2.0, 0.0};
  CastSweep(scanner, world, start, 1.0, 0.0, 0.02);
  for (int i = 0; i < 360; ++i) {
    const double t = 0.02 + scanner.time_offset_s(i);
    const Pose2& p = scanner.truth().world_from_sensor[i];
    EXPECT_NEAR(p.x_m, 1.5 + t, 1e-9);
    const AnalyticHit geometric = RoomHit(p.translation(), p.theta_rad + scanner.bearing_rad(i));
    EXPECT_NEAR(scanner.scan().readings[i].range_m, geometric.range_m,
                WallTolerance(0.0, geometric.cos_incidence));
  }
}

// Readings due before the first Cast() of a sweep are cast from the tick's start
// pose; later ones from the pose interpolated within the tick (x, y and theta
// along the shorter way round ±π).
TEST(LaserScannerTest, LateReadingsUseTickStartPose) {
  World world(Room(), {});
  LaserScanner scanner = MakeScanner(Exact(LaserScannerOptions::Profile("acuity_accurange")));
  scanner.BeginSweep(0.0);
  EXPECT_FALSE(scanner.SweepComplete());
  const Pose2 a{2.0, 2.0, 3.0};
  const Pose2 b{2.1, 2.0, -3.0};  // 0.283 rad further counter-clockwise, across ±π
  scanner.Cast(world, 0.0105, a, 0.0205, b, -1);
  EXPECT_FALSE(scanner.SweepComplete());
  scanner.Cast(world, 0.0205, b, 1.0, b, -1);
  ASSERT_TRUE(scanner.SweepComplete());
  const auto& poses = scanner.truth().world_from_sensor;
  for (int i = 0; i <= 10; ++i) EXPECT_EQ(poses[i], a) << i;  // 0 .. 10 ms
  const double turn = 2 * kPi - 6.0;
  for (int i = 11; i <= 20; ++i) {
    const double s = (0.001 * i - 0.0105) / 0.01;
    EXPECT_NEAR(poses[i].x_m, 2.0 + 0.1 * s, 1e-9) << i;
    EXPECT_NEAR(core::NormalizeAngle(poses[i].theta_rad - (3.0 + s * turn)), 0.0, 1e-9) << i;
  }
  for (int i = 21; i < 360; ++i) EXPECT_NEAR(poses[i].x_m, 2.1, 1e-9);
}

// Casting tick by tick with a still robot gives the same scan and truth as
// ScanFrom(), draw for draw (the error models run in reading order at the end).
TEST(LaserScannerTest, TickCastingOfStillRobotEqualsScanFrom) {
  World world(Room(), {});
  const LaserScannerOptions options = LaserScannerOptions::Profile("acuity_accurange");
  LaserScanner ticked = MakeScanner(options, kMount);
  LaserScanner whole = MakeScanner(options, kMount);
  const Pose2 pose{2.5, 1.5, -0.7};
  CastSweep(ticked, world, pose, 0.0, 0.0, 0.0);
  core::LaserScanTruth truth;
  const core::LaserScan scan = whole.ScanFrom(world, pose, 0.0, -1, &truth);
  ASSERT_EQ(scan.readings.size(), ticked.scan().readings.size());
  for (std::size_t i = 0; i < scan.readings.size(); ++i) {
    EXPECT_EQ(scan.readings[i].range_m, ticked.scan().readings[i].range_m) << i;
    EXPECT_EQ(scan.readings[i].valid, ticked.scan().readings[i].valid) << i;
    EXPECT_EQ(truth.true_range_m[i], ticked.truth().true_range_m[i]) << i;
  }
}

// Retro-reflective targets set the reflector bit (§3.3), other surfaces don't,
// with noise and effects on.
TEST(LaserScannerTest, RetroReflectorsAreFlagged) {
  WorldDescription d = EmptyWorld();
  d.walls.push_back(WallFacingOrigin("wall", 3.0, "paint"));
  d.cylinders.push_back({"beacon", {2.0, 0.8}, 0.05, 1.0, 0.0, "reflector"});
  d.boxes.push_back({"crate", {2.0, -0.8, 0.0}, {0.3, 0.3, 1.0}, 0.0, "paint"});
  World world(d, {});
  const int beacon = ElementIndex(world, "beacon");
  LaserScanner scanner = MakeScanner(LaserScannerOptions::Profile("sick_lms200"));
  core::LaserScanTruth truth;
  const core::LaserScan scan = scanner.ScanFrom(world, {}, 0.0, -1, &truth);
  int flagged = 0, beacon_readings = 0;
  for (std::size_t i = 0; i < scan.readings.size(); ++i) {
    const core::LaserReading& r = scan.readings[i];
    if (truth.element[i] == beacon) {
      ++beacon_readings;
      EXPECT_TRUE(r.valid);
      // A mixed pixel at the beacon's rim is pulled towards the bright reflector.
      EXPECT_TRUE(r.reflector) << i;
    }
    flagged += r.reflector;
  }
  EXPECT_GE(beacon_readings, 2);  // 0.1 m wide at 2.16 m: ≈ 2.6° / 0.5°
  // Only the beacon's readings, plus at most one mixed pixel on each side of it.
  EXPECT_GE(flagged, beacon_readings);
  EXPECT_LE(flagged, beacon_readings + 2);
}

// Glass is not seen: the wall behind it is measured, exactly without noise.
TEST(LaserScannerTest, TransparentSurfacesAreSeenThrough) {
  WorldDescription d = EmptyWorld();
  d.walls.push_back(WallFacingOrigin("glass_wall", 1.5, "glass"));
  d.walls.push_back(WallFacingOrigin("wall", 3.0, "paint"));
  World world(d, {});
  const int wall = ElementIndex(world, "wall");
  for (const bool effects : {false, true}) {
    LaserScannerOptions o = Exact(LaserScannerOptions::Profile("sick_lms200"));
    o.effects = effects;
    LaserScanner scanner = MakeScanner(o);
    core::LaserScanTruth truth;
    const core::LaserScan scan = scanner.ScanFrom(world, {}, 0.0, -1, &truth);
    int seen = 0;
    for (std::size_t i = 0; i < scan.readings.size(); ++i) {
      const double b = scan.readings[i].bearing_rad;
      if (std::abs(b) > 1.0) continue;  // wall within 5.5 m
      ++seen;
      EXPECT_EQ(truth.element[i], wall);
      EXPECT_TRUE(scan.readings[i].valid);
      EXPECT_NEAR(scan.readings[i].range_m, 3.0 / std::cos(b),
                  WallTolerance(o.range_resolution_m, std::cos(b)))
          << i;
    }
    EXPECT_GT(seen, 200);
  }
}

// Readings that meet nothing within the maximum range are invalid at max range,
// with max range and no element as truth, whatever the error models.
TEST(LaserScannerTest, NoHitIsInvalidAtMaxRange) {
  WorldDescription d = EmptyWorld();
  d.walls.push_back(WallFacingOrigin("far_wall", 9.0, "paint"));  // beyond the 8 m
  World world(d, {});
  for (const bool on : {false, true}) {
    LaserScannerOptions o = LaserScannerOptions::Profile("sick_lms200");
    o.noise = on;
    o.effects = on;
    LaserScanner scanner = MakeScanner(o);
    core::LaserScanTruth truth;
    const core::LaserScan scan = scanner.ScanFrom(world, {}, 0.0, -1, &truth);
    EXPECT_EQ(scan.max_range_m, 8.0);
    for (std::size_t i = 0; i < scan.readings.size(); ++i) {
      EXPECT_FALSE(scan.readings[i].valid);
      EXPECT_EQ(scan.readings[i].range_m, 8.0);
      EXPECT_EQ(truth.true_range_m[i], 8.0);
      EXPECT_EQ(truth.element[i], -1);
    }
  }
}

// Dark surfaces: dropouts at the configured rate (binomial, five standard
// errors) and σ multiplied by dark_sigma_factor; neither without effects.
TEST(LaserScannerTest, DarkSurfacesDropOutAndAreNoisier) {
  WorldDescription d = EmptyWorld();
  d.walls.push_back(WallFacingOrigin("velvet_wall", 2.0, "velvet"));
  World world(d, {});
  for (const bool effects : {true, false}) {
    LaserScannerOptions o = LaserScannerOptions::Profile("sick_lms200");
    o.effects = effects;
    LaserScanner scanner = MakeScanner(o);
    long n = 0, dropped = 0, valid = 0;
    double sum_sq = 0.0;
    for (int s = 0; s < 100; ++s) {
      core::LaserScanTruth truth;
      const core::LaserScan scan = scanner.ScanFrom(world, {}, 0.1 * s, -1, &truth);
      for (std::size_t i = 0; i < scan.readings.size(); ++i) {
        if (truth.true_range_m[i] > 7.0) continue;  // away from the range limit
        ++n;
        if (!scan.readings[i].valid) {
          ++dropped;
          continue;
        }
        ++valid;
        const double e = scan.readings[i].range_m - truth.true_range_m[i];
        sum_sq += e * e;
      }
    }
    ASSERT_GT(n, 20000);
    const double p = effects ? o.dark_dropout_probability : 0.0;
    EXPECT_NEAR(static_cast<double>(dropped) / n, p, 5.0 * std::sqrt(0.3 * 0.7 / n) + 1e-12);
    // About the geometric range: σ² plus the quantization's q²/12.
    const double sigma = o.range_sigma_m * (effects ? o.dark_sigma_factor : 1.0);
    const double q = o.range_resolution_m;
    const double expected_rms = std::sqrt(sigma * sigma + q * q / 12.0);
    const double rms = std::sqrt(sum_sq / valid);
    EXPECT_NEAR(rms, expected_rms, 5.0 * expected_rms / std::sqrt(2.0 * valid));
  }
}

// A specular wall met head-on returns, and gives no return beyond the incidence
// limit (incidence = bearing for a wall facing the sensor); without effects it
// answers like any wall.
TEST(LaserScannerTest, SpecularSurfacesVanishAtGrazingIncidence) {
  WorldDescription d = EmptyWorld();
  d.walls.push_back(WallFacingOrigin("chrome_wall", 2.0, "chrome"));
  World world(d, {});
  for (const bool effects : {true, false}) {
    LaserScannerOptions o = LaserScannerOptions::Profile("sick_lms200");
    o.effects = effects;
    LaserScanner scanner = MakeScanner(o);
    const core::LaserScan scan = scanner.ScanFrom(world, {}, 0.0, -1, nullptr);
    int head_on = 0, grazing = 0;
    for (const core::LaserReading& r : scan.readings) {
      const double incidence = std::abs(r.bearing_rad);
      if (2.0 / std::cos(incidence) > 7.5) continue;  // beyond the range limit anyway
      if (incidence < o.specular_max_incidence_rad - 0.01) {
        ++head_on;
        EXPECT_TRUE(r.valid) << r.bearing_rad;
      } else if (incidence > o.specular_max_incidence_rad + 0.01) {
        ++grazing;
        EXPECT_EQ(r.valid, !effects) << r.bearing_rad;
        if (effects) {
          EXPECT_EQ(r.range_m, o.max_range_m);
        }
      }
    }
    EXPECT_GT(head_on, 200);
    EXPECT_GT(grazing, 40);
  }
}

// The documented mixed-pixel model (§2.2.1.6 "A"): a box edge placed a quarter
// divergence beside a reading's central ray leaves 3/4 of its footprint on the
// box and 1/4 on the wall behind, and the reading is their amplitude-weighted
// mean range, within the bisection's 1/128 uncertainty of the fraction. Its
// neighbours are pure, and without effects the reading is the box's range.
TEST(LaserScannerTest, MixedPixelsAtDepthEdgesOnlyWithEffects) {
  const LaserScannerOptions lms = LaserScannerOptions::Profile("sick_lms200");
  const int i = 192;  // bearing 6°
  const double b = -kPi / 2 + i * kPi / 360;
  const double delta = lms.beam_divergence_rad;
  const double edge_y = 2.0 * std::tan(b + delta / 4);
  WorldDescription d = EmptyWorld();
  d.walls.push_back(WallFacingOrigin("wall", 5.0, "paint"));
  d.boxes.push_back(
      {"box", {2.25, 0.5 * (edge_y - 1.0), 0.0}, {0.5, edge_y + 1.0, 1.0}, 0, "paint"});
  World world(d, {});

  const double r_box = 2.0 / std::cos(b);
  const double a_box = RelativeAmplitude(1.0, r_box, std::cos(b));
  const double r_wall = 5.0 / std::cos(b + delta / 2);  // the edge ray's range
  const double a_wall = RelativeAmplitude(1.0, r_wall, std::cos(b + delta / 2));
  auto mixed = [&](double w) {
    return ((1 - w) * a_box * r_box + w * a_wall * r_wall) / ((1 - w) * a_box + w * a_wall);
  };
  const double tolerance = std::abs(mixed(0.25 + 1.0 / 128) - mixed(0.25 - 1.0 / 128)) / 2 +
                           0.5 * lms.range_resolution_m + kRayCastTolM;

  for (const bool effects : {true, false}) {
    LaserScannerOptions o = lms;
    o.noise = false;
    o.effects = effects;
    LaserScanner scanner = MakeScanner(o);
    const core::LaserScan scan = scanner.ScanFrom(world, {}, 0.0, -1, nullptr);
    const auto& r = scan.readings;
    // Boxes are exact in Bullet: the box's range is off by the quantization only.
    const double box_tol = 0.5 * o.range_resolution_m + kRayCastTolM;
    EXPECT_NEAR(r[i].range_m, effects ? mixed(0.25) : r_box, effects ? tolerance : box_tol);
    EXPECT_TRUE(r[i].valid);
    EXPECT_NEAR(r[i - 1].range_m, 2.0 / std::cos(r[i - 1].bearing_rad), box_tol);
    const double cos_next = std::cos(r[i + 1].bearing_rad);
    EXPECT_NEAR(r[i + 1].range_m, 5.0 / cos_next, WallTolerance(o.range_resolution_m, cos_next));
    // Readings between the box and the wall: only mixed pixels, one at each
    // box edge at most (the lower edge at y = -1 lands where it may).
    int between = 0;
    for (const core::LaserReading& reading : r) {
      if (!reading.valid || std::abs(reading.bearing_rad) > 0.8) continue;  // wall within 7.2 m
      const double box_m = 2.0 / std::cos(reading.bearing_rad);
      const double wall_m = 5.0 / std::cos(reading.bearing_rad);
      between += reading.range_m > box_m + 0.01 && reading.range_m < wall_m - 0.01;
    }
    if (effects) {
      EXPECT_GE(between, 1);
      EXPECT_LE(between, 2);
    } else {
      EXPECT_EQ(between, 0);
    }
  }
  // Sanity of the expectation: the mixed range lies well between the surfaces.
  EXPECT_GT(mixed(0.25), r_box + 0.1);
  EXPECT_LT(mixed(0.25), r_wall - 1.0);
}

// Acuity amplitude model (§2.2.1.3): a head-on wall at 1 m (amplitude ≈ 4) has
// σ = range_sigma_m; one at 12 m (amplitude ≈ 0.028 < s_min) has
// σ = low_amplitude_sigma_m. Checked on the sample σ of each.
TEST(LaserScannerTest, AcuitySigmaFollowsAmplitude) {
  LaserScannerOptions o = LaserScannerOptions::Profile("acuity_accurange");
  o.outlier_probability = 0.0;
  EXPECT_GT(RelativeAmplitude(1.0, 1.0 / std::cos(0.2), std::cos(0.2)), o.min_amplitude);
  EXPECT_LT(RelativeAmplitude(1.0, 12.0, 1.0), o.min_amplitude);
  for (const double face_m : {1.0, 12.0}) {
    WorldDescription d = EmptyWorld();
    d.walls.push_back(WallFacingOrigin("wall", face_m, "paint"));
    World world(d, {});
    LaserScanner scanner = MakeScanner(o);
    long n = 0;
    double sum_sq = 0.0;
    for (int s = 0; s < 300; ++s) {
      core::LaserScanTruth truth;
      const core::LaserScan scan = scanner.ScanFrom(world, {}, 0.36 * s, -1, &truth);
      for (std::size_t i = 0; i < scan.readings.size(); ++i) {
        if (std::abs(scan.readings[i].bearing_rad) > 0.2) continue;
        ASSERT_TRUE(scan.readings[i].valid);
        const double e = scan.readings[i].range_m - truth.true_range_m[i];
        sum_sq += e * e;
        ++n;
      }
    }
    const double sigma = face_m < 5.0 ? o.range_sigma_m : o.low_amplitude_sigma_m;
    EXPECT_NEAR(std::sqrt(sum_sq / n), sigma, 5.0 * sigma / std::sqrt(2.0 * n)) << face_m;
  }
  // Amplitude law: reflectivity·cos(incidence)/(r/r_ref)².
  EXPECT_DOUBLE_EQ(RelativeAmplitude(1.0, kAmplitudeReferenceRangeM, 1.0), 1.0);
  EXPECT_DOUBLE_EQ(RelativeAmplitude(0.5, 2 * kAmplitudeReferenceRangeM, 0.5), 0.0625);
  EXPECT_GT(LaserReflectivity(LaserResponse::kRetroReflective), 1.0);
  EXPECT_LT(LaserReflectivity(LaserResponse::kDark), o.min_amplitude * 4);
}

// Acuity outliers: a uniform range in (0, max range) with the configured
// probability; those farther than 0.25 m from the truth are counted and
// compared with p·(1 − 0.5 m / max range), within five binomial standard errors.
TEST(LaserScannerTest, AcuityOutliersAtConfiguredRate) {
  World world(Room(), {});
  const LaserScannerOptions o = LaserScannerOptions::Profile("acuity_accurange");
  LaserScanner scanner = MakeScanner(o);
  long n = 0, far = 0;
  for (int s = 0; s < 200; ++s) {
    core::LaserScanTruth truth;
    const core::LaserScan scan = scanner.ScanFrom(world, {3.0, 2.0, 0.1}, 0.36 * s, -1, &truth);
    for (std::size_t i = 0; i < scan.readings.size(); ++i) {
      ++n;
      far += std::abs(scan.readings[i].range_m - truth.true_range_m[i]) > 0.25;
      EXPECT_GT(scan.readings[i].range_m, 0.0);
      EXPECT_LT(scan.readings[i].range_m, o.max_range_m);
    }
  }
  const double p = o.outlier_probability * (1.0 - 0.5 / o.max_range_m);
  EXPECT_NEAR(static_cast<double>(far) / n, p, 5.0 * std::sqrt(p * (1 - p) / n));
}

// A scanner on a robot, looking back over its own chassis: with the robot's
// element group ignored, its rays pass the chassis and meet the wall behind;
// without, the chassis 7.5 cm away is measured.
TEST(LaserScannerTest, IgnoredGroupIsNotSeen) {
  WorldDescription d = EmptyWorld();
  d.walls.push_back(WallOf("wall", {{-3.05, -20.0}, {-3.05, 20.0}}, false, "paint"));
  World world(d, {});
  pavilion::testing::WorldRobot robot;
  robot.id = "robot";
  robot.model.model = "box";
  robot.model.footprint_m = {{-0.225, -0.225}, {0.225, -0.225}, {0.225, 0.225}, {-0.225, 0.225}};
  robot.model.chassis_base_z_m = 0.04;
  robot.model.chassis_height_m = 0.66;
  robot.model.left_wheel = {"left", 0.09, 0.03, 1.5, {0.0, 0.2}};
  robot.model.right_wheel = {"right", 0.09, 0.03, 1.5, {0.0, -0.2}};
  robot.model.material = "paint";
  const int r = pavilion::testing::AddRobot(world, robot);
  const int group = world.robot_group(r);
  const Pose2 robot_from_sensor{0.3, 0.0, kPi};  // in front of the chassis, facing it
  LaserScanner scanner =
      MakeScanner(Exact(LaserScannerOptions::Profile("sick_lms200")), robot_from_sensor);
  core::LaserScanTruth ignoring, seeing;
  const core::LaserScan through = scanner.ScanFrom(world, {}, 0.0, group, &ignoring);
  const core::LaserScan blocked = scanner.ScanFrom(world, {}, 0.0, -1, &seeing);
  const int centre = 180;  // straight back along the robot's x axis
  EXPECT_NEAR(through.readings[centre].range_m, 3.3, 0.002);
  EXPECT_NEAR(blocked.readings[centre].range_m, 0.075, 0.002);
  int own = 0;
  for (std::size_t i = 0; i < through.readings.size(); ++i) {
    if (ignoring.element[i] >= 0) {
      EXPECT_NE(world.elements()[ignoring.element[i]].group, group);
    }
    own += seeing.element[i] >= 0 && world.elements()[seeing.element[i]].group == group;
  }
  EXPECT_GT(own, 100);  // the 45 cm chassis spans ≈ 143° seen from 7.5 cm
}

// Same seed and stream: identical scans, bit for bit. Another stream id: different noise.
TEST(LaserScannerTest, ScansAreDeterministicPerStream) {
  World world(Room(), {});
  const LaserScannerOptions o = LaserScannerOptions::Profile("acuity_accurange");
  LaserScanner a = MakeScanner(o, kMount, 7);
  LaserScanner b = MakeScanner(o, kMount, 7);
  LaserScanner c = MakeScanner(o, kMount, 8);
  int differing = 0;
  for (int s = 0; s < 5; ++s) {
    const Pose2 pose{2.0 + 0.1 * s, 2.0, 0.2 * s};
    const core::LaserScan sa = a.ScanFrom(world, pose, s, -1, nullptr);
    const core::LaserScan sb = b.ScanFrom(world, pose, s, -1, nullptr);
    const core::LaserScan sc = c.ScanFrom(world, pose, s, -1, nullptr);
    for (std::size_t i = 0; i < sa.readings.size(); ++i) {
      EXPECT_EQ(sa.readings[i].range_m, sb.readings[i].range_m);
      EXPECT_EQ(sa.readings[i].valid, sb.readings[i].valid);
      EXPECT_EQ(sa.readings[i].reflector, sb.readings[i].reflector);
      EXPECT_EQ(sa.readings[i].bearing_rad, sb.readings[i].bearing_rad);
      EXPECT_EQ(sa.readings[i].time_offset_s, sb.readings[i].time_offset_s);
      differing += sa.readings[i].range_m != sc.readings[i].range_m;
    }
  }
  EXPECT_GT(differing, 1000);  // σ = 0.5 mm, unquantized: nearly every reading
}

// The scan stamp is the sweep start plus the constant bias (§2.2.1.5); the
// readings' offsets are unaffected. The Acuity profile carries the thesis' 5 ms.
TEST(LaserScannerTest, StampCarriesTimestampBias) {
  World world(Room(), {});
  LaserScannerOptions o = LaserScannerOptions::Profile("sick_lms200");
  o.timestamp_bias_s = -0.002;
  LaserScanner scanner = MakeScanner(o);
  scanner.BeginSweep(1.5);
  scanner.Cast(world, 1.5, {3, 2, 0}, 1.6, {3, 2, 0}, -1);
  ASSERT_TRUE(scanner.SweepComplete());
  EXPECT_DOUBLE_EQ(scanner.scan().stamp_s, 1.498);
  EXPECT_EQ(scanner.scan().readings[1].time_offset_s, scanner.time_offset_s(1));
  EXPECT_DOUBLE_EQ(scanner.ScanFrom(world, {3, 2, 0}, 2.0, -1, nullptr).stamp_s, 1.998);

  LaserScanner acuity = MakeScanner(LaserScannerOptions::Profile("acuity_accurange"));
  EXPECT_DOUBLE_EQ(acuity.ScanFrom(world, {3, 2, 0}, 2.0, -1, nullptr).stamp_s, 2.005);
  const core::LaserScan scan = acuity.ScanFrom(world, {3, 2, 0}, 2.0, -1, nullptr);
  EXPECT_EQ(scan.sensor_id, "laser");
  EXPECT_EQ(scan.max_range_m, acuity.options().max_range_m);
}

// A sweep is complete only once all its readings are cast, and Cast() without a
// sweep does nothing.
TEST(LaserScannerTest, SweepCompletesAfterItsLastReading) {
  World world(Room(), {});
  LaserScanner scanner = MakeScanner(LaserScannerOptions::Profile("sick_lms200"));
  scanner.Cast(world, 0.0, {3, 2, 0}, 1.0, {3, 2, 0}, -1);
  EXPECT_FALSE(scanner.SweepComplete());
  scanner.BeginSweep(0.0);
  scanner.Cast(world, 0.0, {3, 2, 0}, scanner.options().sweep_s, {3, 2, 0}, -1);
  EXPECT_FALSE(scanner.SweepComplete());  // the last reading is due at sweep_s itself
  scanner.Cast(world, scanner.options().sweep_s, {3, 2, 0}, 0.1, {3, 2, 0}, -1);
  EXPECT_TRUE(scanner.SweepComplete());
  EXPECT_EQ(scanner.scan().readings.size(), 361u);
  scanner.BeginSweep(0.1);
  EXPECT_FALSE(scanner.SweepComplete());
}

// Every out-of-range option is rejected with its field's name; profiles are
// valid and unknown profile names are rejected.
TEST(LaserScannerTest, OptionsAreValidated) {
  using Mutation = std::function<void(LaserScannerOptions&)>;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::pair<std::string, Mutation>> cases = {
      {"profile", [](auto& o) { o.profile = "lms"; }},
      {"fov_rad", [](auto& o) { o.fov_rad = 0.0; }},
      {"fov_rad", [](auto& o) { o.fov_rad = 7.0; }},
      {"beams", [](auto& o) { o.beams = 1; }},
      {"first_bearing_rad", [&](auto& o) { o.first_bearing_rad = nan; }},
      {"max_range_m", [](auto& o) { o.max_range_m = 0.0; }},
      {"max_range_m", [](auto& o) { o.max_range_m = std::numeric_limits<double>::infinity(); }},
      {"scan_rate_hz", [](auto& o) { o.scan_rate_hz = -1.0; }},
      {"sweep_s", [](auto& o) { o.sweep_s = -0.001; }},
      {"sweep_s", [](auto& o) { o.sweep_s = 0.2; }},  // longer than the 0.1 s scan period
      {"interlaced_turns", [](auto& o) { o.interlaced_turns = 0; }},
      {"interlaced_turns", [](auto& o) { o.interlaced_turns = 361; }},
      {"timestamp_bias_s", [&](auto& o) { o.timestamp_bias_s = nan; }},
      {"range_sigma_m", [](auto& o) { o.range_sigma_m = -0.01; }},
      {"range_resolution_m", [](auto& o) { o.range_resolution_m = -0.001; }},
      {"min_amplitude", [](auto& o) { o.min_amplitude = 1.5; }},
      {"low_amplitude_sigma_m", [](auto& o) { o.low_amplitude_sigma_m = -1.0; }},
      {"outlier_probability", [](auto& o) { o.outlier_probability = 1.1; }},
      {"dark_dropout_probability", [](auto& o) { o.dark_dropout_probability = -0.1; }},
      {"dark_sigma_factor", [](auto& o) { o.dark_sigma_factor = 0.5; }},
      {"specular_max_incidence_rad", [](auto& o) { o.specular_max_incidence_rad = 2.0; }},
      {"beam_divergence_rad", [](auto& o) { o.beam_divergence_rad = -0.001; }},
      {"mixed_pixel_min_gap_m", [](auto& o) { o.mixed_pixel_min_gap_m = 0.0; }},
  };
  for (const auto& [field, mutate] : cases) {
    LaserScannerOptions o;
    mutate(o);
    try {
      o.Validate();
      ADD_FAILURE() << field << " accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
    }
    EXPECT_THROW(MakeScanner(o), std::invalid_argument) << field;
  }
  for (const std::string name : {"sick_lms200", "acuity_accurange", "custom"}) {
    const LaserScannerOptions o = LaserScannerOptions::Profile(name);
    EXPECT_EQ(o.profile, name);
    EXPECT_NO_THROW(o.Validate()) << name;
  }
  EXPECT_THROW(LaserScannerOptions::Profile("sick_lms291"), std::invalid_argument);
  // The LMS 200 profile is the thesis' configuration (§2.2.2).
  const LaserScannerOptions lms = LaserScannerOptions::Profile("sick_lms200");
  EXPECT_EQ(lms.beams, 361);
  EXPECT_DOUBLE_EQ(lms.fov_rad, kPi);
  EXPECT_EQ(lms.max_range_m, 8.0);
  EXPECT_EQ(lms.range_sigma_m, 0.01);
  // The Acuity profile: 1° at 1 kHz over a full turn (§2.2.1.4), amplitude model on.
  const LaserScannerOptions acuity = LaserScannerOptions::Profile("acuity_accurange");
  EXPECT_EQ(acuity.beams, 360);
  EXPECT_DOUBLE_EQ(acuity.fov_rad, 2 * kPi);
  EXPECT_NEAR(acuity.scan_rate_hz, 2.778, 1e-3);
  EXPECT_TRUE(acuity.amplitude_model);
  EXPECT_GT(acuity.outlier_probability, 0.0);
}

}  // namespace
}  // namespace pavilion::sim
