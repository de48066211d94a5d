// Issue 17/18: a random kidnap in the expo hall. A localizing robot wanders;
// at 4 s it is lifted to a random free pose drawn from the seed. The kidnap
// is in events.jsonl with a true move of at least min_distance_m and a turn
// of at least min_turn_deg into free space, the EKF's consequences follow
// (the truth-judged loss), metrics.json has the relocalization section and
// localization.csv the state and hypothesis columns, and the same seed gives
// the same events.jsonl for one and two threads.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "nav/reactive/swept_polygon.h"
#include "scenarios/config/data_paths.h"
#include "scenarios/config/robot_loader.h"
#include "scenarios/config/scenario.h"
#include "scenarios/config/world_loader.h"
#include "scenarios/events/kidnap_event.h"
#include "tests/support/run_pavilion.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

constexpr double kMinDistanceM = 2.0;
constexpr double kMinTurnDeg = 30.0;
constexpr double kMarginM = 0.1;

// The setup of parallel_determinism_test's robots in expo_hall, wandering.
const char* const kScenario =
    "kind: scenario\n"
    "name: kidnap_once\n"
    "world: expo_hall\n"
    "seed: 7\n"
    "duration_s: 12\n"
    "robots:\n"
    "  - {id: r1, model: robox, pose: [0.0, 3.0, 0.0], localization: {},\n"
    "     wander: {laser: front}}\n"
    "events:\n"
    "  - {at_s: 4, type: kidnap, robot: r1, min_distance_m: 2.0, min_turn_deg: 30,\n"
    "     margin_m: 0.1}\n"
    "outputs:\n"
    "  scan_log: false\n";

fs::path RunWithThreads(const fs::path& dir, int threads) {
  const fs::path out = dir / ("threads_" + std::to_string(threads));
  const pavilion::testing::PavilionResult r =
      pavilion::testing::RunPavilion({"run", (dir / "scenario.yaml").string(), "--out",
                                      out.string(), "--threads", std::to_string(threads)},
                                     dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return out;
}

std::vector<Json> Events(const fs::path& out) {
  std::vector<Json> events;
  for (const std::string& line :
       pavilion::testing::SplitLines(pavilion::testing::ReadTextFile(out / "events.jsonl"))) {
    if (!line.empty()) events.push_back(Json::parse(line));
  }
  return events;
}

// Confirms the kidnap's record, its free destination, its consequences and
// its determinism over thread counts.
TEST(KidnapScenarioTest, RandomKidnapMovesFarIntoFreeSpaceDeterministically) {
  const fs::path dir = pavilion::testing::TestDir();
  pavilion::testing::WriteFile(dir, "scenario.yaml", kScenario);
  const fs::path one = RunWithThreads(dir, 1);
  std::vector<Json> kidnaps, lost;
  for (const Json& e : Events(one)) {
    if (e.at("type") == "kidnap") kidnaps.push_back(e);
    if (e.at("type") == "lost") lost.push_back(e);
  }
  ASSERT_EQ(kidnaps.size(), 1u);
  const Json& k = kidnaps[0];
  EXPECT_EQ(k.at("robot"), "r1");
  EXPECT_DOUBLE_EQ(k.at("time_s").get<double>(), 4.0);
  const std::vector<double> before = k.at("before").get<std::vector<double>>();
  const std::vector<double> after = k.at("after").get<std::vector<double>>();
  const double moved_m = std::hypot(after[0] - before[0], after[1] - before[1]);
  EXPECT_GE(moved_m, kMinDistanceM);
  EXPECT_NEAR(k.at("distance_m").get<double>(), moved_m, 1e-5);
  EXPECT_GE(std::abs(k.at("turn_deg").get<double>()), kMinTurnDeg);
  // The destination is free of the hall's static geometry (the only robot, no
  // bodies) with the margin, and inside the floor.
  const Scenario s = LoadScenarioFile((dir / "scenario.yaml").string());
  const sim::RobotDescription& model = s.robots[0].config.description;
  const RobotFootprint footprint{nav::Circumradius(model.footprint_m) + kMarginM,
                                 model.chassis_base_z_m,
                                 model.chassis_base_z_m + model.chassis_height_m};
  EXPECT_EQ(StaticObstacleAt(s.world, footprint, {after[0], after[1], after[2]}), "");
  // The EKF was not told: the truth says it is lost right after.
  ASSERT_FALSE(lost.empty());
  EXPECT_GT(lost[0].at("time_s").get<double>(), 4.0);
  EXPECT_GT(lost[0].at("position_error_m").get<double>(), 1.0);
  const Json metrics = Json::parse(pavilion::testing::ReadTextFile(one / "metrics.json"));
  const Json& relocalization = metrics.at("robots").at("r1").at("relocalization");
  EXPECT_EQ(relocalization.at("kidnaps").get<int>(), 1);
  EXPECT_GT(relocalization.at("per_kidnap").at(0).at("motion_s").get<double>(), 1.0);
  EXPECT_EQ(metrics.at("fleet").at("relocalization").at("kidnaps").get<int>(), 1);
  const std::string csv = pavilion::testing::ReadTextFile(one / "localization.csv");
  EXPECT_NE(csv.substr(0, csv.find('\n')).find(",lost,state,hypotheses"), std::string::npos);
  EXPECT_NE(csv.find(",localized,1,0\n"), std::string::npos);  // hypotheses, matched_edges
  // Same seed, same bytes, for one and two threads.
  const fs::path two = RunWithThreads(dir, 2);
  EXPECT_EQ(pavilion::testing::ReadTextFile(one / "events.jsonl"),
            pavilion::testing::ReadTextFile(two / "events.jsonl"));
  EXPECT_EQ(pavilion::testing::ReadTextFile(one / "metrics.json"),
            pavilion::testing::ReadTextFile(two / "metrics.json"));
}

}  // namespace
}  // namespace pavilion::scenarios
