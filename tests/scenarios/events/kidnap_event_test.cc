// The kidnap event's reader (issue 17, "Event timeline"): bad robots, poses and
// times are one line each naming file:line: key; every_s repeats; a robot's
// teleport is a kidnap.
#include "scenarios/events/kidnap_event.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scenarios/config/input_error.h"
#include "scenarios/config/scenario.h"
#include "scenarios/events/free_space.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

using pavilion::testing::Contains;
using pavilion::testing::LineOf;
using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

// A 16 m square room (0.2 m walls) with a 2 m box exhibit at its centre.
const char* const kWorld =
    "kind: world\n"
    "name: kidnap_room\n"
    "materials:\n"
    "  concrete: {friction: 0.8}\n"
    "floor: {min: [-10, -10], max: [10, 10], material: concrete}\n"
    "walls:\n"
    "  - {id: outline, points: [[-8, -8], [8, -8], [8, 8], [-8, 8]], closed: true,\n"
    "     thickness: 0.2, height: 2.5, material: concrete}\n"
    "boxes:\n"
    "  - {id: exhibit, pose: [0, 0, 0], size: [2, 2, 1], material: concrete}\n";

// A scenario of 10 s with robot r1 in kWorld and the given event lines.
std::string ScenarioWith(const std::string& events) {
  return "kind: scenario\n"
         "name: kidnap_test\n"
         "seed: 4\n"
         "duration_s: 10\n"
         "world: world.yaml\n"
         "robots:\n"
         "  - {id: r1, model: robox, pose: [-5, -5, 0]}\n"
         "events:\n" +
         events;
}

std::string Write(const std::string& scenario) {
  const auto dir = TestDir();
  WriteFile(dir, "world.yaml", kWorld);
  return WriteFile(dir, "scenario.yaml", scenario);
}

std::vector<Diagnostic> Errors(const std::string& path) {
  try {
    LoadScenarioFile(path);
  } catch (const InputError& e) {
    return e.diagnostics();
  }
  ADD_FAILURE() << "loaded " << path;
  return {};
}

// Expects exactly one problem, at `key_path` on the line of `marker`, saying `says`.
void ExpectOneError(const std::string& events, const std::string& marker,
                    const std::string& key_path, const std::string& says) {
  const std::string text = ScenarioWith(events);
  const std::string path = Write(text);
  const std::vector<Diagnostic> all = Errors(path);
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].file, path);
  EXPECT_EQ(all[0].line, LineOf(text, marker));
  EXPECT_EQ(all[0].key_path, key_path);
  EXPECT_TRUE(Contains(all[0].message, says)) << all[0].ToString();
  // One line, file:line: key: message.
  const std::string line = all[0].ToString();
  EXPECT_EQ(line.find('\n'), std::string::npos);
  EXPECT_EQ(line.rfind(path + ":" + std::to_string(all[0].line) + ": " + key_path + ": ", 0), 0u)
      << line;
}

// Confirms that a kidnap of a robot the scenario lacks is an error at its robot key.
TEST(KidnapEventTest, UnknownRobotIsAnError) {
  ExpectOneError("  - {at_s: 2, type: kidnap, robot: r9}\n", "robot: r9", "events[0].robot",
                 "no robot 'r9'");
}

// Confirms that a pose inside the wall (its 0.2 m thickness, and the robot's
// footprint beside it) or inside the exhibit is an error at the pose key.
TEST(KidnapEventTest, PoseInAWallOrExhibitIsAnError) {
  ExpectOneError("  - {at_s: 2, type: kidnap, robot: r1, pose: [8.0, 3.0, 0.0]}\n", "at_s: 2",
                 "events[0].pose", "would overlap 'outline'");
  ExpectOneError("  - {at_s: 2, type: kidnap, robot: r1, pose: [0.2, 0.1, 0.0]}\n", "at_s: 2",
                 "events[0].pose", "would overlap 'exhibit'");
  ExpectOneError("  - {at_s: 2, type: teleport, body: r1, pose: [-8.1, 0.0, 0.0]}\n", "at_s: 2",
                 "events[0].pose", "would overlap 'outline'");
}

// Confirms that a pose beyond the floor is an error at the pose key.
TEST(KidnapEventTest, PoseOutsideTheWorldIsAnError) {
  ExpectOneError("  - {at_s: 2, type: kidnap, robot: r1, pose: [12.0, 0.0, 0.0]}\n", "at_s: 2",
                 "events[0].pose", "outside the world's floor");
}

// Confirms that an event due after the file's duration_s is an error at its at_s.
TEST(KidnapEventTest, AtPastDurationIsAnError) {
  ExpectOneError("  - {at_s: 12, type: kidnap, robot: r1}\n", "at_s: 12", "events[0].at_s",
                 "after the scenario's duration_s (10 s)");
}

// Confirms that a free pose, a random kidnap repeated every 3 s and a robot's
// teleport load as kidnaps with their options.
TEST(KidnapEventTest, LoadsPosesRepeatsAndTeleportAlias) {
  const std::string path = Write(ScenarioWith(
      "  - {at_s: 2, type: kidnap, robot: r1, every_s: 3, min_distance_m: 3, min_turn_deg: 45}\n"
      "  - {at_s: 1, type: kidnap, robot: r1, pose: [5, 5, 1.0]}\n"
      "  - {at_s: 9.5, type: teleport, body: r1, pose: [-5, 5, 0.0]}\n"
      "  - {at_s: 0, type: kidnap, robot: r1, per_m: 0.005, turn_deg: 180}\n"));
  const Scenario s = LoadScenarioFile(path);
  std::vector<double> times;
  for (const TimedEvent& e : s.events) times.push_back(e.at_s);
  EXPECT_EQ(times, (std::vector<double>{0, 1, 2, 5, 8, 9.5}));
  const auto* random = dynamic_cast<const KidnapEvent*>(s.events[2].event.get());
  ASSERT_NE(random, nullptr);
  EXPECT_FALSE(random->pose().has_value());
  EXPECT_DOUBLE_EQ(random->options().min_distance_m, 3.0);
  EXPECT_NEAR(random->options().min_turn_rad, 45.0 * 3.14159265358979 / 180.0, 1e-9);
  EXPECT_EQ(s.events[3].event, s.events[2].event);  // one event, repeated
  const auto* fixed = dynamic_cast<const KidnapEvent*>(s.events[1].event.get());
  ASSERT_NE(fixed, nullptr);
  EXPECT_DOUBLE_EQ(fixed->pose()->theta_rad, 1.0);
  const auto* alias = dynamic_cast<const KidnapEvent*>(s.events[5].event.get());
  ASSERT_NE(alias, nullptr);
  EXPECT_EQ(alias->type(), "kidnap");
  const auto* by_distance = dynamic_cast<const KidnapEvent*>(s.events[0].event.get());
  ASSERT_NE(by_distance, nullptr);
  EXPECT_TRUE(by_distance->ongoing());
  EXPECT_DOUBLE_EQ(by_distance->options().per_m, 0.005);
}

// Confirms the free-space check: a disc clear of the room's walls and exhibit
// is free, one touching the exhibit or its inside is not.
TEST(KidnapEventTest, StaticObstacleAtFindsWallsAndInsides) {
  sim::WorldDescription world;
  world.floor.min_m = {-10, -10};
  world.floor.max_m = {10, 10};
  sim::Box box;
  box.id = "exhibit";
  box.size_m = {4, 4, 1};
  world.boxes.push_back(box);
  const RobotFootprint footprint{0.4, 0.05, 0.5};
  EXPECT_EQ(StaticObstacleAt(world, footprint, {5, 5, 0}), "");
  EXPECT_EQ(StaticObstacleAt(world, footprint, {2.3, 0, 0}), "exhibit");  // 0.3 m from its face
  EXPECT_EQ(StaticObstacleAt(world, footprint, {0, 0, 0}), "exhibit");    // inside, far from faces
  EXPECT_EQ(StaticObstacleAt(world, footprint, {9.8, 0, 0}), kFloorEdge);
}

}  // namespace
}  // namespace pavilion::scenarios
