// `pavilion run` as a test (issue 17): the expectation table, exit 3 when an
// expectation fails, --junit, and SIGTERM ending a run with valid files.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/run_pavilion.h"
#include "tests/support/test_files.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using pavilion::testing::Contains;
using pavilion::testing::ReadTextFile;
using pavilion::testing::RunPavilion;
using pavilion::testing::SplitLines;
using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

const std::string kWorld = pavilion::testing::WalledRoomWorld("expect_room");

// A Robox driving 0.3 m/s for 3 s towards the east wall, 4 m away: about
// 0.9 m travelled (less the acceleration), no collision.
std::string Scenario(const fs::path& dir, const std::string& expect, double duration_s = 4) {
  WriteFile(dir, "world.yaml", kWorld);
  return WriteFile(dir, "scenario.yaml",
                   "kind: scenario\n"
                   "name: expect_cli\n"
                   "duration_s: " +
                       std::to_string(duration_s) +
                       "\n"
                       "world: world.yaml\n"
                       "robots:\n"
                       "  - {id: r1, model: robox, pose: [0, 0, 0],\n"
                       "     drive: [{at_s: 0, speed_mps: 0.3, turn_radps: 0.0},\n"
                       "             {at_s: 3, speed_mps: 0.0, turn_radps: 0.0}]}\n"
                       "expect:\n" +
                       expect);
}

TEST(ExpectCliTest, PassingExpectationsExitZero) {
  const fs::path dir = TestDir();
  const std::string file = Scenario(dir,
                                    "  - robots.r1.distance_m > 0.7\n"
                                    "  - robots.r1.distance_m < 1.0\n"
                                    "  - never: {event: collision}\n");
  const auto r = RunPavilion({"run", file, "--out", (dir / "out").string()}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Contains(r.out, "3 of 3 expectations passed")) << r.out;
  const auto json = nlohmann::json::parse(ReadTextFile(dir / "out" / "expectations.json"));
  EXPECT_EQ(json.at("passed"), true);
  EXPECT_EQ(json.at("results").size(), 3u);
}

TEST(ExpectCliTest, AFailureExitsThreeAndJUnitNamesIt) {
  const fs::path dir = TestDir();
  const std::string file = Scenario(dir,
                                    "  - robots.r1.distance_m > 0.7\n"
                                    "  - robots.r1.distance_m < 0.5\n"
                                    "  - robots.r1.localization.position_rmse_m < 0.05\n");
  const fs::path junit = dir / "junit.xml";
  const auto r =
      RunPavilion({"run", file, "--out", (dir / "out").string(), "--junit", junit.string()}, dir);
  EXPECT_EQ(r.exit_code, 3) << r.err;
  EXPECT_TRUE(Contains(r.out, "fail     robots.r1.distance_m < 0.5")) << r.out;
  // r1 does not localize: the expectation on its localization is missing.
  EXPECT_TRUE(Contains(r.out, "missing  robots.r1.localization.position_rmse_m")) << r.out;
  EXPECT_TRUE(Contains(r.out, "1 of 3 expectations passed")) << r.out;
  const std::string xml = ReadTextFile(junit);
  EXPECT_TRUE(Contains(xml, "tests=\"3\" failures=\"2\" errors=\"0\"")) << xml;
  // 0.3 m/s for 3 s: 0.9 m (the robot reaches its speed within a few centimetres).
  EXPECT_TRUE(Contains(xml,
                       "<testcase classname=\"expect_cli\" name=\"robots.r1.distance_m &lt; "
                       "0.5\" time=\"0\">\n      <failure message=\"measured 0.9"))
      << xml;
  EXPECT_TRUE(Contains(xml, "expected &lt; 0.5\"")) << xml;
  EXPECT_TRUE(Contains(xml, "missing: robots.r1.localization.position_rmse_m")) << xml;
}

TEST(ExpectCliTest, BadExpectationIsBadInput) {
  const fs::path dir = TestDir();
  const std::string file = Scenario(dir, "  - robots.r1.distanse_m > 0.7\n");
  const auto r = RunPavilion({"run", file, "--out", (dir / "out").string()}, dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(Contains(r.err, "scenario.yaml:10: expect[0]: robots.r1.distanse_m: unknown metric"))
      << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "metrics.json"));
}

// Events past a shorter --duration are dropped with a note; the file's own
// duration still bounds them (a later one is an error).
TEST(ExpectCliTest, EventsPastAShorterDurationAreSkippedWithANote) {
  const fs::path dir = TestDir();
  const std::string file = Scenario(dir,
                                    "  - robots.r1.distance_m > 0\n"
                                    "events:\n"
                                    "  - {at_s: 1, type: push, body: r1, impulse: [10, 0]}\n"
                                    "  - {at_s: 3, type: push, body: r1, impulse: [10, 0]}\n");
  const auto r =
      RunPavilion({"run", file, "--out", (dir / "out").string(), "--duration", "2"}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Contains(r.err, "1 event(s) due at or after 2 s skipped")) << r.err;
  const auto metrics = nlohmann::json::parse(ReadTextFile(dir / "out" / "metrics.json"));
  EXPECT_EQ(metrics.at("events").at("push"), 1);
}

// SIGTERM mid-run: exit 143, every file valid, metrics.json and run_finished
// saying the run was interrupted.
TEST(ExpectCliTest, SigtermEndsTheRunCleanly) {
  const fs::path dir = TestDir();
  const std::string file = Scenario(dir, "  - robots.r1.distance_m > 0\n", 3600);
  const fs::path out = dir / "out";
  std::vector<std::string> args{PAVILION_BINARY, "run", file, "--out", out.string()};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, (dir / "stdout.txt").c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&actions, 2, (dir / "stderr.txt").c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ), 0);
  posix_spawn_file_actions_destroy(&actions);
  // Wait until the run is stepping (its logs are open), then let it run a while.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline && !fs::exists(out / "events.jsonl")) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  ASSERT_EQ(kill(pid, SIGTERM), 0);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 143) << ReadTextFile(dir / "stderr.txt");
  const auto metrics = nlohmann::json::parse(ReadTextFile(out / "metrics.json"));
  EXPECT_EQ(metrics.at("interrupted"), true);
  EXPECT_LT(metrics.at("sim_duration_s").get<double>(), 3600.0);
  const std::vector<std::string> events = SplitLines(ReadTextFile(out / "events.jsonl"));
  ASSERT_FALSE(events.empty());
  for (const std::string& line : events) EXPECT_TRUE(nlohmann::json::accept(line)) << line;
  const auto last = nlohmann::json::parse(events.back());
  EXPECT_EQ(last.at("type"), "run_finished");
  EXPECT_EQ(last.at("interrupted"), true);
  EXPECT_EQ(last.at("signal"), SIGTERM);
  // Every trajectory row is whole: as many fields as the header.
  const std::vector<std::string> rows = SplitLines(ReadTextFile(out / "trajectories.csv"));
  ASSERT_GT(rows.size(), 2u);
  const auto fields = [](const std::string& s) { return std::count(s.begin(), s.end(), ','); };
  for (const std::string& row : rows) EXPECT_EQ(fields(row), fields(rows[0]));
  EXPECT_TRUE(fs::exists(out / "report.html"));
  EXPECT_TRUE(fs::exists(out / "expectations.json"));
}

// A robot that drives off the floor's edge falls: the run ends there with a
// robot_left_floor event, exit 4, a failed "reaches its end" expectation and
// every file valid up to then (issue 21: a kidnapped Robox drove out of the
// hall's entrance and on through the void for the rest of the day).
TEST(ExpectCliTest, ARobotLeavingTheFloorEndsTheRunWithExitFour) {
  const fs::path dir = TestDir();
  // A floor 4 m across with nothing on it; the Robox drives east at 0.5 m/s
  // from its middle and reaches the edge, 2 m away, after about 4 s.
  WriteFile(dir, "world.yaml",
            "kind: world\n"
            "name: bare_floor\n"
            "materials:\n"
            "  concrete: {friction: 0.8}\n"
            "floor: {min: [-2, -2], max: [2, 2], material: concrete}\n");
  const std::string file = WriteFile(dir, "scenario.yaml",
                                     "kind: scenario\n"
                                     "name: off_the_edge\n"
                                     "duration_s: 20\n"
                                     "world: world.yaml\n"
                                     "robots:\n"
                                     "  - {id: r1, model: robox, pose: [0, 0, 0],\n"
                                     "     drive: [{at_s: 0, speed_mps: 0.5, turn_radps: 0.0}]}\n"
                                     "expect:\n"
                                     "  - robots.r1.distance_m > 1\n");
  const fs::path out = dir / "out";
  const auto r = RunPavilion({"run", file, "--out", out.string()}, dir);
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_TRUE(Contains(r.err, "the run ended early: robot 'r1' left the floor at (2.")) << r.err;
  EXPECT_TRUE(Contains(r.out, "fail     the run reaches its end")) << r.out;
  const auto metrics = nlohmann::json::parse(ReadTextFile(out / "metrics.json"));
  const double ended_s = metrics.at("sim_duration_s").get<double>();
  EXPECT_GT(ended_s, 3.5);
  EXPECT_LT(ended_s, 6.0);
  EXPECT_TRUE(Contains(metrics.at("ended_early").get<std::string>(), "robot 'r1' left the floor"));
  const std::vector<std::string> events = SplitLines(ReadTextFile(out / "events.jsonl"));
  ASSERT_GE(events.size(), 2u);
  const auto left = nlohmann::json::parse(events[events.size() - 2]);
  EXPECT_EQ(left.at("type"), "robot_left_floor");
  EXPECT_EQ(left.at("robot"), "r1");
  EXPECT_GT(left.at("pose")[0].get<double>(), 2.0);
  const auto last = nlohmann::json::parse(events.back());
  EXPECT_EQ(last.at("type"), "run_finished");
  EXPECT_TRUE(last.contains("ended_early"));
  const auto expectations = nlohmann::json::parse(ReadTextFile(out / "expectations.json"));
  EXPECT_EQ(expectations.at("passed"), false);
  EXPECT_TRUE(Contains(ReadTextFile(out / "report.html"), "The run ended early: robot"));
}

}  // namespace
