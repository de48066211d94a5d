// Issue 15 in CI (shortened runs of the shipped fleet scenarios; the hour-long
// acceptance over five seeds is fleet_acceptance_test, `make acceptance`):
// ten coordinated Robox keep clear of each other and of the walls, never share
// a station, exchange a few bytes per tick, and produce the same bytes for 1,
// 2 and 8 threads; with the coordination off nothing is exchanged.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "tests/support/run_pavilion.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// TestDir() starts the test's folder afresh: call it once per test.
json RunFleet(const fs::path& base, const std::string& scenario, const std::string& tag,
              double duration_s, int threads, int seed = 1) {
  const fs::path out = base / tag;
  const pavilion::testing::PavilionResult r = pavilion::testing::RunPavilion(
      {"run", std::string(PAVILION_SOURCE_DIR) + "/scenarios/" + scenario + ".yaml", "--out",
       out.string(), "--duration", std::to_string(duration_s), "--threads", std::to_string(threads),
       "--seed", std::to_string(seed)},
      base);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return json::parse(pavilion::testing::ReadTextFile(out / "metrics.json"));
}

TEST(Fleet, TenCoordinatedRobotsKeepClearAndNeverShareAStation) {
  const json m = RunFleet(pavilion::testing::TestDir(), "expo_tours", "tours", 150.0, 2);
  const json& fleet = m.at("fleet");
  const json& c = fleet.at("coordination");
  EXPECT_TRUE(c.at("coordination").get<bool>());
  EXPECT_EQ(c.at("robots").get<int>(), 10);
  EXPECT_EQ(fleet.at("collisions").at("robot").get<int>(), 0);
  EXPECT_EQ(fleet.at("collisions").at("wall_or_exhibit_visible").get<int>(), 0);
  // Goal coordination never sends two robots to one station, and passage
  // claims keep a passer out of a station another robot holds.
  EXPECT_EQ(c.at("station_conflicts").get<int>(), 0);
  EXPECT_GE(fleet.at("missions_completed").get<int>(), 10);
  EXPECT_LE(c.at("longest_blocked_s").get<double>(), 60.0);
  // A message per robot and dynamic-window cycle of a few dozen bytes (§6.3.5:
  // "a matter of a few bytes"), the server forwarding the changed ones.
  EXPECT_GT(c.at("bytes_up").get<int>(), 0);
  EXPECT_LT(c.at("bytes_per_robot_s").get<double>(), 10000.0);
}

TEST(Fleet, SameBytesForOneTwoAndEightThreads) {
  const fs::path base = pavilion::testing::TestDir();
  RunFleet(base, "expo_tours", "threads_1", 20.0, 1);
  for (const int threads : {2, 8}) {
    const std::string tag = "threads_" + std::to_string(threads);
    RunFleet(base, "expo_tours", tag, 20.0, threads);
    for (const char* name :
         {"metrics.json", "events.jsonl", "trajectories.csv", "localization.csv"}) {
      SCOPED_TRACE(std::string(name) + ", " + std::to_string(threads) + " threads");
      const std::string a = pavilion::testing::ReadTextFile(base / "threads_1" / name);
      EXPECT_FALSE(a.empty());
      EXPECT_TRUE(a == pavilion::testing::ReadTextFile(base / tag / name));
    }
  }
}

// Seed 2 runs into the §6.5 situation within a minute and a half: robox_06
// at 68.1 s. (It was robox_04 at 41.7 s until a robot stood for its belief's
// uncertainty after a bump, 2026-12-07; robox_02 at 20.9 s, in a chain of five
// robots beside the end of a glass panel, until the robots' outline took their
// wheels' tyres for their spheres, 2026-12-07; seed 4 met it until robots held
// their belief at the goal, 2026-12-07, and seed 5 until the wheels' set-points
// were ramped, 2026-12-05.) The overlap deadlock is detected, resolved, and
// pictured at the moment of its detection. Every deadlock detected at least the
// resolution bound (30 s) before the run's end is resolved; one detected later
// may still be under way when the run ends.
TEST(Fleet, WithTheCoordinationOffNothingIsExchangedAndTheFirstDeadlockIsPictured) {
  const fs::path base = pavilion::testing::TestDir();
  constexpr double kDurationS = 100.0;
  constexpr double kResolutionBoundS = 30.0;
  const json m = RunFleet(base, "expo_tours_fallback", "fallback", kDurationS, 2, 2);
  const json& c = m.at("fleet").at("coordination");
  EXPECT_FALSE(c.at("coordination").get<bool>());
  EXPECT_EQ(c.at("bytes_up").get<int>(), 0);
  EXPECT_EQ(c.at("bytes_down").get<int>(), 0);
  EXPECT_EQ(c.at("fleet_replans").get<int>(), 0);
  EXPECT_GE(c.at("deadlocks_detected").get<int>(), 1);
  EXPECT_LE(c.at("longest_deadlock_s").get<double>(), kResolutionBoundS);
  std::map<std::string, double> open_since;  // robot: detected at, not yet resolved
  int judged = 0;
  std::istringstream events(pavilion::testing::ReadTextFile(base / "fallback" / "events.jsonl"));
  for (std::string line; std::getline(events, line);) {
    const json e = json::parse(line);
    const std::string type = e.at("type").get<std::string>();
    const double t = e.at("time_s").get<double>();
    if (type == "deadlock_detected") {
      open_since[e.at("robot").get<std::string>()] = t;
      if (t <= kDurationS - kResolutionBoundS) ++judged;
    } else if (type == "deadlock_resolved") {
      open_since.erase(e.at("robot").get<std::string>());
    }
  }
  EXPECT_GE(judged, 1);
  for (const auto& [robot, since_s] : open_since) {
    EXPECT_GT(since_s, kDurationS - kResolutionBoundS) << robot << " unresolved since " << since_s;
  }
  const std::string png =
      pavilion::testing::ReadTextFile(base / "fallback" / "snapshots" / "deadlock_first.png");
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  const std::string report = pavilion::testing::ReadTextFile(base / "fallback" / "report.html");
  EXPECT_NE(report.find("The first overlap deadlock"), std::string::npos);
  EXPECT_NE(report.find("snapshots/deadlock_first.png"), std::string::npos);
}

}  // namespace
}  // namespace pavilion::scenarios
