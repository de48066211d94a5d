// Issue 14's navigation acceptance scenes in the Expo.02 hall (thesis
// chapter 6): a Robox localizing at 2 Hz on a mission to one station, pushed
// off its path mid-way, and one sent behind a U-shaped crowd (§6.5). The
// scenes are written into the test's folder; the figures come from the run's
// typed metrics, events.jsonl and trajectories.csv (ground truth).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scenarios/config/scenario.h"
#include "scenarios/run/scenario_runner.h"
#include "tests/support/csv_column.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

namespace fs = std::filesystem;

// One Robox on a one-station mission; `extra` adds top-level blocks (bodies,
// events) before the robot.
std::string Scene(
    const std::string& name, double duration_s, const std::string& start_pose,
    const std::string& station, const std::string& extra,
    const std::string& localization = "{rate_hz: 2, initial_sigma: [0.01, 0.01, 0.01]}") {
  return "kind: scenario\n"
         "name: " +
         name +
         "\n"
         "world: expo_hall\n"
         "seed: 1\n"
         "duration_s: " +
         std::to_string(duration_s) +
         "\n"
         "physics: {rate_hz: 200}\n"
         "outputs: {trajectory_rate_hz: 10, scan_log: false}\n"
         "materials:\n"
         "  visitor: {friction: 0.6, color: [0.85, 0.55, 0.35]}\n" +
         extra +
         "robots:\n"
         "  - id: robox_1\n"
         "    model: robox\n"
         "    pose: " +
         start_pose +
         "\n"
         "    localization: " +
         localization +
         "\n"
         "    mission: {stations: [" +
         station + "], timeout_s: 60}\n";
}

struct SceneRun {
  RobotMetrics robot;
  std::vector<nlohmann::json> events;
  fs::path dir;
};

SceneRun RunScene(const fs::path& dir, const std::string& name, const std::string& yaml) {
  const std::string file = pavilion::testing::WriteFile(dir, name + ".yaml", yaml);
  const Scenario s = LoadScenarioFile(file);
  SceneRun run;
  run.dir = dir / name;
  const RunMetrics metrics = RunScenario(s, RunOptions{run.dir.string(), false}).metrics;
  EXPECT_EQ(metrics.robots.size(), 1u);
  if (!metrics.robots.empty()) run.robot = metrics.robots.front();
  std::ifstream in(run.dir / "events.jsonl");
  std::string line;
  while (std::getline(in, line)) run.events.push_back(nlohmann::json::parse(line));
  return run;
}

std::vector<nlohmann::json> EventsOfType(const SceneRun& run, const std::string& type) {
  std::vector<nlohmann::json> found;
  for (const nlohmann::json& e : run.events) {
    if (e.value("type", "") == type) found.push_back(e);
  }
  return found;
}

// Largest true displacement (m) normal to the robot's true heading at `from_s`
// within `window_s` after it: how far a push moved it sideways.
double LateralDisplacementM(const fs::path& run_dir, double from_s, double window_s) {
  const fs::path csv = run_dir / "trajectories.csv";
  const std::vector<double> t = pavilion::testing::ReadCsvColumn(csv, "time_s");
  const std::vector<double> x = pavilion::testing::ReadCsvColumn(csv, "true_x_m");
  const std::vector<double> y = pavilion::testing::ReadCsvColumn(csv, "true_y_m");
  const std::vector<double> th = pavilion::testing::ReadCsvColumn(csv, "true_theta_rad");
  const auto at = std::lower_bound(t.begin(), t.end(), from_s - 1e-9);
  if (at == t.end()) return 0.0;
  const std::size_t k0 = static_cast<std::size_t>(at - t.begin());
  double largest_m = 0.0;
  for (std::size_t k = k0; k < t.size() && t[k] <= from_s + window_s; ++k) {
    const double lateral_m = -(x[k] - x[k0]) * std::sin(th[k0]) + (y[k] - y[k0]) * std::cos(th[k0]);
    largest_m = std::max(largest_m, std::abs(lateral_m));
  }
  return largest_m;
}

// Pushed scene: from (3.0, -0.6) heading +x along the bottom corridor to
// station_10 (12.1, 1.5), 9.4 m away (about 20 s unpushed). At 7 s the robot
// is at about (6.9, -0.23), heading 0, with 1.7 m of open floor on its left up
// to bench_2; the push is to its left (+y).
constexpr double kPushAtS = 7.0;
// The largest sideways push the 2 Hz EKF survives (N s): 180 N s moves the
// robot 0.10 m, the validation gate then rejects every line and the estimator
// declares itself lost (repeated gate failures; since the wheels' set-points
// ramp at the window's acceleration, 2026-12-05, so does 170 N s, and 140 N s
// moves it less than 8 cm); from 270 N s the 115 kg
// robot also tips onto its base and jams. Issue 14's 1 m push is out of reach
// of an impulse: the robot is carried instead (the test after this one).
constexpr double kPushNs = 160.0;
constexpr double kMinPushDisplacementM = 0.08;
// Bound on the true final error at the station after the push, m.
constexpr double kPushedGoalErrorM = 0.08;

// No wall, exhibit or invisible object touched, and the run ends on
// station_10 (the truth, not the belief).
void ExpectUntouchedAtStation10(const SceneRun& run) {
  EXPECT_EQ(run.robot.collisions_by_class.of(CollisionClass::kVisible), 0);
  EXPECT_EQ(run.robot.collisions_by_class.of(CollisionClass::kInvisible), 0);
  const std::vector<double> x =
      pavilion::testing::ReadCsvColumn(run.dir / "trajectories.csv", "true_x_m");
  const std::vector<double> y =
      pavilion::testing::ReadCsvColumn(run.dir / "trajectories.csv", "true_y_m");
  ASSERT_FALSE(x.empty());
  EXPECT_NEAR(x.back(), 12.1, kPushedGoalErrorM);
  EXPECT_NEAR(y.back(), 1.5, kPushedGoalErrorM);
}

// A push to the side mid-way (unseen by the odometry: the wheels skid) does
// not lose the localization, and the mission completes without touching a wall
// or exhibit. No replan: the band absorbs a 9 cm shove.
TEST(NavigationScenarios, PushedOffItsPathCompletes) {
  const fs::path dir = pavilion::testing::TestDir();
  char push[160];
  std::snprintf(push, sizeof push,
                "events:\n  - {at_s: %g, type: push, body: robox_1, impulse: [0, %g]}\n", kPushAtS,
                kPushNs);
  const SceneRun run =
      RunScene(dir, "pushed", Scene("nav_pushed", 40.0, "[3.0, -0.6, 0.0]", "station_10", push));
  ASSERT_TRUE(run.robot.navigation);
  const nav::NavigationFigures& n = *run.robot.navigation;
  const double lateral_m = LateralDisplacementM(run.dir, kPushAtS, 2.0);
  RecordProperty("push_lateral_displacement_m", std::to_string(lateral_m));
  EXPECT_GE(lateral_m, kMinPushDisplacementM);
  EXPECT_EQ(n.missions_completed, 1);
  EXPECT_EQ(n.missions_aborted_total(), 0);
  EXPECT_TRUE(EventsOfType(run, "lost").empty());
  // Ends on the station (the truth, not the belief). The EKF never absorbs the
  // whole push: the lines that would correct it stay outside the gate and the
  // estimate keeps 0.059 m of the 0.09 m (0.004 m unpushed), with a 1 cm sigma.
  ExpectUntouchedAtStation10(run);
}

// Issue 14's 1 m push: the robot is carried 1 m to its left mid-way (lifted:
// a push that moves a 115 kg Robox on its motors 1 m tips it first, see
// kPushNs), which neither its encoders nor its bumpers feel. Its localization
// (global, chapter 5) notices, relocalizes, and the held mission is replanned
// from where the robot finds itself and completed, without touching anything.
TEST(NavigationScenarios, CarriedOneMetreOffItsPathReplansAndCompletes) {
  const fs::path dir = pavilion::testing::TestDir();
  char kidnap[200];
  std::snprintf(kidnap, sizeof kidnap,
                "events:\n  - {at_s: %g, type: kidnap, robot: robox_1, pose: [6.9, 0.77, 0.0]}\n",
                kPushAtS);
  const SceneRun run =
      RunScene(dir, "carried",
               Scene("nav_carried", 50.0, "[3.0, -0.6, 0.0]", "station_10", kidnap,
                     "{method: global, rate_hz: 2, initial_sigma: [0.01, 0.01, 0.01]}"));
  const std::vector<nlohmann::json> kidnaps = EventsOfType(run, "kidnap");
  ASSERT_EQ(kidnaps.size(), 1u);
  EXPECT_NEAR(kidnaps[0].value("distance_m", 0.0), 1.0, 0.02);
  ASSERT_TRUE(run.robot.navigation);
  const nav::NavigationFigures& n = *run.robot.navigation;
  EXPECT_EQ(n.missions_completed, 1);
  EXPECT_EQ(n.missions_aborted_total(), 0);
  EXPECT_GE(n.replans, 1);
  for (const nlohmann::json& e : EventsOfType(run, "relocalized")) {
    EXPECT_TRUE(e.value("correct", false)) << e.dump();
  }
  ExpectUntouchedAtStation10(run);
}

// U scene (§6.5): station_07 (10.54, 3.23) faces exhibit 07. Eight standing
// people (r 0.22 m) form a U, 2.5 m wide between the arms' centres, whose
// bottom (x 7.39, 4 people at y 1.98..4.48) is 3.15 m in front of the station
// and whose arms (x 6.59 and 5.79) open west towards the robot at
// (4.74, 3.23) heading +x: the straight line to the station runs into the U.
// North of the U the arena (y >= 5.3) leaves 0.6 m, so the way is south.
constexpr double kUBottomX = 7.39;
constexpr double kUArmStepM = 0.8;
constexpr double kULowY = 1.98;
constexpr double kUHighY = 4.48;
constexpr double kUMaxMissionS = 60.0;

std::string UShapedCrowd() {
  std::vector<std::pair<double, double>> people;
  for (int k = 0; k < 4; ++k) people.emplace_back(kUBottomX, kULowY + k * (kUHighY - kULowY) / 3.0);
  for (int k = 1; k <= 2; ++k) {
    people.emplace_back(kUBottomX - k * kUArmStepM, kULowY);
    people.emplace_back(kUBottomX - k * kUArmStepM, kUHighY);
  }
  std::string text = "bodies:\n";
  for (std::size_t i = 0; i < people.size(); ++i) {
    char line[200];
    std::snprintf(line, sizeof line,
                  "  - {id: person_%zu, pose: [%.3f, %.3f, 0], shape: {type: cylinder, radius: "
                  "0.22, height: 1.7}, mass_kg: 70, material: visitor}\n",
                  i + 1, people[i].first, people[i].second);
    text += line;
  }
  return text;
}

// The robot leaves the U trap and reaches the station behind it within 60 s
// without touching anyone or anything.
TEST(NavigationScenarios, UShapedCrowdReachedWithoutContact) {
  const fs::path dir = pavilion::testing::TestDir();
  const SceneRun run =
      RunScene(dir, "u_crowd",
               Scene("nav_u_crowd", 70.0, "[4.74, 3.23, 0.0]", "station_07", UShapedCrowd()));
  ASSERT_TRUE(run.robot.navigation);
  const nav::NavigationFigures& n = *run.robot.navigation;
  EXPECT_EQ(n.missions_completed, 1);
  EXPECT_EQ(n.missions_aborted_total(), 0);
  const std::vector<nlohmann::json> done = EventsOfType(run, "mission_completed");
  ASSERT_EQ(done.size(), 1u);
  const double duration_s = done.front().at("duration_s").get<double>();
  RecordProperty("mission_duration_s", std::to_string(duration_s));
  EXPECT_LE(duration_s, kUMaxMissionS);
  // The U forced a detour: the mission's path is well beyond the 5.8 m line.
  EXPECT_GT(done.front().at("path_length_m").get<double>(), 8.0);
  EXPECT_EQ(run.robot.collisions_by_class.of(CollisionClass::kVisitor), 0);
  EXPECT_EQ(run.robot.collisions_by_class.of(CollisionClass::kVisible), 0);
  EXPECT_EQ(run.robot.collisions_by_class.of(CollisionClass::kInvisible), 0);
}

}  // namespace
}  // namespace pavilion::scenarios

namespace pavilion::scenarios {
namespace {

// A walker that touches a standing robot stands for the pause, then walks on
// when its walk leads away (issue 14's walkers, until the crowd model): one
// that stood as long as it touched pinned a Robox to a wall for the rest of a
// tour. The walker starts 3 mm from the robot's front flat.
TEST(NavigationScenarios, AWalkerTouchingARobotWalksOn) {
  const fs::path dir = pavilion::testing::TestDir();
  const std::string yaml =
      "kind: scenario\n"
      "name: walker_touching\n"
      "world: expo_hall\n"
      "seed: 3\n"
      "duration_s: 40\n"
      "outputs: {trajectory_rate_hz: 10, scan_log: false}\n"
      "materials:\n"
      "  visitor: {friction: 0.6, color: [0.85, 0.55, 0.35]}\n"
      "bodies:\n"
      "  - {id: walker_1, pose: [3.563, -0.6, 0], shape: {type: cylinder, radius: 0.22, "
      "height: 1.7}, mass_kg: 70, material: visitor,\n"
      "     motion: {type: random_walk, speed_mps: 0.8, mean_leg_s: 5}}\n"
      "robots:\n"
      "  - {id: robox_1, model: robox, pose: [3.0, -0.6, 0.0]}\n";
  const SceneRun run = RunScene(dir, "walker_touching", yaml);
  std::ifstream in(run.dir / "trajectories.csv");
  std::string line;
  std::getline(in, line);  // header: time_s,id,true_x_m,true_y_m,...
  double farthest_m = 0.0;
  int rows = 0;
  while (std::getline(in, line)) {
    if (line.find(",walker_1,") == std::string::npos) continue;
    double t = 0.0, x = 0.0, y = 0.0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf,walker_1,%lf,%lf", &t, &x, &y), 3) << line;
    farthest_m = std::max(farthest_m, std::hypot(x - 3.563, y + 0.6));
    ++rows;
  }
  EXPECT_GT(rows, 100);
  RecordProperty("walker_farthest_m", std::to_string(farthest_m));
  EXPECT_GT(farthest_m, 2.0);  // it walked on (standing for good: 0)
}

}  // namespace
}  // namespace pavilion::scenarios
