// A robot's mission: block as the scenario reader sees it (mission_reader.h).
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "scenarios/config/input_error.h"
#include "scenarios/config/scenario.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

bool Contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

std::vector<Diagnostic> LoadErrors(const std::string& path) {
  try {
    LoadScenarioFile(path);
  } catch (const InputError& e) {
    return e.diagnostics();
  }
  ADD_FAILURE() << "LoadScenarioFile accepted " << path;
  return {};
}

// The rush's rest nodes (mission.rest_among) load, and a name the map does
// not have is a file:line:key error.
TEST(ScenarioLoaderTest, ReadsRestNodesAndReportsAnUnknownOne) {
  const std::string source = std::string(PAVILION_SOURCE_DIR) + "/scenarios/expo_rush.yaml";
  const Scenario rush = LoadScenarioFile(source);
  ASSERT_TRUE(rush.robots[3].mission.has_value());
  const std::vector<std::string>& rest = rush.robots[3].mission->navigation.rest_among;
  ASSERT_EQ(rest.size(), 10u);
  EXPECT_EQ(rest.front(), "dock_01");
  std::ifstream in(source);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string docks = "rest_among: &docks [dock_01,";
  const std::size_t at = text.find(docks);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, docks.size(), "rest_among: &docks [dock_11,");
  text.replace(text.find("world: expo_hall"), 16,
               "world: " + std::string(PAVILION_SOURCE_DIR) + "/worlds/expo_hall/world.yaml");
  const std::string path = WriteFile(TestDir(), "rush.yaml", text);
  const std::vector<Diagnostic> all = LoadErrors(path);
  // Once per robot, each at the anchor's line (the others alias its list).
  ASSERT_EQ(all.size(), rush.robots.size());
  EXPECT_EQ(all[0].key_path, "robots[0].mission.rest_among[0]");
  EXPECT_EQ(all[19].key_path, "robots[19].mission.rest_among[0]");
  EXPECT_GT(all[0].line, 0);
  EXPECT_EQ(all[19].line, all[0].line);
  EXPECT_TRUE(Contains(all[0].message, "unknown station 'dock_11'")) << all[0].message;
}

// hold_belief_at_goal: on unless the mission turns it off (the thesis'
// pause of localization at the goal); a value that is no boolean is a
// file:line:key error.
// office_errands.yaml's text, its world named by its full path (for a copy elsewhere).
std::string OfficeErrandsText() {
  std::ifstream in(std::string(PAVILION_SOURCE_DIR) + "/scenarios/office_errands.yaml");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t world = text.find("world: office_floor");
  if (world == std::string::npos) return "";
  return text.replace(
      world, 19, "world: " + std::string(PAVILION_SOURCE_DIR) + "/worlds/office_floor/world.yaml");
}

TEST(ScenarioLoaderTest, ReadsWhetherTheBeliefIsHeldAtTheGoal) {
  const std::string source = std::string(PAVILION_SOURCE_DIR) + "/scenarios/office_errands.yaml";
  ASSERT_TRUE(LoadScenarioFile(source).robots[0].mission.has_value());
  EXPECT_TRUE(LoadScenarioFile(source).robots[0].mission->navigation.hold_belief_at_goal);
  const std::string text = OfficeErrandsText();
  const std::string key = "    mission:\n";
  ASSERT_NE(text.find(key), std::string::npos);
  std::string off = text;
  off.insert(off.find(key) + key.size(), "      hold_belief_at_goal: false\n");
  const Scenario paused = LoadScenarioFile(WriteFile(TestDir(), "paused.yaml", off));
  EXPECT_FALSE(paused.robots[0].mission->navigation.hold_belief_at_goal);
  std::string bad = text;
  bad.insert(bad.find(key) + key.size(), "      hold_belief_at_goal: sometimes\n");
  const std::vector<Diagnostic> all = LoadErrors(WriteFile(TestDir(), "bad.yaml", bad));
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].key_path, "robots[0].mission.hold_belief_at_goal");
  EXPECT_GT(all[0].line, 0);
}

// localization.slip_sigma: 3 cm, 3 cm and 1° unless given; [0, 0, 0] is the
// thesis' filter; a negative sigma is an error at its line.
TEST(ScenarioLoaderTest, ReadsTheSlipSigma) {
  const std::string text = OfficeErrandsText();
  const std::string key = "    localization:\n";
  ASSERT_NE(text.find(key), std::string::npos);
  const Scenario plain = LoadScenarioFile(WriteFile(TestDir(), "plain.yaml", text));
  EXPECT_EQ(plain.robots[0].localization.slip_sigma, Eigen::Vector3d(0.03, 0.03, 0.0175));
  std::string thesis = text;
  thesis.insert(thesis.find(key) + key.size(), "      slip_sigma: [0, 0, 0]\n");
  const Scenario single = LoadScenarioFile(WriteFile(TestDir(), "thesis.yaml", thesis));
  EXPECT_TRUE(single.robots[0].localization.slip_sigma.isZero(0.0));
  std::string bad = text;
  bad.insert(bad.find(key) + key.size(), "      slip_sigma: [0.03, -0.01, 0.02]\n");
  const std::vector<Diagnostic> all = LoadErrors(WriteFile(TestDir(), "bad_slip.yaml", bad));
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].key_path, "robots[0].localization.slip_sigma");
  EXPECT_GT(all[0].line, 0);
}

// uncertain_slow_m / uncertain_stop_m / uncertain_reach_m set the hold for an
// uncertain belief (UncertaintyOptions); slow at or above stop is an error at
// its line.
TEST(ScenarioLoaderTest, ReadsTheHoldForAnUncertainBelief) {
  const std::string text = OfficeErrandsText();
  const std::string key = "    mission:\n";
  ASSERT_NE(text.find(key), std::string::npos);
  const nav::UncertaintyOptions defaults;
  const Scenario plain = LoadScenarioFile(WriteFile(TestDir(), "plain.yaml", text));
  EXPECT_EQ(plain.robots[0].mission->navigation.uncertainty.stop_m, defaults.stop_m);
  std::string set = text;
  set.insert(set.find(key) + key.size(),
             "      uncertain_slow_m: 0.2\n      uncertain_stop_m: 0.5\n"
             "      uncertain_reach_m: 2\n      uncertain_hold_max_s: 30\n"
             "      uncertain_crawl_mps: 0.1\n");
  const Scenario read = LoadScenarioFile(WriteFile(TestDir(), "set.yaml", set));
  EXPECT_EQ(read.robots[0].mission->navigation.uncertainty.slow_m, 0.2);
  EXPECT_EQ(read.robots[0].mission->navigation.uncertainty.stop_m, 0.5);
  EXPECT_EQ(read.robots[0].mission->navigation.uncertainty.reach_m, 2.0);
  EXPECT_EQ(read.robots[0].mission->navigation.uncertainty.hold_max_s, 30.0);
  EXPECT_EQ(read.robots[0].mission->navigation.uncertainty.crawl_mps, 0.1);
  std::string bad = text;
  bad.insert(bad.find(key) + key.size(), "      uncertain_slow_m: 0.4\n");
  const std::vector<Diagnostic> all = LoadErrors(WriteFile(TestDir(), "bad_hold.yaml", bad));
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0].key_path, "robots[0].mission.uncertain_slow_m");
  EXPECT_GT(all[0].line, 0);
}

}  // namespace
}  // namespace pavilion::scenarios
