// CI's shortened runs of issue 14's navigation scenarios (the full-length runs
// over several seeds are navigation_acceptance_test): the chapter 6 stack —
// global plan, command queue, NF1 and elastic band, dynamic window — driving
// from the robot's own estimate and scans, judged against ground truth.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "scenarios/config/scenario.h"
#include "scenarios/run/scenario_runner.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

RunMetrics RunFor(const std::string& scenario, std::uint64_t seed, double duration_s,
                  const std::filesystem::path& out, int threads = 0,
                  std::vector<std::string> assignments = {}) {
  ScenarioOverrides overrides;
  overrides.seed = seed;
  overrides.duration_s = duration_s;
  overrides.assignments = std::move(assignments);
  const Scenario s = LoadScenarioFile(
      std::string(PAVILION_SOURCE_DIR) + "/scenarios/" + scenario + ".yaml", overrides);
  return RunScenario(s, RunOptions{out.string(), false, threads}).metrics;
}

int CountEvents(const std::filesystem::path& events, const std::string& type) {
  std::ifstream in(events);
  int n = 0;
  for (std::string line; std::getline(in, line);) {
    if (nlohmann::json::parse(line).value("type", "") == type) ++n;
  }
  return n;
}

std::string Slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Pygmalion's first errands through the office floor (§4.5.3): each completed,
// no collision, never lost, the events agreeing with the figures.
TEST(NavigationTour, OfficeErrandsShortRunCompletesEveryErrand) {
  const std::filesystem::path dir = pavilion::testing::TestDir() / "errands";
  const RunMetrics m = RunFor("office_errands", 1, 250.0, dir);
  const RobotMetrics& r = m.robots.front();
  ASSERT_TRUE(r.navigation);
  const nav::NavigationFigures& n = *r.navigation;
  EXPECT_GE(n.missions_completed, 3);
  EXPECT_EQ(n.missions_aborted_total(), 0);
  EXPECT_EQ(r.collisions, 0);
  ASSERT_TRUE(r.localization);
  EXPECT_EQ(r.localization->lost_situations, 0);
  EXPECT_EQ(CountEvents(dir / "events.jsonl", "mission_completed"), n.missions_completed);
  EXPECT_EQ(CountEvents(dir / "events.jsonl", "mission_started"), n.missions_started);
  // At Computer 2000's 0.4 m/s limit an errand of 15-35 m takes about a minute.
  EXPECT_GT(n.mission_time_s / n.missions_completed, 20.0);
  EXPECT_LT(n.mission_time_s / n.missions_completed, 120.0);
  EXPECT_GT(n.min_clearance_m, 0.0);
}

// Robox among 30 walkers in the Expo hall: stations reached, nothing the laser
// sees or the map's ghost points guard is hit. A walker's shove can lose the
// EKF; the mission is then aborted as lost and the robot relocalizes (seeds
// 1-4 complete 3-6 missions in these 240 s), but no mission ends blocked,
// timed out or unreachable.
TEST(NavigationTour, ExpoTourShortRunReachesStationsWithoutHittingExhibits) {
  const std::filesystem::path dir = pavilion::testing::TestDir() / "expo";
  const RunMetrics m = RunFor("expo_tour", 1, 240.0, dir);
  const RobotMetrics& r = m.robots.front();
  ASSERT_TRUE(r.navigation);
  EXPECT_GE(r.navigation->missions_completed, 3);
  const auto aborted = [&](nav::AbortReason reason) {
    return r.navigation->missions_aborted[static_cast<std::size_t>(reason)];
  };
  EXPECT_EQ(aborted(nav::AbortReason::kBlocked), 0);
  EXPECT_EQ(aborted(nav::AbortReason::kTimeout), 0);
  EXPECT_EQ(aborted(nav::AbortReason::kUnreachable), 0);
  EXPECT_EQ(r.collisions_by_class.of(CollisionClass::kVisible), 0);
  EXPECT_EQ(r.collisions_by_class.of(CollisionClass::kInvisible), 0);
  EXPECT_LT(r.navigation->longest_blocked_s, 60.0);
  // 10 Hz while it drives: 240 s less the dwells and the final approaches.
  EXPECT_GT(r.navigation->dwa_cycles, 1200);
  EXPECT_LE(r.navigation->dwa_cycles, 2400);
}

// The OMPL initial planner seeds its samplers from the scenario's seed, robot
// and plan number and stops by iterations: the same bytes for 1 and 2 threads.
TEST(NavigationTour, OmplInitialPlannerIsByteIdenticalForAnyThreadCount) {
  const std::filesystem::path dir = pavilion::testing::TestDir() / "ompl";
  const std::vector<std::string> ompl = {"robots.0.mission.initial_planner=ompl_rrt_connect"};
  const RunMetrics one = RunFor("expo_tour", 1, 60.0, dir / "t1", 1, ompl);
  RunFor("expo_tour", 1, 60.0, dir / "t2", 2, ompl);
  ASSERT_TRUE(one.robots.front().navigation);
  EXPECT_GE(one.robots.front().navigation->missions_started, 1);
  for (const char* f : {"events.jsonl", "trajectories.csv", "localization.csv", "metrics.json"}) {
    EXPECT_EQ(Slurp(dir / "t1" / f), Slurp(dir / "t2" / f)) << f;
  }
  EXPECT_NE(Slurp(dir / "t1" / "events.jsonl").find("mission_started"), std::string::npos);
}

}  // namespace
}  // namespace pavilion::scenarios
