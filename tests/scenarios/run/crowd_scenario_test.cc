// The crowd scenarios end to end: expo_crowd's ten minutes (every §6.5
// behaviour happens, nobody passes through anybody or anything by more than
// 5 cm) and the demo (its Robox's odometry error is what its push explains,
// no longer 7.8 m of bulldozing by velocity-driven walkers).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "scenarios/config/scenario.h"
#include "scenarios/run/scenario_runner.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

RunMetrics RunShipped(const std::string& name, std::optional<double> duration_s = std::nullopt) {
  ScenarioOverrides overrides;
  overrides.duration_s = duration_s;
  overrides.assignments = {"outputs.scan_log=false"};
  const Scenario s =
      LoadScenarioFile(PAVILION_SOURCE_DIR "/scenarios/" + name + ".yaml", overrides);
  const std::filesystem::path out = pavilion::testing::TestDir() / name;
  return RunScenario(s, RunOptions{out.string(), false, 1}).metrics;
}

// Ten minutes of expo_crowd: about 100 present, every behaviour begun at
// least once and pushes delivered, no interpenetration beyond 5 cm
// (people with people, walls and exhibits, robots).
TEST(CrowdScenario, ExpoCrowdTenMinutes) {
  const RunMetrics m = RunShipped("expo_crowd");
  ASSERT_TRUE(m.crowd);
  const CrowdFigures& c = *m.crowd;
  EXPECT_NEAR(c.mean_present, 100.0, 20.0);
  EXPECT_GT(c.arrivals, 30);  // 400 an hour for 10 minutes: 67 expected
  EXPECT_GT(c.departures, 30);
  EXPECT_LE(c.max_overlap_m, 0.05);
  EXPECT_GT(c.pushes, 0);
  for (const auto& [behaviour, episodes] : c.episodes) EXPECT_GT(episodes, 0) << behaviour;
  ASSERT_EQ(m.robots.size(), 1u);
  ASSERT_TRUE(m.robots[0].social);
  EXPECT_GT(m.robots[0].social->intimate_intrusions, 0);  // crowded, followed, blocked, pushed
  const CollisionCounts& k = m.robots[0].collisions_by_class;
  EXPECT_GT(k.visitor_into_robot, 0);
}

// The demo: sixty ordinary visitors walk around the Robox; its final
// odometry error is what the 40 N s push at 30 s explains (centimetres).
TEST(CrowdScenario, DemoRoboxIsNotBulldozed) {
  const RunMetrics m = RunShipped("expo_visitors");
  ASSERT_TRUE(m.crowd);
  EXPECT_NEAR(m.crowd->mean_present, 60.0, 5.0);
  ASSERT_EQ(m.robots.size(), 1u);
  EXPECT_LT(m.robots[0].odometry_final_position_error_m, 0.1);
  EXPECT_EQ(m.robots[0].collisions_by_class.visitor_into_robot, 0);
}

}  // namespace
}  // namespace pavilion::scenarios
