#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "scenarios/config/input_error.h"
#include "scenarios/config/scenario.h"
#include "scenarios/config/validate.h"
#include "scenarios/events/scripted_events.h"
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

// A 16 m square hall with a door and a spawn area; no scenario materials.
const std::string kWorld =
    "kind: world\n"
    "name: test_hall\n"
    "materials:\n"
    "  concrete:\n"
    "    friction: 0.8\n"
    "  wood:\n"
    "    friction: 0.6\n"
    "floor:\n"
    "  min: [-10, -10]\n"
    "  max: [10, 10]\n"
    "  material: concrete\n"
    "walls:\n"
    "  - id: outline\n"
    "    points: [[-8, -8], [8, -8], [8, 8], [-8, 8]]\n"
    "    closed: true\n"
    "    thickness: 0.2\n"
    "    height: 2.5\n"
    "    material: concrete\n"
    "doors:\n"
    "  - id: door_1\n"
    "    hinge: [0, 5]\n"
    "    closed_yaw: 0\n"
    "    open_yaw: 1.5\n"
    "    width: 0.9\n"
    "    thickness: 0.04\n"
    "    height: 2.0\n"
    "    state: closed\n"
    "    material: wood\n"
    "places:\n"
    "  lobby:\n"
    "    area: [[-6, -6], [6, -6], [6, 6], [-6, 6]]\n"
    "  start:\n"
    "    pose: [0, 0, 0]\n";

// A scenario using kWorld as world.yaml next to it; `groups_count` visitors.
std::string ScenarioText(int groups_count = 3) {
  return "kind: scenario\n"
         "name: test_run\n"
         "seed: 3\n"
         "duration_s: 10\n"
         "world: world.yaml\n"
         "materials:\n"
         "  skin:\n"
         "    friction: 0.5\n"
         "    color: [0.9, 0.7, 0.6]\n"
         "physics:\n"
         "  rate_hz: 200\n"
         "bodies:\n"
         "  - id: cart\n"
         "    shape: {type: box, size: [0.6, 0.4, 0.5]}\n"
         "    mass_kg: 20\n"
         "    material: wood\n"
         "    pose: [1, 2, 0.5]\n"
         "    motion:\n"
         "      type: scripted\n"
         "      segments:\n"
         "        - {duration_s: 4, velocity: [0.5, 0]}\n"
         "groups:\n"
         "  - id: visitor\n"
         "    count: " +
         std::to_string(groups_count) +
         "\n"
         "    shape: {type: cylinder, radius: 0.25, height: 1.7}\n"
         "    mass_kg: 70\n"
         "    material: skin\n"
         "    area: lobby\n"
         "    motion: {type: random_walk, speed_mps: 0.8}\n"
         "events:\n"
         "  - {at_s: 2, type: push, body: visitor_001, impulse: [10, 0]}\n"
         "  - {at_s: 1, type: door, door: door_1, state: open}\n";
}

// Writes kWorld and `scenario` into the test folder; returns the scenario path.
std::string WriteScenario(const std::string& scenario, const std::string& world = kWorld) {
  const fs::path dir = TestDir();
  WriteFile(dir, "world.yaml", world);
  return WriteFile(dir, "scenario.yaml", scenario);
}

// Loads a scenario that must fail; returns its diagnostics after checking that
// ValidateFile (without overrides) agrees when there are no overrides.
std::vector<Diagnostic> LoadErrors(const std::string& path,
                                   const ScenarioOverrides& overrides = {}) {
  std::vector<Diagnostic> diagnostics;
  try {
    LoadScenarioFile(path, overrides);
    ADD_FAILURE() << "LoadScenarioFile accepted " << path;
  } catch (const InputError& e) {
    diagnostics = e.diagnostics();
  }
  if (overrides.assignments.empty()) {
    const std::vector<Diagnostic> validated = ValidateFile(path);
    EXPECT_EQ(validated.size(), diagnostics.size());
    for (std::size_t i = 0; i < std::min(validated.size(), diagnostics.size()); ++i) {
      EXPECT_EQ(validated[i].ToString(), diagnostics[i].ToString());
    }
  }
  return diagnostics;
}

// Confirms that a valid scenario loads with its bodies, world and time-sorted events.
TEST(ScenarioLoaderTest, LoadsScenarioWithWorldBodiesAndEvents) {
  const std::string path = WriteScenario(ScenarioText());
  const Scenario s = LoadScenarioFile(path);
  EXPECT_TRUE(ValidateFile(path).empty());
  EXPECT_EQ(s.name, "test_run");
  EXPECT_EQ(s.source_file, path);
  EXPECT_EQ(s.seed, 3u);
  EXPECT_DOUBLE_EQ(s.duration_s, 10.0);
  EXPECT_EQ(s.world.name, "test_hall");
  EXPECT_EQ(s.world.source_file, (fs::path(path).parent_path() / "world.yaml").string());

  ASSERT_EQ(s.bodies.size(), 4u);
  const BodyEntry& cart = s.bodies[0];
  EXPECT_EQ(cart.spec.id, "cart");
  EXPECT_EQ(cart.spec.shape.type, sim::BodyShapeType::kBox);
  EXPECT_EQ(cart.spec.shape.box_size_m, Eigen::Vector3d(0.6, 0.4, 0.5));
  EXPECT_EQ(cart.spec.pose, (core::Pose2{1, 2, 0.5}));
  EXPECT_DOUBLE_EQ(cart.spec.mass_kg, 20.0);
  EXPECT_TRUE(cart.spec.driven);
  EXPECT_FALSE(cart.spawn_polygon.has_value());
  ASSERT_EQ(cart.motion.type, MotionSpec::Type::kScripted);
  ASSERT_EQ(cart.motion.scripted.segments.size(), 1u);
  EXPECT_DOUBLE_EQ(cart.motion.scripted.segments[0].duration_s, 4.0);
  EXPECT_EQ(cart.motion.scripted.segments[0].velocity_mps, Eigen::Vector2d(0.5, 0));
  EXPECT_TRUE(cart.motion.scripted.body_frame);

  ASSERT_EQ(s.events.size(), 2u);
  const auto* door = dynamic_cast<const DoorEvent*>(s.events[0].event.get());
  ASSERT_NE(door, nullptr);  // at 1 s, listed second
  EXPECT_EQ(door->door(), "door_1");
  EXPECT_TRUE(door->open());
  const auto* push = dynamic_cast<const PushEvent*>(s.events[1].event.get());
  ASSERT_NE(push, nullptr);
  EXPECT_EQ(push->target(), "visitor_001");
  EXPECT_EQ(push->impulse_ns(), Eigen::Vector2d(10, 0));
}

// Confirms that a group expands into bodies <id>_000, <id>_001, ... sharing its fields.
TEST(ScenarioLoaderTest, ExpandsGroupsIntoNumberedBodies) {
  const Scenario s = LoadScenarioFile(WriteScenario(ScenarioText(12)));
  ASSERT_EQ(s.bodies.size(), 13u);
  for (int k = 0; k < 12; ++k) {
    const BodyEntry& b = s.bodies[1 + k];
    char expected[32];
    std::snprintf(expected, sizeof expected, "visitor_%03d", k);
    EXPECT_EQ(b.spec.id, expected);
    EXPECT_EQ(b.spawn_area, "lobby");
    ASSERT_TRUE(b.spawn_polygon.has_value());
    EXPECT_EQ(b.spawn_polygon->size(), 4u);
    EXPECT_EQ(b.motion.type, MotionSpec::Type::kRandomWalk);
    EXPECT_DOUBLE_EQ(b.motion.random_walk.speed_mps, 0.8);
    EXPECT_TRUE(b.spec.driven);
    EXPECT_EQ(b.spec.material, "skin");
    EXPECT_DOUBLE_EQ(b.spec.mass_kg, 70.0);
    EXPECT_DOUBLE_EQ(b.spec.shape.radius_m, 0.25);
  }
  EXPECT_EQ(s.bodies[1].spec.id, "visitor_000");
  EXPECT_EQ(s.bodies[12].spec.id, "visitor_011");
}

// Confirms that --seed, --duration and --set overrides take effect before validation.
TEST(ScenarioLoaderTest, AppliesOverrides) {
  const std::string path = WriteScenario(ScenarioText());
  ScenarioOverrides overrides;
  overrides.seed = 99;
  overrides.duration_s = 2.5;
  overrides.assignments = {"physics.rate_hz=100", "bodies.0.mass_kg=3",
                           "outputs.trajectory_rate_hz=5", "groups.0.count=2"};
  const Scenario s = LoadScenarioFile(path, overrides);
  EXPECT_EQ(s.seed, 99u);
  EXPECT_DOUBLE_EQ(s.duration_s, 2.5);
  EXPECT_DOUBLE_EQ(s.physics.physics_rate_hz, 100.0);
  EXPECT_DOUBLE_EQ(s.bodies[0].spec.mass_kg, 3.0);
  EXPECT_DOUBLE_EQ(s.outputs.trajectory_rate_hz, 5.0);  // section created by the override
  EXPECT_EQ(s.bodies.size(), 3u);

  // Without overrides the file's values hold.
  const Scenario plain = LoadScenarioFile(path);
  EXPECT_EQ(plain.seed, 3u);
  EXPECT_DOUBLE_EQ(plain.duration_s, 10.0);
  EXPECT_DOUBLE_EQ(plain.physics.physics_rate_hz, 200.0);
  EXPECT_DOUBLE_EQ(plain.outputs.trajectory_rate_hz, 2.0);  // the default (issue 17)
}

// Confirms that a misspelt key given with --set is reported as an unknown key.
TEST(ScenarioLoaderTest, ReportsUnknownKeyFromAssignment) {
  const std::string path = WriteScenario(ScenarioText());
  ScenarioOverrides overrides;
  overrides.assignments = {"physics.rat_hz=100"};
  const std::vector<Diagnostic> all = LoadErrors(path, overrides);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].file, path);
  EXPECT_EQ(all[0].key_path, "physics.rat_hz");
  EXPECT_EQ(all[0].message, "unknown key");
  // An out-of-range value given with --set is checked like one in the file.
  overrides.assignments = {"physics.rate_hz=5"};
  const std::vector<Diagnostic> range = LoadErrors(path, overrides);
  ASSERT_EQ(range.size(), 1u);
  EXPECT_EQ(range[0].file, path);
  EXPECT_EQ(range[0].key_path, "physics.rate_hz");
  EXPECT_TRUE(Contains(range[0].message, "must be in"));
  // The value came from the command line, not from a line of the file.
  EXPECT_EQ(range[0].line, 0);
  EXPECT_EQ(all[0].line, 0);
}

// Confirms that an event naming a body that does not exist is an error at events[0].body.
TEST(ScenarioLoaderTest, ReportsEventWithUnknownBody) {
  std::string text = ScenarioText();
  text.replace(text.find("body: visitor_001"), 17, "body: ghost");
  const std::string path = WriteScenario(text);
  const std::vector<Diagnostic> all = LoadErrors(path);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].file, path);
  EXPECT_EQ(all[0].key_path, "events[0].body");
  EXPECT_EQ(all[0].line, LineOf(text, "body: ghost"));
  EXPECT_TRUE(Contains(all[0].message, "no body 'ghost'"));
}

// A robot entry appended to the scenario text.
std::string WithRobot(const std::string& text, const std::string& robot) {
  return text + "robots:\n" + robot;
}

// Confirms that robots load their model, pose and drive profile, with body-frame
// commands turned into wheel speeds by the calibrated odometry (eq. 2.7).
TEST(ScenarioLoaderTest, LoadsRobotsWithTheirDriveProfile) {
  const std::string text = WithRobot(ScenarioText(),
                                     "  - id: r1\n"
                                     "    model: pygmalion\n"
                                     "    pose: [1, 2, 0.5]\n"
                                     "    systematic: {wheelbase_factor: 1.02}\n"
                                     "    laser_noise: false\n"
                                     "    drive:\n"
                                     "      - {at_s: 0, speed_mps: 0.3, turn_radps: 0.5}\n"
                                     "      - {at_s: 4, left: 1.5, right: -1.5}\n");
  const Scenario s = LoadScenarioFile(WriteScenario(text));
  ASSERT_EQ(s.robots.size(), 1u);
  const RobotEntry& r = s.robots[0];
  EXPECT_EQ(r.id, "r1");
  EXPECT_EQ(r.config.description.model, "pygmalion");
  EXPECT_EQ(r.pose, (core::Pose2{1, 2, 0.5}));
  EXPECT_EQ(r.config.systematic.wheelbase_factor, 1.02);
  ASSERT_FALSE(r.config.lasers.empty());
  for (const sim::LaserMount& mount : r.config.lasers)
    EXPECT_FALSE(mount.options.noise) << mount.id;
  ASSERT_EQ(r.drive.size(), 2u);
  const auto& o = r.config.odometry;
  EXPECT_NEAR(r.drive[0].left_radps * o.left_wheel_radius_m, 0.3 - 0.25 * o.wheelbase_m, 1e-12);
  EXPECT_NEAR(r.drive[0].right_radps * o.right_wheel_radius_m, 0.3 + 0.25 * o.wheelbase_m, 1e-12);
  EXPECT_EQ(r.drive[1].left_radps, 1.5);
  EXPECT_EQ(r.drive[1].right_radps, -1.5);
}

// Confirms the robot entry's errors: unknown model, a drive step mixing both
// forms, steps out of order, an id used twice.
TEST(ScenarioLoaderTest, ReportsBadRobotEntries) {
  const std::string text = WithRobot(ScenarioText(),
                                     "  - id: r1\n"
                                     "    model: no_such_robot\n"
                                     "    pose: [1, 2, 0]\n"
                                     "  - id: r2\n"
                                     "    model: robox\n"
                                     "    pose: [3, 2, 0]\n"
                                     "    drive:\n"
                                     "      - {at_s: 2, left: 1, speed_mps: 0.3}\n"
                                     "      - {at_s: 1, left: 1, right: 1}\n"
                                     "  - id: visitor_001\n"
                                     "    model: robox\n"
                                     "    pose: [-3, 2, 0]\n");
  const std::string path = WriteScenario(text);
  const std::vector<Diagnostic> all = LoadErrors(path);
  std::vector<std::string> keys;
  for (const Diagnostic& d : all) {
    EXPECT_EQ(d.file, path);
    EXPECT_GT(d.line, 0) << d.ToString();
    keys.push_back(d.key_path);
  }
  EXPECT_NE(std::find(keys.begin(), keys.end(), "robots[0].model"), keys.end());
  EXPECT_NE(std::find(keys.begin(), keys.end(), "robots[1].drive[0]"), keys.end());
  EXPECT_NE(std::find(keys.begin(), keys.end(), "robots[1].drive[1]"), keys.end());
  EXPECT_NE(std::find(keys.begin(), keys.end(), "robots[2].id"), keys.end());
  for (const Diagnostic& d : all) {
    if (d.key_path == "robots[0].model") {
      EXPECT_EQ(d.line, LineOf(text, "model: no_such_robot"));
    }
  }
}

// Confirms the wheel model: articulated by default, the scenario's
// physics.wheel_model for every robot unless an entry names its own, and a bad
// name reported at its key and line.
TEST(ScenarioLoaderTest, ReadsTheWheelModelPerScenarioAndRobot) {
  const std::string robots =
      "  - id: r1\n"
      "    model: pygmalion\n"
      "    pose: [1, 2, 0]\n"
      "  - id: r2\n"
      "    model: robox\n"
      "    pose: [3, 2, 0]\n"
      "    wheel_model: articulated\n";
  const Scenario plain = LoadScenarioFile(WriteScenario(WithRobot(ScenarioText(), robots)));
  EXPECT_EQ(plain.wheel_model, sim::WheelModel::kArticulated);
  EXPECT_EQ(plain.robots[0].wheel_model, sim::WheelModel::kArticulated);
  std::string text = WithRobot(ScenarioText(), robots);
  const std::string rate = "  rate_hz: 200\n";
  text.replace(text.find(rate), rate.size(), "  rate_hz: 100\n  wheel_model: raycast\n");
  const Scenario fast = LoadScenarioFile(WriteScenario(text));
  EXPECT_EQ(fast.wheel_model, sim::WheelModel::kRaycast);
  EXPECT_EQ(fast.robots[0].wheel_model, sim::WheelModel::kRaycast);
  EXPECT_EQ(fast.robots[1].wheel_model, sim::WheelModel::kArticulated);
  EXPECT_DOUBLE_EQ(fast.physics.physics_rate_hz, 100.0);

  const std::string bad = WithRobot(ScenarioText(),
                                    "  - id: r1\n"
                                    "    model: pygmalion\n"
                                    "    pose: [1, 2, 0]\n"
                                    "    wheel_model: hovercraft\n");
  const std::string path = WriteScenario(bad);
  const std::vector<Diagnostic> all = LoadErrors(path);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].file, path);
  EXPECT_EQ(all[0].key_path, "robots[0].wheel_model");
  EXPECT_EQ(all[0].line, LineOf(bad, "wheel_model: hovercraft"));
  EXPECT_TRUE(Contains(all[0].message, "raycast")) << all[0].message;
}

// Localization and route entries: read with their defaults; a missing map file,
// an unknown laser, a drive and a route on one robot are errors with lines.
TEST(ScenarioLoaderTest, LoadsLocalizationAndRouteAndReportsTheirErrors) {
  const std::string good = WithRobot(ScenarioText(),
                                     "  - id: r1\n"
                                     "    model: pygmalion\n"
                                     "    pose: [1, 2, 0]\n"
                                     "    localization:\n"
                                     "      map: loc_map.yaml\n"
                                     "      rate_hz: 4\n"
                                     "      initial_offset: [0.3, 0, 0.05]\n"
                                     "      lasers: [front]\n"
                                     "    route:\n"
                                     "      stops: [a, b]\n"
                                     "      max_speed_mps: 0.4\n");
  const std::string good_path = WriteScenario(good);
  // The loader checks that the map exists; the run reads it.
  WriteFile(fs::path(good_path).parent_path(), "loc_map.yaml", "kind: map\nname: m\n");
  const Scenario s = LoadScenarioFile(good_path);
  ASSERT_EQ(s.robots.size(), 1u);
  const RobotEntry& r = s.robots[0];
  EXPECT_TRUE(r.localization.enabled);
  EXPECT_EQ(fs::path(r.localization.map_file).filename(), "loc_map.yaml");
  EXPECT_EQ(r.localization.rate_hz, 4.0);
  EXPECT_EQ(r.localization.initial_offset, (core::Pose2{0.3, 0.0, 0.05}));
  EXPECT_EQ(r.localization.lasers, (std::vector<std::string>{"front"}));
  ASSERT_TRUE(r.route.has_value());
  EXPECT_EQ(r.route->stops, (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(r.route->follower.max_speed_mps, 0.4);

  const std::string bad = WithRobot(ScenarioText(),
                                    "  - id: r1\n"
                                    "    model: pygmalion\n"
                                    "    pose: [1, 2, 0]\n"
                                    "    drive:\n"
                                    "      - {at_s: 0, left: 1, right: 1}\n"
                                    "    localization:\n"
                                    "      map: no_such_map.yaml\n"
                                    "      lasers: [top]\n"
                                    "    route:\n"
                                    "      stops: [a]\n");
  const std::string path = WriteScenario(bad);
  std::vector<std::string> keys;
  for (const Diagnostic& d : LoadErrors(path)) {
    EXPECT_EQ(d.file, path);
    EXPECT_GT(d.line, 0) << d.ToString();
    keys.push_back(d.key_path);
  }
  for (const char* key : {"robots[0].localization.map", "robots[0].localization.lasers[0]",
                          "robots[0].route.stops", "robots[0].route"}) {
    EXPECT_NE(std::find(keys.begin(), keys.end(), key), keys.end()) << key;
  }

  // `map: derive` takes a tape-measure sigma; map_noise_m without it is an error.
  const std::string derive = WithRobot(ScenarioText(),
                                       "  - id: r1\n"
                                       "    model: pygmalion\n"
                                       "    pose: [1, 2, 0]\n"
                                       "    localization:\n"
                                       "      map: derive\n"
                                       "      map_noise_m: 0.002\n");
  const Scenario d = LoadScenarioFile(WriteScenario(derive));
  ASSERT_TRUE(d.robots[0].localization.derive_map_noise_m.has_value());
  EXPECT_EQ(*d.robots[0].localization.derive_map_noise_m, 0.002);
  const std::string stray = WithRobot(ScenarioText(),
                                      "  - id: r1\n"
                                      "    model: pygmalion\n"
                                      "    pose: [1, 2, 0]\n"
                                      "    localization:\n"
                                      "      map_noise_m: 0.002\n");
  const std::vector<Diagnostic> stray_errors = LoadErrors(WriteScenario(stray));
  ASSERT_FALSE(stray_errors.empty());
  EXPECT_EQ(stray_errors[0].key_path, "robots[0].localization.map_noise_m");
  EXPECT_EQ(stray_errors[0].line, LineOf(stray, "map_noise_m: 0.002"));
}

// A wander entry (the hall benchmark's controller): defaults are the peers'
// values, the laser defaults to the model's first; an unknown laser, bad
// options and a wander beside a drive or route are errors at their key and line.
TEST(ScenarioLoaderTest, LoadsWanderAndReportsItsErrors) {
  const std::string good = WithRobot(ScenarioText(),
                                     "  - id: r1\n"
                                     "    model: hall_bot\n"
                                     "    pose: [1, 2, 0]\n"
                                     "    wander: {}\n"
                                     "  - id: r2\n"
                                     "    model: pygmalion\n"
                                     "    pose: [3, 2, 0]\n"
                                     "    wander:\n"
                                     "      laser: rear\n"
                                     "      cruise_speed_mps: 0.3\n"
                                     "      min_avoid_scans: 2\n"
                                     "      max_avoid_scans: 4\n");
  const Scenario s = LoadScenarioFile(WriteScenario(good));
  ASSERT_EQ(s.robots.size(), 2u);
  ASSERT_TRUE(s.robots[0].wander.has_value());
  EXPECT_EQ(s.robots[0].wander->laser, "front");
  EXPECT_EQ(s.robots[0].wander->options.cruise_speed_mps, nav::WanderOptions{}.cruise_speed_mps);
  EXPECT_EQ(s.robots[0].wander->options.max_avoid_scans, 19);
  ASSERT_TRUE(s.robots[1].wander.has_value());
  EXPECT_EQ(s.robots[1].wander->laser, "rear");
  EXPECT_EQ(s.robots[1].wander->options.cruise_speed_mps, 0.3);
  EXPECT_EQ(s.robots[1].wander->options.min_avoid_scans, 2);
  EXPECT_EQ(s.robots[1].wander->options.max_avoid_scans, 4);

  const std::string bad = WithRobot(ScenarioText(),
                                    "  - id: r1\n"
                                    "    model: hall_bot\n"
                                    "    pose: [1, 2, 0]\n"
                                    "    drive:\n"
                                    "      - {at_s: 0, left: 1, right: 1}\n"
                                    "    wander: {laser: top}\n"
                                    "  - id: r2\n"
                                    "    model: hall_bot\n"
                                    "    pose: [3, 2, 0]\n"
                                    "    wander:\n"
                                    "      stop_distance_m: 2.0\n"
                                    "      min_avoid_scans: 5\n"
                                    "      max_avoid_scans: 3\n"
                                    "      turbo: true\n");
  const std::string path = WriteScenario(bad);
  std::map<std::string, int> lines;
  for (const Diagnostic& d : LoadErrors(path)) {
    EXPECT_EQ(d.file, path);
    EXPECT_GT(d.line, 0) << d.ToString();
    lines[d.key_path] = d.line;
  }
  EXPECT_EQ(lines["robots[0].wander.laser"], LineOf(bad, "wander: {laser: top}"));
  EXPECT_EQ(lines["robots[0].wander"], LineOf(bad, "wander: {laser: top}"));
  EXPECT_EQ(lines["robots[1].wander.stop_distance_m"], LineOf(bad, "stop_distance_m: 2.0"));
  EXPECT_EQ(lines["robots[1].wander.max_avoid_scans"], LineOf(bad, "max_avoid_scans: 3"));
  EXPECT_EQ(lines["robots[1].wander.turbo"], LineOf(bad, "turbo: true"));
}

// Confirms that a body material defined neither by the world nor the scenario is an error.
TEST(ScenarioLoaderTest, ReportsUnknownBodyMaterial) {
  std::string text = ScenarioText();
  text.replace(text.find("material: wood"), 14, "material: marble");
  const std::string path = WriteScenario(text);
  const std::vector<Diagnostic> all = LoadErrors(path);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].file, path);
  EXPECT_EQ(all[0].key_path, "bodies[0].material");
  EXPECT_EQ(all[0].line, LineOf(text, "material: marble"));
  EXPECT_TRUE(Contains(all[0].message, "unknown material 'marble'"));
}

// Confirms that scenario-level materials add new materials bodies can use, but may
// not redefine the world's.
TEST(ScenarioLoaderTest, ScenarioMaterialsAreUsableByBodies) {
  const Scenario s = LoadScenarioFile(WriteScenario(ScenarioText()));
  ASSERT_TRUE(s.world.materials.contains("skin"));
  EXPECT_DOUBLE_EQ(s.world.materials.at("skin").friction, 0.5);
  EXPECT_DOUBLE_EQ(s.world.materials.at("skin").rgba[0], 0.9);
  EXPECT_TRUE(s.world.materials.contains("concrete"));  // the world's stay
  EXPECT_EQ(s.bodies.back().spec.material, "skin");

  // Without the scenario's materials section, "skin" is unknown.
  std::string text = ScenarioText();
  const std::size_t from = text.find("materials:\n");
  text.erase(from, text.find("physics:") - from);
  const std::vector<Diagnostic> missing = LoadErrors(WriteScenario(text));
  ASSERT_EQ(missing.size(), 1u);
  EXPECT_EQ(missing[0].key_path, "groups[0].material");

  // Redefining a world material is an error.
  text = ScenarioText();
  text.replace(text.find("  skin:\n"), 8, "  concrete:\n");
  text.replace(text.find("material: skin"), 14, "material: concrete");
  const std::vector<Diagnostic> twice = LoadErrors(WriteScenario(text));
  ASSERT_EQ(twice.size(), 1u);
  EXPECT_EQ(twice[0].key_path, "materials.concrete");
  EXPECT_TRUE(Contains(twice[0].message, "already defined by the world"));
}

// Confirms that problems of the world file are reported against the world file.
TEST(ScenarioLoaderTest, ReportsWorldErrorsAgainstWorldFile) {
  std::string world = kWorld;
  world.replace(world.find("thickness: 0.2"), 14, "thickness: -1");
  const std::string path = WriteScenario(ScenarioText(), world);
  const std::string world_path = (fs::path(path).parent_path() / "world.yaml").string();
  const std::vector<Diagnostic> all = LoadErrors(path);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].file, world_path);
  EXPECT_EQ(all[0].key_path, "walls[0].thickness");
  EXPECT_EQ(all[0].line, LineOf(world, "thickness: -1"));
  EXPECT_EQ(all[0].ToString().rfind(world_path + ":", 0), 0u);

  // A world that does not exist is named by its resolved path.
  std::string text = ScenarioText();
  text.replace(text.find("world: world.yaml"), 17, "world: missing/world.yaml");
  const std::string path2 = WriteScenario(text);
  const std::vector<Diagnostic> gone = LoadErrors(path2);
  ASSERT_EQ(gone.size(), 1u);
  EXPECT_EQ(gone[0].file, (fs::path(path2).parent_path() / "missing" / "world.yaml").string());
}

// Confirms that every shipped scenario file (scenarios/ and its folders, such
// as hall_bench/) validates with no diagnostics.
TEST(ScenarioLoaderTest, EveryShippedScenarioValidates) {
  const fs::path dir = fs::path(PAVILION_SOURCE_DIR) / "scenarios";
  std::vector<fs::path> files;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const std::string ext = entry.path().extension().string();
    if (entry.is_regular_file() && (ext == ".yaml" || ext == ".yml")) files.push_back(entry.path());
  }
  if (files.empty()) GTEST_SKIP() << "no scenario files under " << dir << " yet";
  std::sort(files.begin(), files.end());
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.string());
    for (const Diagnostic& d : ValidateFile(file.string())) ADD_FAILURE() << d.ToString();
    EXPECT_NO_THROW(LoadScenarioFile(file.string()));
  }
}

}  // namespace
}  // namespace pavilion::scenarios

namespace pavilion::scenarios {
namespace {

// Issue 7: laser_backend is planar by default, bullet on request, and a bad
// value is one error naming the file, key and line; laser_max_tilt_deg sets
// the planar caster's fallback angle.
TEST(ScenarioLoaderTest, ReadsAndValidatesTheLaserBackend) {
  const Scenario plain = LoadScenarioFile(WriteScenario(ScenarioText()));
  EXPECT_EQ(plain.laser_backend, LaserBackend::kPlanar);
  EXPECT_NEAR(plain.planar_laser.max_tilt_rad, std::numbers::pi / 180.0, 1e-15);
  const Scenario bullet = LoadScenarioFile(
      WriteScenario("laser_backend: bullet\nlaser_max_tilt_deg: 2.5\n" + ScenarioText()));
  EXPECT_EQ(bullet.laser_backend, LaserBackend::kBullet);
  EXPECT_NEAR(bullet.planar_laser.max_tilt_rad, 2.5 * std::numbers::pi / 180.0, 1e-15);
  const std::string path = WriteScenario(ScenarioText() + "laser_backend: fast\n");
  const std::vector<Diagnostic> errors = LoadErrors(path);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].file, path);
  EXPECT_EQ(errors[0].key_path, "laser_backend");
  EXPECT_GT(errors[0].line, 0);
  EXPECT_TRUE(Contains(errors[0].message, "planar, bullet")) << errors[0].message;
  const std::vector<Diagnostic> tilt =
      LoadErrors(WriteScenario(ScenarioText() + "laser_max_tilt_deg: 90\n"));
  ASSERT_EQ(tilt.size(), 1u);
  EXPECT_EQ(tilt[0].key_path, "laser_max_tilt_deg");
}

}  // namespace
}  // namespace pavilion::scenarios

namespace pavilion::scenarios {
namespace {

// A robot entry of pygmalion at (1, 2) with `extra` lines under it.
std::string PygmalionWith(const std::string& extra) {
  return WithRobot(ScenarioText(),
                   "  - id: r1\n"
                   "    model: pygmalion\n"
                   "    pose: [1, 2, 0]\n" +
                       extra);
}

// Confirms that an out-of-range option of six different options structs is
// one error `file:line: key.path: <Validate's message>` at the key's line:
// the range lives in the struct's Validate() and the loader reports it.
TEST(ScenarioLoaderTest, OutOfRangeOptionsReportValidateMessageAtTheirKey) {
  struct Case {
    std::string text;      // the scenario
    std::string marker;    // text on the key's line
    std::string key_path;  // expected key path
    std::string message;   // Validate's message for the same value
  };
  nav::WanderOptions wander;
  wander.avoid_turn_rate_radps = 0.0;
  nav::PathFollowerOptions follower;
  follower.lookahead_m = 20.0;
  sim::RandomWalkOptions walk;
  walk.speed_mps = 9.0;
  sim::WorldOptions physics;
  physics.solver_iterations = 500;
  OutputOptions outputs;
  outputs.image_width_px = 50;
  sim::SystematicErrors systematic;
  systematic.wheelbase_factor = 1.5;
  std::string walker = ScenarioText();
  walker.replace(walker.find("speed_mps: 0.8"), 14, "speed_mps: 9");
  std::string solver = ScenarioText();
  solver.replace(solver.find("  rate_hz: 200\n"), 15, "  rate_hz: 200\n  solver_iterations: 500\n");
  const std::vector<Case> cases = {
      {PygmalionWith("    wander:\n      avoid_turn_rate_radps: 0\n"), "avoid_turn_rate_radps: 0",
       "robots[0].wander.avoid_turn_rate_radps", ValidateMessage(wander)},
      {PygmalionWith("    route:\n      stops: [a, b]\n      lookahead_m: 20\n"), "lookahead_m: 20",
       "robots[0].route.lookahead_m", ValidateMessage(follower)},
      {walker, "speed_mps: 9", "groups[0].motion.speed_mps", ValidateMessage(walk)},
      {solver, "solver_iterations: 500", "physics.solver_iterations", ValidateMessage(physics)},
      {ScenarioText() + "outputs:\n  image_width_px: 50\n", "image_width_px: 50",
       "outputs.image_width_px", ValidateMessage(outputs)},
      {PygmalionWith("    systematic: {wheelbase_factor: 1.5}\n"), "wheelbase_factor: 1.5",
       "robots[0].systematic.wheelbase_factor", ValidateMessage(systematic)},
  };
  for (const Case& c : cases) {
    ASSERT_FALSE(c.message.empty()) << c.key_path;
    const std::string path = WriteScenario(c.text);
    const std::vector<Diagnostic> all = LoadErrors(path);
    ASSERT_EQ(all.size(), 1u) << c.key_path;
    EXPECT_EQ(all[0].ToString(), path + ":" + std::to_string(LineOf(c.text, c.marker)) + ": " +
                                     c.key_path + ": " + c.message);
  }
}

// Confirms that the loader and Validate() agree at the boundaries of their
// ranges: a value Validate() accepts loads, one it rejects is an error at its
// key (avoid_turn_rate_radps was [1e-6, 10] in the loader, (0, 10] in Validate).
TEST(ScenarioLoaderTest, LoaderAndValidateAgreeAtTheRangeBoundaries) {
  using Mutate = std::function<void(double)>;
  nav::WanderOptions wander;
  nav::PathFollowerOptions follower;
  sim::WorldOptions physics;
  struct Case {
    std::string key;  // under the block
    std::string block;
    std::function<std::string(const std::string& value)> text;
    Mutate set;
    std::function<std::string()> validate;
    std::vector<double> values;
  };
  const auto wander_text = [](const std::string& key) {
    return [key](const std::string& v) {
      return PygmalionWith("    wander:\n      " + key + ": " + v + "\n");
    };
  };
  const std::vector<Case> cases = {
      {"avoid_turn_rate_radps",
       "robots[0].wander",
       wander_text("avoid_turn_rate_radps"),
       [&](double v) { wander = {}, wander.avoid_turn_rate_radps = v; },
       [&] { return ValidateMessage(wander); },
       {-1e-9, 0.0, 1e-9, 1e-7, 1e-6, 10.0, std::nextafter(10.0, 11.0)}},
      {"obstruction_distance_m",
       "robots[0].wander",
       [](const std::string& v) {  // with stop_distance_m 0, below any obstruction distance
         return PygmalionWith(
             "    wander:\n      stop_distance_m: 0\n      obstruction_distance_m: " + v + "\n");
       },
       [&](double v) {
         wander = {};
         wander.stop_distance_m = 0.0;
         wander.obstruction_distance_m = v;
       },
       [&] { return ValidateMessage(wander); },
       {0.0, 1e-4, 0.5, 1000.0, 1000.5}},
      {"max_speed_mps",
       "robots[0].route",
       [](const std::string& v) {
         return PygmalionWith("    route:\n      stops: [a, b]\n      max_speed_mps: " + v + "\n");
       },
       [&](double v) { follower.max_speed_mps = v; },
       [&] { return ValidateMessage(follower); },
       {0.005, 0.01, 5.0, 5.5}},
      {"rate_hz",
       "physics",
       [](const std::string& v) {
         std::string text = ScenarioText();
         text.replace(text.find("  rate_hz: 200\n"), 15, "  rate_hz: " + v + "\n");
         return text;
       },
       [&](double v) { physics.physics_rate_hz = v; },
       [&] { return ValidateMessage(physics); },
       {9.999, 10.0, 10000.0, 10000.5}},
  };
  for (const Case& c : cases) {
    for (const double value : c.values) {
      c.set(value);
      const std::string message = c.validate();
      const std::string path = WriteScenario(c.text(ExactText(value)));
      if (message.empty()) {
        EXPECT_NO_THROW(LoadScenarioFile(path)) << c.key << " = " << value;
        EXPECT_TRUE(ValidateFile(path).empty()) << c.key << " = " << value;
      } else {
        const std::vector<Diagnostic> all = LoadErrors(path);
        ASSERT_EQ(all.size(), 1u) << c.key << " = " << value;
        EXPECT_EQ(all[0].key_path, c.block + "." + c.key);
        EXPECT_EQ(all[0].message, message);
        EXPECT_GT(all[0].line, 0);
      }
    }
  }
}

// Confirms that every out-of-range field of one options struct is reported,
// each at its own key, and that a relation between fields (stop distance
// beyond the obstruction distance) is reported at the field Validate() names
// even when that key is absent (at the block's line).
TEST(ScenarioLoaderTest, ReportsEveryBadFieldOfAnOptionsStruct) {
  const std::string text = PygmalionWith(
      "    wander:\n"
      "      cruise_speed_mps: 11\n"
      "      avoid_speed_mps: -1\n"
      "      max_avoid_scans: 2000000\n"
      "  - id: r2\n"
      "    model: pygmalion\n"
      "    pose: [3, 2, 0]\n"
      "    wander:\n"
      "      obstruction_distance_m: 0.2\n");
  const std::string path = WriteScenario(text);
  std::map<std::string, int> lines;
  for (const Diagnostic& d : LoadErrors(path)) lines[d.key_path] = d.line;
  EXPECT_EQ(lines.size(), 4u);
  EXPECT_EQ(lines["robots[0].wander.cruise_speed_mps"], LineOf(text, "cruise_speed_mps: 11"));
  EXPECT_EQ(lines["robots[0].wander.avoid_speed_mps"], LineOf(text, "avoid_speed_mps: -1"));
  EXPECT_EQ(lines["robots[0].wander.max_avoid_scans"], LineOf(text, "max_avoid_scans: 2000000"));
  EXPECT_EQ(lines["robots[1].wander.stop_distance_m"], LineOf(text, "obstruction_distance_m: 0.2"));
}

// Confirms that type errors stay the reader's (before Validate): a string for a
// number and a fraction for an integer are errors at their key.
TEST(ScenarioLoaderTest, ReportsOptionTypeErrorsAtTheirKey) {
  const std::string text = PygmalionWith(
      "    wander:\n"
      "      cruise_speed_mps: fast\n"
      "      min_avoid_scans: 2.5\n");
  std::map<std::string, std::string> messages;
  for (const Diagnostic& d : LoadErrors(WriteScenario(text))) messages[d.key_path] = d.message;
  EXPECT_EQ(messages.size(), 2u);
  EXPECT_EQ(messages["robots[0].wander.cruise_speed_mps"], "expected a number, got 'fast'");
  EXPECT_EQ(messages["robots[0].wander.min_avoid_scans"], "expected an integer");
}

}  // namespace
}  // namespace pavilion::scenarios
