// The spawn_group event (issue 17's timeline, with the crowd of issue 16): a
// burst of visitors enters at a spot or place; bad input is one line naming
// file:line: key.
#include "scenarios/events/crowd_events.h"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scenarios/config/scenario.h"
#include "scenarios/run/scenario_runner.h"
#include "tests/support/load_errors.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

using pavilion::testing::LineOf;
using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

// A 16 m square room with a 2 m box exhibit at its centre, a door-less
// entrance area in one corner and a lobby place.
const char* const kWorld =
    "kind: world\n"
    "name: spawn_room\n"
    "materials:\n"
    "  concrete: {friction: 0.8}\n"
    "  visitor: {friction: 0.6}\n"
    "floor: {min: [-10, -10], max: [10, 10], material: concrete}\n"
    "walls:\n"
    "  - {id: outline, points: [[-8, -8], [8, -8], [8, 8], [-8, 8]], closed: true,\n"
    "     thickness: 0.2, height: 2.5, material: concrete}\n"
    "boxes:\n"
    "  - {id: exhibit, pose: [0, 0, 0], size: [2, 2, 1], material: concrete}\n"
    "places:\n"
    "  visitor_spawn: {area: [[-7, -7], [-5, -7], [-5, -5], [-7, -5]]}\n"
    "  visitor_exit: {area: [[5, 5], [7, 5], [7, 7], [5, 7]]}\n"
    "  lobby: {pose: [4, -4, 0]}\n"
    "  station_exhibit: {pose: [0, -2, 1.5708]}\n";

std::string ScenarioWith(const std::string& crowd, const std::string& events) {
  return "kind: scenario\n"
         "name: spawn_test\n"
         "seed: 4\n"
         "duration_s: 10\n"
         "world: world.yaml\n" +
         crowd + "events:\n" + events;
}

const std::string kCrowd = "crowd: {pool: 12, max_present: 12}\n";

std::string Write(const std::string& scenario) {
  const auto dir = TestDir();
  WriteFile(dir, "world.yaml", kWorld);
  return WriteFile(dir, "scenario.yaml", scenario);
}

void ExpectOneError(const std::string& crowd, const std::string& events, const std::string& marker,
                    const std::string& key_path, const std::string& says) {
  const std::string text = ScenarioWith(crowd, events);
  const Diagnostic d = pavilion::testing::ExpectOneLoadError(Write(text), key_path, says);
  EXPECT_EQ(d.line, LineOf(text, marker));
}

// Confirms the load-time checks: a crowd is needed, the pool bounds the
// count, the spot must be free floor, the place must exist.
TEST(SpawnGroupEventTest, BadInputIsOneLineAtItsKey) {
  ExpectOneError("", "  - {at_s: 2, type: spawn_group, at: [3, 3], count: 4}\n", "at_s: 2",
                 "events[0].type", "needs a crowd");
  ExpectOneError(kCrowd, "  - {at_s: 2, type: spawn_group, at: [3, 3], count: 20}\n", "at_s: 2",
                 "events[0].count", "pool (12)");
  ExpectOneError(kCrowd, "  - {at_s: 2, type: spawn_group, at: [0.3, 0.2], count: 4}\n", "at_s: 2",
                 "events[0].at", "meets exhibit");
  ExpectOneError(kCrowd, "  - {at_s: 2, type: spawn_group, at: [8.0, 3.0], count: 4}\n", "at_s: 2",
                 "events[0].at", "meets outline");
  ExpectOneError(kCrowd, "  - {at_s: 2, type: spawn_group, place: atrium, count: 4}\n", "at_s: 2",
                 "events[0].place", "no place 'atrium'");
}

// A party of five at the lobby at 2 s: five bodies of the pool come onto the
// floor there, the record says so, and they are on the floor afterwards.
TEST(SpawnGroupEventTest, APartyWalksInAtAPlace) {
  const std::string path =
      Write(ScenarioWith(kCrowd, "  - {at_s: 2, type: spawn_group, place: lobby, count: 5}\n"));
  const Scenario s = LoadScenarioFile(path);
  const auto out = TestDir() / "out";
  const RunMetrics m = RunScenario(s, RunOptions{out.string(), false, 1}).metrics;
  ASSERT_TRUE(m.crowd);
  EXPECT_EQ(m.crowd->arrivals, 5);
  EXPECT_EQ(m.crowd->max_present, 5);
  std::ifstream events(out / "events.jsonl");
  int records = 0;
  for (std::string line; std::getline(events, line);) {
    const nlohmann::json e = nlohmann::json::parse(line);
    if (e.at("type") != "spawn_group") continue;
    ++records;
    EXPECT_DOUBLE_EQ(e.at("time_s").get<double>(), 2.0);
    EXPECT_EQ(e.at("count"), 5);
    EXPECT_EQ(e.at("spawned"), 5);
    EXPECT_EQ(e.at("at")[0], 4.0);
  }
  EXPECT_EQ(records, 1);
}

}  // namespace
}  // namespace pavilion::scenarios
