// Robot files (robots/<name>/robot.yaml): the shipped robots against the
// thesis, and one malformed file per error class with its file:line: key.
#include "scenarios/config/robot_loader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/geometry/polygon.h"
#include "core/types/pose2.h"
#include "scenarios/config/data_paths.h"
#include "scenarios/config/input_error.h"
#include "scenarios/config/validate.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

namespace fs = std::filesystem;
using pavilion::testing::Contains;
using pavilion::testing::ExactText;
using pavilion::testing::LineOf;
using pavilion::testing::TestDir;
using pavilion::testing::ValidateMessage;
using pavilion::testing::WriteFile;

constexpr double kPi = std::numbers::pi;
constexpr double kDeg = kPi / 180.0;

sim::RobotConfig LoadShipped(const std::string& name) {
  return LoadRobotFile(ResolveRobotPath(name));
}

// True when `bearing_rad`, seen from the sensor, lies inside the laser's field of view.
bool InFieldOfView(const sim::LaserMount& laser, double bearing_rad) {
  double offset = core::NormalizeAngle(bearing_rad - laser.options.first_bearing_rad);
  if (offset < 0.0) offset += 2 * kPi;
  return offset <= laser.options.fov_rad + 1e-9;
}

// True when some laser sees the direction `bearing_rad` of the base frame.
bool Covered(const std::vector<sim::LaserMount>& lasers, double bearing_rad) {
  for (const sim::LaserMount& l : lasers) {
    if (InFieldOfView(l, bearing_rad - l.robot_from_sensor.theta_rad)) return true;
  }
  return false;
}

// True when the point (base frame) is outside every laser's field of view.
bool InBlindZone(const std::vector<sim::LaserMount>& lasers, const Eigen::Vector2d& p) {
  for (const sim::LaserMount& l : lasers) {
    const Eigen::Vector2d in_sensor = l.robot_from_sensor.Inverse() * p;
    if (InFieldOfView(l, std::atan2(in_sensor.y(), in_sensor.x()))) return false;
  }
  return true;
}

// True when the zones together cover every bearing.
bool BumpersCoverAround(const std::vector<sim::BumperZone>& zones) {
  for (double b = -180.0; b < 180.0; b += 0.5) {
    bool hit = false;
    for (const sim::BumperZone& z : zones) {
      double width = std::remainder(z.to_rad - z.from_rad, 2 * kPi);
      if (width <= 0) width += 2 * kPi;
      double offset = std::remainder(b * kDeg - z.from_rad, 2 * kPi);
      if (offset < 0) offset += 2 * kPi;
      hit = hit || offset <= width + 1e-9;
    }
    if (!hit) return false;
  }
  return true;
}

// Confirms every shipped robot loads and validates clean (the CLI's check).
TEST(RobotLoaderTest, ShippedRobotsValidate) {
  for (const std::string name : {"robox", "pygmalion"}) {
    const std::string path = ResolveRobotPath(name);
    EXPECT_TRUE(ValidateFile(path).empty()) << path;
    EXPECT_NO_THROW(LoadRobotFile(path)) << path;
  }
}

// Confirms Robox matches the thesis: 115 kg (§6.5), 1.65 m tall (A.5), two LMS 200
// back to back covering 360° with the markers in their blind zones (§6.3.5.1).
TEST(RobotLoaderTest, RoboxMatchesTheThesis) {
  const sim::RobotConfig c = LoadShipped("robox");
  const sim::RobotDescription& d = c.description;
  EXPECT_EQ(d.model, "robox");
  EXPECT_NEAR(d.total_mass_kg(), 115.0, 0.5);
  EXPECT_NEAR(d.chassis_base_z_m + d.chassis_height_m, 1.65, 0.01);
  EXPECT_EQ(d.footprint_m.size(), 8u);  // octagonal base
  ASSERT_EQ(c.lasers.size(), 2u);
  for (const sim::LaserMount& l : c.lasers) {
    EXPECT_EQ(l.options.profile, "sick_lms200");
    EXPECT_NEAR(l.options.fov_rad, kPi, 1e-12);  // 180° (§2.2.2)
    EXPECT_EQ(l.options.beams, 361);             // at 0.5°
    EXPECT_NEAR(l.options.max_range_m, 8.0, 1e-12);
  }
  EXPECT_NEAR(std::abs(core::NormalizeAngle(c.lasers[0].robot_from_sensor.theta_rad -
                                            c.lasers[1].robot_from_sensor.theta_rad)),
              kPi, 1e-9);  // back to back
  for (double b = -180.0; b < 180.0; b += 0.25) EXPECT_TRUE(Covered(c.lasers, b * kDeg)) << b;
  // Between the scanners, at the sides, lies a blind zone: the markers are there.
  ASSERT_EQ(d.markers.size(), 2u);
  for (const sim::MarkerSpec& m : d.markers) {
    EXPECT_TRUE(InBlindZone(c.lasers, m.position_m)) << m.id;
    for (double side : {-1.0, 1.0}) {  // the whole post, not just its axis
      EXPECT_TRUE(InBlindZone(c.lasers, m.position_m + Eigen::Vector2d(side * m.radius_m, 0)));
    }
    EXPECT_NEAR(std::abs(std::atan2(m.position_m.y(), m.position_m.x())), kPi / 2, 1e-9);
    EXPECT_EQ(d.materials.at(m.material).laser, core::LaserResponse::kRetroReflective);
    // The post spans the scan plane of robots of the same design.
    EXPECT_LT(m.base_z_m, c.lasers[0].z_m);
    EXPECT_GT(m.base_z_m + m.height_m, c.lasers[0].z_m);
  }
  EXPECT_TRUE(d.materials.contains(d.material));
  EXPECT_EQ(c.bumpers.size(), 8u);  // tactile plates on the eight faces
  EXPECT_TRUE(BumpersCoverAround(c.bumpers));
  ASSERT_EQ(c.cameras.size(), 2u);
  EXPECT_EQ(c.cameras[0].id, "up");
  EXPECT_NEAR(c.cameras[0].mount.pitch_rad, -kPi / 2, 1e-9);  // looking upwards (A.5)
  EXPECT_TRUE(c.cameras[0].grayscale);
  EXPECT_EQ(c.cameras[1].id, "forward");
}

// Confirms Pygmalion matches appendix A.1: 45 × 45 × 70 cm, 55 kg, 50,000 pulses per
// wheel revolution, eight bumper zones, two LMS 200 covering 2π (§2.2.2), a 640 × 480
// grey-scale camera.
TEST(RobotLoaderTest, PygmalionMatchesTheThesis) {
  const sim::RobotConfig c = LoadShipped("pygmalion");
  const sim::RobotDescription& d = c.description;
  EXPECT_NEAR(d.total_mass_kg(), 55.0, 0.5);
  Eigen::Vector2d lo = d.footprint_m.front(), hi = lo;
  for (const Eigen::Vector2d& p : d.footprint_m) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  EXPECT_NEAR(hi.x() - lo.x(), 0.45, 0.005);
  EXPECT_NEAR(hi.y() - lo.y(), 0.45, 0.005);
  EXPECT_NEAR(d.chassis_base_z_m + d.chassis_height_m, 0.70, 0.005);
  EXPECT_EQ(c.encoders.ticks_per_revolution, 50000);
  EXPECT_EQ(c.bumpers.size(), 8u);
  EXPECT_TRUE(BumpersCoverAround(c.bumpers));
  ASSERT_EQ(c.lasers.size(), 2u);
  for (double b = -180.0; b < 180.0; b += 0.25) EXPECT_TRUE(Covered(c.lasers, b * kDeg)) << b;
  ASSERT_EQ(c.cameras.size(), 1u);
  EXPECT_EQ(c.cameras[0].width_px, 640);
  EXPECT_EQ(c.cameras[0].height_px, 480);
  EXPECT_TRUE(c.cameras[0].grayscale);
  EXPECT_TRUE(d.markers.empty());
}

// Confirms the shipped odometry holds calibrated values (docs/calibration.md):
// close to the URDF's wheels (the simulated robots are built without systematic
// errors, so only the physics' slip moves them), a positive k, and the encoders
// at 200 Hz (§4.4.3). odometry_calibration_test checks them against a fresh
// calibration.
TEST(RobotLoaderTest, ShippedOdometryIsCalibratedNearTheNominalModel) {
  for (const std::string name : {"robox", "pygmalion"}) {
    const sim::RobotConfig c = LoadShipped(name);
    const sim::RobotDescription& d = c.description;
    EXPECT_NEAR(c.odometry.left_wheel_radius_m / d.left_wheel.radius_m, 1.0, 0.005) << name;
    EXPECT_NEAR(c.odometry.right_wheel_radius_m / d.right_wheel.radius_m, 1.0, 0.005) << name;
    // Robox's 110 kg chassis over-turns ~11 mrad in each braked 90 deg corner of
    // the UMBmark squares, which the calibration reads as a 0.8 % longer
    // wheelbase (docs/calibration.md).
    EXPECT_NEAR(c.odometry.wheelbase_m / d.wheelbase_m(), 1.0, 0.01) << name;
    EXPECT_GT(c.odometry.k_left_m, 0.0) << name;
    EXPECT_LT(c.odometry.k_left_m, 1e-4) << name;
    EXPECT_DOUBLE_EQ(c.odometry.k_left_m, c.odometry.k_right_m) << name;
    EXPECT_DOUBLE_EQ(c.encoders.rate_hz, 200.0) << name;
    EXPECT_DOUBLE_EQ(c.systematic.wheel_radius_ratio, 1.0) << name;
    EXPECT_DOUBLE_EQ(c.systematic.wheelbase_factor, 1.0) << name;
  }
}

// Confirms that ROBOT arguments resolve as names under robots/ or as paths.
TEST(RobotLoaderTest, ResolvesNamesAndPaths) {
  EXPECT_EQ(ResolveRobotPath("robox"),
            (fs::path(DataRoot()) / "robots" / "robox" / "robot.yaml").string());
  const std::string folder = std::string(PAVILION_SOURCE_DIR) + "/robots/pygmalion";
  EXPECT_EQ(ResolveRobotPath(folder), folder + "/robot.yaml");
  EXPECT_EQ(ResolveRobotPath("my/robot.yaml", "/base"), "/base/my/robot.yaml");
}

// A valid robot file for the error tests, next to a copy of Pygmalion's URDF.
const std::string kRobot =
    "kind: robot\n"
    "name: test_robot\n"
    "urdf: robot.urdf\n"
    "materials:\n"
    "  shell:\n"
    "    friction: 0.5\n"
    "  foil:\n"
    "    laser: retro_reflective\n"
    "drive:\n"
    "  left_joint: left_wheel_joint\n"
    "  right_joint: right_wheel_joint\n"
    "  max_wheel_torque_nm: 20\n"
    "  max_wheel_speed_radps: 13\n"
    "  max_wheel_accel_radps2: 20\n"
    "chassis:\n"
    "  link: chassis\n"
    "  material: shell\n"
    "casters: [caster_front, caster_rear]\n"
    "encoders:\n"
    "  ticks_per_revolution: 50000\n"
    "odometry:\n"
    "  left_wheel_radius_m: 0.075\n"
    "  right_wheel_radius_m: 0.075\n"
    "  wheelbase_m: 0.38\n"
    "  k_left_m: 5.0e-6\n"
    "  k_right_m: 5.0e-6\n"
    "lasers:\n"
    "  - id: front\n"
    "    link: laser_front\n"
    "    profile: sick_lms200\n"
    "bumpers:\n"
    "  - {name: front, from_deg: -45, to_deg: 45}\n"
    "markers:\n"
    "  - id: side\n"
    "    position: [0, 0.23]\n"
    "    radius_m: 0.02\n"
    "    z_range_m: [0.4, 0.6]\n"
    "    material: foil\n";

// kRobot with `from` (which must occur) replaced by `to`.
std::string Edited(const std::string& from, const std::string& to,
                   const std::string& base = kRobot) {
  std::string text = base;
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "'" << from << "' not in the test robot";
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

// Writes `yaml` (and `urdf`, Pygmalion's by default) to a fresh folder; returns the yaml path.
std::string WriteRobot(const std::string& yaml, const std::string& urdf = "") {
  const fs::path dir = TestDir();
  if (urdf.empty()) {
    fs::copy_file(std::string(PAVILION_SOURCE_DIR) + "/robots/pygmalion/robot.urdf",
                  dir / "robot.urdf");
  } else {
    WriteFile(dir, "robot.urdf", urdf);
  }
  return WriteFile(dir, "robot.yaml", yaml);
}

// Loads a robot file that must fail; returns its diagnostics after checking that
// ValidateFile reports the same ones.
std::vector<Diagnostic> LoadErrors(const std::string& path) {
  std::vector<Diagnostic> diagnostics;
  try {
    LoadRobotFile(path);
    ADD_FAILURE() << "LoadRobotFile accepted " << path;
  } catch (const InputError& e) {
    diagnostics = e.diagnostics();
    EXPECT_EQ(std::string(e.what()), diagnostics.front().ToString());
  }
  const std::vector<Diagnostic> validated = ValidateFile(path);
  EXPECT_EQ(validated.size(), diagnostics.size());
  for (std::size_t i = 0; i < std::min(validated.size(), diagnostics.size()); ++i) {
    EXPECT_EQ(validated[i].ToString(), diagnostics[i].ToString());
  }
  return diagnostics;
}

// Expects exactly one diagnostic, at `key_path` on the line of `marker` in `yaml`.
Diagnostic ExpectError(const std::string& yaml, const std::string& key_path,
                       const std::string& marker, const std::string& urdf = "") {
  const std::string path = WriteRobot(yaml, urdf);
  const std::vector<Diagnostic> diagnostics = LoadErrors(path);
  std::string all;
  for (const Diagnostic& d : diagnostics) all += "\n  " + d.ToString();
  EXPECT_EQ(diagnostics.size(), 1u) << all;
  if (diagnostics.empty()) return {};
  const Diagnostic& d = diagnostics.front();
  EXPECT_EQ(d.file, path);
  EXPECT_EQ(d.key_path, key_path);
  EXPECT_EQ(d.line, LineOf(yaml, marker));
  EXPECT_EQ(d.ToString().find('\n'), std::string::npos);
  return d;
}

// Confirms that the test robot itself is valid and reads its values.
TEST(RobotLoaderTest, ReadsTheTestRobot) {
  const sim::RobotConfig c = LoadRobotFile(WriteRobot(kRobot));
  EXPECT_EQ(c.description.model, "test_robot");
  EXPECT_DOUBLE_EQ(c.description.max_wheel_torque_nm, 20.0);
  EXPECT_EQ(c.description.material, "shell");
  ASSERT_EQ(c.lasers.size(), 1u);
  EXPECT_EQ(c.lasers[0].link, "laser_front");
  EXPECT_NEAR(c.lasers[0].robot_from_sensor.x_m, 0.10, 1e-12);
  EXPECT_NEAR(c.lasers[0].z_m, 0.50, 1e-12);
  ASSERT_EQ(c.bumpers.size(), 1u);
  EXPECT_NEAR(c.bumpers[0].from_rad, -kPi / 4, 1e-12);
  ASSERT_EQ(c.description.markers.size(), 1u);
  EXPECT_NEAR(c.description.markers[0].position_m.y(), 0.23, 1e-12);
  EXPECT_NEAR(c.description.markers[0].base_z_m, 0.4, 1e-12);
  EXPECT_NEAR(c.description.markers[0].height_m, 0.2, 1e-12);
  EXPECT_FALSE(c.encoders.noise);
  EXPECT_EQ(c.encoders.ticks_per_revolution, 50000);
}

// Confirms that a laser's profile is the base and each key overrides one field,
// angles given in degrees.
TEST(RobotLoaderTest, LaserKeysOverrideTheProfile) {
  const std::string yaml = Edited("    profile: sick_lms200\n",
                                  "    profile: acuity_accurange\n"
                                  "    fov_deg: 270\n"
                                  "    first_bearing_deg: -135\n"
                                  "    beams: 541\n"
                                  "    noise: false\n");
  const sim::RobotConfig c = LoadRobotFile(WriteRobot(yaml));
  const sim::LaserScannerOptions acuity = sim::LaserScannerOptions::Profile("acuity_accurange");
  const sim::LaserScannerOptions& o = c.lasers.at(0).options;
  EXPECT_EQ(o.profile, "acuity_accurange");
  EXPECT_NEAR(o.fov_rad, 1.5 * kPi, 1e-12);
  EXPECT_NEAR(o.first_bearing_rad, -0.75 * kPi, 1e-12);
  EXPECT_EQ(o.beams, 541);
  EXPECT_FALSE(o.noise);
  EXPECT_EQ(o.amplitude_model, acuity.amplitude_model);  // not overridden: the profile's
  EXPECT_EQ(o.range_sigma_m, acuity.range_sigma_m);
  EXPECT_EQ(o.specular_max_incidence_rad, acuity.specular_max_incidence_rad);  // exactly
}

// Confirms that a footprint given in the file replaces the derived one (either
// orientation, stored counter-clockwise) and must be convex.
TEST(RobotLoaderTest, FootprintOverride) {
  const std::string yaml =
      Edited("  material: shell\n",
             "  material: shell\n  footprint: [[0.3, 0], [0, -0.3], [-0.3, 0], [0, 0.3]]\n");
  const sim::RobotConfig c = LoadRobotFile(WriteRobot(yaml));
  ASSERT_EQ(c.description.footprint_m.size(), 4u);
  EXPECT_NEAR(core::SignedArea(c.description.footprint_m), 0.18, 1e-12);

  const std::string concave = Edited("  material: shell\n",
                                     "  material: shell\n  footprint: [[0.3, 0.3], [-0.3, 0.3], "
                                     "[0, 0], [-0.3, -0.3], [0.3, -0.3]]\n");
  const Diagnostic d = ExpectError(concave, "chassis.footprint", "footprint:");
  EXPECT_TRUE(Contains(d.message, "convex"));
}

// Confirms that an unknown key is an error naming file, line and key path.
TEST(RobotLoaderTest, UnknownKeyIsReported) {
  Diagnostic d = ExpectError(
      Edited("  max_wheel_torque_nm: 20\n", "  max_wheel_torque_nm: 20\n  max_torque: 30\n"),
      "drive.max_torque", "max_torque:");
  EXPECT_EQ(d.message, "unknown key");
  d = ExpectError(kRobot + "colour: red\n", "colour", "colour:");
  EXPECT_EQ(d.message, "unknown key");
  d = ExpectError(Edited("    profile: sick_lms200\n", "    profile: sick_lms200\n    fov: 90\n"),
                  "lasers[0].fov", "fov:");
  EXPECT_EQ(d.message, "unknown key");
}

// Confirms that a value that is not a number (or out of range) names its key and line.
TEST(RobotLoaderTest, BadNumberIsReported) {
  Diagnostic d =
      ExpectError(Edited("  max_wheel_speed_radps: 13\n", "  max_wheel_speed_radps: fast\n"),
                  "drive.max_wheel_speed_radps", "fast");
  EXPECT_TRUE(Contains(d.message, "expected a number, got 'fast'"));
  d = ExpectError(
      Edited("    profile: sick_lms200\n", "    profile: sick_lms200\n    fov_deg: 400\n"),
      "lasers[0].fov_deg", "fov_deg");
  EXPECT_TRUE(Contains(d.message, "must be in"));
  d = ExpectError(Edited("  ticks_per_revolution: 50000\n", "  ticks_per_revolution: 0.5\n"),
                  "encoders.ticks_per_revolution", "ticks_per_revolution");
  EXPECT_TRUE(Contains(d.message, "integer"));
}

// Confirms that a sensor on a link the URDF does not have is reported at its `link`.
TEST(RobotLoaderTest, SensorOnUnknownLinkIsReported) {
  const Diagnostic d = ExpectError(Edited("    link: laser_front\n", "    link: laser_top\n"),
                                   "lasers[0].link", "laser_top");
  EXPECT_TRUE(Contains(d.message, "unknown link 'laser_top'"));
  EXPECT_TRUE(Contains(d.message, "laser_front"));  // lists the links there are
  // A wheel is not a mount either.
  const Diagnostic w = ExpectError(Edited("    link: laser_front\n", "    link: left_wheel\n"),
                                   "lasers[0].link", "left_wheel\n");
  EXPECT_TRUE(Contains(w.message, "unknown link 'left_wheel'"));
}

// Confirms that a chassis link missing from the URDF is reported at chassis.link
// with the URDF's message.
TEST(RobotLoaderTest, MissingLinkIsReportedWhereItIsNamed) {
  const Diagnostic d =
      ExpectError(Edited("  link: chassis\n", "  link: body\n"), "chassis.link", "link: body");
  EXPECT_TRUE(Contains(d.message, "robot.urdf: chassis link 'body' does not exist"));
  const Diagnostic j = ExpectError(Edited("  left_joint: left_wheel_joint\n", "  left_joint: lw\n"),
                                   "drive.left_joint", "left_joint: lw");
  EXPECT_TRUE(Contains(j.message, "joint 'lw' does not exist"));
  const Diagnostic c = ExpectError(
      Edited("[caster_front, caster_rear]", "[caster_front, caster_x]"), "casters[1]", "casters:");
  EXPECT_TRUE(Contains(c.message, "caster link 'caster_x' does not exist"));
}

// Confirms that a caster's suspension is read onto that caster, and that one
// naming no caster, or a caster twice, is reported where it is named.
TEST(RobotLoaderTest, SuspensionSpringsTheNamedCaster) {
  const std::string sprung =
      "casters: [caster_front, caster_rear]\n"
      "suspension:\n"
      "  - {caster: caster_rear, stiffness_npm: 20000, damping_nspm: 500}\n";
  const sim::RobotConfig c =
      LoadRobotFile(WriteRobot(Edited("casters: [caster_front, caster_rear]\n", sprung)));
  ASSERT_EQ(c.description.casters.size(), 2u);
  EXPECT_EQ(c.description.casters[0].stiffness_npm, 0.0);
  EXPECT_EQ(c.description.casters[1].stiffness_npm, 20000.0);
  EXPECT_EQ(c.description.casters[1].damping_nspm, 500.0);

  const Diagnostic unknown =
      ExpectError(Edited("casters: [caster_front, caster_rear]\n",
                         "casters: [caster_front, caster_rear]\nsuspension:\n"
                         "  - {caster: left_wheel, stiffness_npm: 20000}\n"),
                  "suspension[0].caster", "caster: left_wheel");
  EXPECT_TRUE(Contains(unknown.message, "not one of the robot's `casters`"));
  const Diagnostic twice = ExpectError(Edited("casters: [caster_front, caster_rear]\n",
                                              "casters: [caster_front, caster_rear]\nsuspension:\n"
                                              "  - {caster: caster_rear, stiffness_npm: 20000}\n"
                                              "  - {caster: caster_rear, stiffness_npm: 30000}\n"),
                                       "suspension[1].caster", "stiffness_npm: 30000");
  EXPECT_TRUE(Contains(twice.message, "twice"));
  ExpectError(Edited("casters: [caster_front, caster_rear]\n",
                     "casters: [caster_front, caster_rear]\nsuspension:\n"
                     "  - {caster: caster_rear, stiffness_npm: -5}\n"),
              "suspension[0].stiffness_npm", "stiffness_npm: -5");
}

// Confirms that problems inside the URDF are reported at the `urdf` key with the
// URDF's own file:line message: zero-mass chassis, joint without axis, missing link.
TEST(RobotLoaderTest, UrdfErrorsAreReportedAtTheUrdfKey) {
  const std::string pygmalion = [] {
    std::ifstream in(std::string(PAVILION_SOURCE_DIR) + "/robots/pygmalion/robot.urdf");
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  auto urdf_edited = [&](const std::string& from, const std::string& to) {
    return Edited(from, to, pygmalion);
  };
  Diagnostic d = ExpectError(kRobot, "urdf",
                             "urdf:", urdf_edited("<mass value=\"42.0\"/>", "<mass value=\"0\"/>"));
  EXPECT_TRUE(Contains(d.message, "robot.urdf:"));
  EXPECT_TRUE(Contains(d.message, "link 'chassis': the chassis needs an <inertial> with mass > 0"));

  const std::string no_axis =
      urdf_edited("    <origin xyz=\"0 0.19 0.075\" rpy=\"0 0 0\"/>\n    <axis xyz=\"0 1 0\"/>\n",
                  "    <origin xyz=\"0 0.19 0.075\" rpy=\"0 0 0\"/>\n");
  d = ExpectError(kRobot, "urdf", "urdf:", no_axis);
  EXPECT_TRUE(
      Contains(d.message, "robot.urdf:" + std::to_string(LineOf(no_axis, "\"left_wheel_joint\"")) +
                              ": joint 'left_wheel_joint': continuous joint has no <axis>"));

  d = ExpectError(kRobot, "urdf", "urdf:",
                  urdf_edited("<child link=\"laser_rear\"/>", "<child link=\"laser_back\"/>"));
  EXPECT_TRUE(
      Contains(d.message, "joint 'laser_rear_joint': child link 'laser_back' does not exist"));

  d = ExpectError(Edited("urdf: robot.urdf\n", "urdf: missing.urdf\n"), "urdf", "urdf:");
  EXPECT_TRUE(Contains(d.message, "URDF file not found"));
}

// Confirms the consistency checks of the robot file itself.
TEST(RobotLoaderTest, InconsistentValuesAreReported) {
  Diagnostic d = ExpectError(Edited("    material: foil\n", "    material: shell\n"),
                             "markers[0].material", "    material: shell");
  EXPECT_TRUE(Contains(d.message, "retro_reflective"));
  d = ExpectError(Edited("  material: shell\n", "  material: steel\n"), "chassis.material",
                  "material: steel");
  EXPECT_TRUE(Contains(d.message, "unknown material 'steel'"));
  d = ExpectError(Edited("  wheelbase_m: 0.38\n", "  wheelbase_m: 0.038\n"), "odometry.wheelbase_m",
                  "0.038");
  EXPECT_TRUE(Contains(d.message, "factor of 2"));
  d = ExpectError(Edited("from_deg: -45, to_deg: 45", "from_deg: 45, to_deg: 45"),
                  "bumpers[0].to_deg", "to_deg");
  EXPECT_TRUE(Contains(d.message, "must not be empty"));
  d = ExpectError(Edited("    profile: sick_lms200\n",
                         "    profile: sick_lms200\n  - id: front\n    link: laser_rear\n"),
                  "lasers[1].id", "id: front\n    link: laser_rear");
  EXPECT_TRUE(Contains(d.message, "used twice"));
  d = ExpectError(Edited("  ticks_per_revolution: 50000\n", "  rate_hz: 100\n"),
                  "encoders.ticks_per_revolution", "rate_hz: 100");  // the mapping's line
  EXPECT_TRUE(Contains(d.message, "required key is missing"));
}

// Confirms that an out-of-range option of four options structs (encoders,
// odometry, laser scanner, systematic errors) is one error `file:line:
// key.path: <Validate's message>` at the key's line, degrees turned into the
// struct's radians before Validate() sees them.
TEST(RobotLoaderTest, OutOfRangeOptionsReportValidateMessageAtTheirKey) {
  sim::EncoderOptions encoders;
  encoders.rate_hz = 0.0;
  core::EncoderOdometryOptions odometry;
  odometry.k_left_m = 2.0;
  sim::LaserScannerOptions laser = sim::LaserScannerOptions::Profile("sick_lms200");
  laser.beam_divergence_rad = 6.0 * kDeg;
  sim::SystematicErrors systematic;
  systematic.wheelbase_factor = 1.2;
  struct Case {
    std::string yaml, key_path, marker, message;
  };
  const std::vector<Case> cases = {
      {Edited("  ticks_per_revolution: 50000\n", "  ticks_per_revolution: 50000\n  rate_hz: 0\n"),
       "encoders.rate_hz", "rate_hz: 0", ValidateMessage(encoders)},
      {Edited("  k_left_m: 5.0e-6\n", "  k_left_m: 2\n"), "odometry.k_left_m", "k_left_m: 2",
       ValidateMessage(odometry)},
      {Edited("    profile: sick_lms200\n",
              "    profile: sick_lms200\n    beam_divergence_deg: 6\n"),
       "lasers[0].beam_divergence_deg", "beam_divergence_deg", ValidateMessage(laser)},
      {kRobot + "systematic:\n  wheelbase_factor: 1.2\n", "systematic.wheelbase_factor",
       "wheelbase_factor: 1.2", ValidateMessage(systematic)},
  };
  for (const Case& c : cases) {
    ASSERT_FALSE(c.message.empty()) << c.key_path;
    const Diagnostic d = ExpectError(c.yaml, c.key_path, c.marker);
    EXPECT_EQ(d.ToString(), d.file + ":" + std::to_string(LineOf(c.yaml, c.marker)) + ": " +
                                c.key_path + ": " + c.message);
  }
}

// Confirms that the robot loader and Validate() agree at the boundaries where
// they used to differ: beam divergence (loader [0, 5.7°], Validate [0, 0.1
// rad]), systematic errors (loader [0.5, 2], Validate (0.5, 2), now [0.9,
// 1.1]), a camera's field of view (loader [1°, 179°], now (0, π)) and the
// encoders' rate (loader [1e-3, 1e5] Hz, Validate > 0).
TEST(RobotLoaderTest, LoaderAndValidateAgreeAtTheRangeBoundaries) {
  struct Case {
    std::string key_path;
    std::function<std::string(const std::string&)> yaml;
    std::function<std::string(double)> validate;  // Validate's message for the value
    std::vector<double> values;
  };
  const std::vector<Case> cases = {
      {"lasers[0].beam_divergence_deg",
       [](const std::string& v) {
         return Edited("    profile: sick_lms200\n",
                       "    profile: sick_lms200\n    beam_divergence_deg: " + v + "\n");
       },
       [](double v) {
         sim::LaserScannerOptions o = sim::LaserScannerOptions::Profile("sick_lms200");
         o.beam_divergence_rad = v * kDeg;
         return ValidateMessage(o);
       },
       {-0.01, 0.0, 5.7, 5.72, 0.1 / kDeg, 5.73}},
      {"systematic.wheel_radius_ratio",
       [](const std::string& v) {
         return kRobot + "systematic:\n  wheel_radius_ratio: " + v + "\n";
       },
       [](double v) {
         sim::SystematicErrors o;
         o.wheel_radius_ratio = v;
         return ValidateMessage(o);
       },
       {0.5, 0.89, 0.9, 1.0, 1.1, 1.11, 2.0}},
      {"cameras[0].hfov_deg",
       [](const std::string& v) {
         return kRobot + "cameras:\n  - id: cam\n    link: laser_front\n    hfov_deg: " + v + "\n";
       },
       [](double v) {
         sim::CameraMount o;
         o.hfov_rad = v * kDeg;
         return ValidateMessage(o);
       },
       {0.0, 0.5, 1.0, 179.0, 179.5, 180.0}},
      {"encoders.rate_hz",
       [](const std::string& v) {
         return Edited("  ticks_per_revolution: 50000\n",
                       "  ticks_per_revolution: 50000\n  rate_hz: " + v + "\n");
       },
       [](double v) {
         sim::EncoderOptions o;
         o.rate_hz = v;
         return ValidateMessage(o);
       },
       {0.0, 1e-4, 1e-3, 1e5, 1e5 + 1}},
  };
  for (const Case& c : cases) {
    for (const double value : c.values) {
      const std::string yaml = c.yaml(ExactText(value));
      const std::string message = c.validate(value);
      if (message.empty()) {
        EXPECT_NO_THROW(LoadRobotFile(WriteRobot(yaml))) << c.key_path << " = " << value;
      } else {
        const Diagnostic d =
            ExpectError(yaml, c.key_path, c.key_path.substr(c.key_path.rfind('.') + 1));
        EXPECT_EQ(d.message, message) << c.key_path << " = " << value;
      }
    }
  }
}

}  // namespace
}  // namespace pavilion::scenarios
