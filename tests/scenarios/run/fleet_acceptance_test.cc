// Issue 15's acceptance runs (make acceptance; not in CI): expo_tours and
// expo_tours_fallback over five seeds for their full hour, the fallback also
// with the deadlock resolution switched off. The bounds are the issue's; the
// figures per seed are in docs/benchmarks.md.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "scenarios/config/scenario.h"
#include "scenarios/run/scenario_runner.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

RunMetrics RunFull(const std::string& scenario, std::uint64_t seed, bool resolve = true) {
  ScenarioOverrides overrides;
  overrides.seed = seed;
  if (!resolve) overrides.assignments.push_back("fleet.deadlock_resolution=off");
  const Scenario s = LoadScenarioFile(
      std::string(PAVILION_SOURCE_DIR) + "/scenarios/" + scenario + ".yaml", overrides);
  const std::filesystem::path out =
      pavilion::testing::TestDir() /
      (scenario + "_" + std::to_string(seed) + (resolve ? "" : "_off"));
  return RunScenario(s, RunOptions{out.string(), false}).metrics;
}

class ExpoToursAcceptance : public ::testing::TestWithParam<std::uint64_t> {};

// Zero robot-robot and robot-wall collisions, >= 95 % of started missions
// completed, >= 10 missions per robot-hour, never blocked (nor standing with a
// mission) over 60 s, never two robots within 1 m of the same station node.
TEST_P(ExpoToursAcceptance, TenRobotsGiveToursForAnHour) {
  const RunMetrics m = RunFull("expo_tours", GetParam());
  ASSERT_TRUE(m.fleet);
  int started = 0, completed = 0, robots = 0;
  for (const RobotMetrics& r : m.robots) {
    ASSERT_TRUE(r.navigation);
    ++robots;
    started += r.navigation->missions_started;
    completed += r.navigation->missions_completed;
    EXPECT_EQ(r.collisions_by_class.of(CollisionClass::kRobot), 0) << r.id;
    EXPECT_EQ(r.collisions_by_class.of(CollisionClass::kVisible), 0) << r.id;
    EXPECT_LE(r.navigation->longest_blocked_s, 60.0) << r.id;
    // A blocked episode ends when its mission is aborted (after 45 s), and a
    // robot can be blocked again at once: the stand across aborts is the
    // criterion's plain sense (seed 4 at 545db6e: 1,005 s beside a lost
    // robot, every episode under 60 s).
    EXPECT_LE(r.navigation->longest_still_s, 60.0) << r.id;
  }
  // The mission each robot is on when the hour ends cannot complete.
  EXPECT_GE(completed, 0.95 * (started - robots));
  EXPECT_GE(completed / (m.sim_duration_s / 3600.0 * robots), 10.0);
  EXPECT_EQ(m.fleet->proximity.station_conflicts, 0);
}
INSTANTIATE_TEST_SUITE_P(FiveSeeds, ExpoToursAcceptance, ::testing::Values(1, 2, 3, 4, 5));

class FallbackAcceptance : public ::testing::TestWithParam<std::uint64_t> {};

// At least one overlap deadlock per seed, every one resolved within 30 s; the
// same seed with the resolution off leaves a robot stuck (still with a mission
// for over 120 s).
TEST_P(FallbackAcceptance, OverlapDeadlocksAreResolved) {
  const RunMetrics on = RunFull("expo_tours_fallback", GetParam());
  int detected = 0, resolved = 0, unresolved = 0;
  double longest_s = 0.0;
  for (const RobotMetrics& r : on.robots) {
    detected += r.navigation->deadlocks_detected;
    resolved += r.navigation->deadlocks_resolved;
    unresolved += r.navigation->deadlocks_unresolved;
    longest_s = std::max(longest_s, r.navigation->longest_deadlock_s);
  }
  EXPECT_GE(detected, 1);
  EXPECT_EQ(unresolved, 0);
  EXPECT_LE(longest_s, 30.0);
  const RunMetrics off = RunFull("expo_tours_fallback", GetParam(), false);
  double longest_still_s = 0.0;
  for (const RobotMetrics& r : off.robots) {
    longest_still_s = std::max(longest_still_s, r.navigation->longest_still_s);
  }
  EXPECT_GT(longest_still_s, 120.0);
}
INSTANTIATE_TEST_SUITE_P(FiveSeeds, FallbackAcceptance, ::testing::Values(1, 2, 3, 4, 5));

}  // namespace
}  // namespace pavilion::scenarios
