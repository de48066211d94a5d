// The hall benchmark (docs/benchmarks.md): the shipped world, robot and
// scenarios hold the layout the peers ran, and ten wandering robots move,
// stay in the hall, keep clear of the exhibits and repeat bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "scenarios/config/data_paths.h"
#include "scenarios/config/robot_loader.h"
#include "scenarios/config/scenario.h"
#include "scenarios/config/world_loader.h"
#include "scenarios/run/scenario_runner.h"
#include "tests/support/run_pavilion.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

namespace fs = std::filesystem;

const fs::path kDir = fs::path(PAVILION_SOURCE_DIR) / "scenarios" / "hall_bench";
constexpr double kHalfChassisM = 0.15;  // the 0.30 m square chassis
constexpr double kBoxHalfM = 0.5;       // 1 m exhibits
// Contact penetration Bullet allows between touching solids (m).
constexpr double kPenetrationM = 0.01;

nlohmann::json Layout() {
  std::ifstream in(kDir / "hall_layout.json");
  return nlohmann::json::parse(in);
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A robot's samples from trajectories.csv: (x, y) over time.
std::map<std::string, std::vector<Eigen::Vector2d>> Tracks(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line;
  std::getline(in, line);  // header: time_s,id,true_x_m,true_y_m,...
  std::map<std::string, std::vector<Eigen::Vector2d>> tracks;
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string time, id, x, y;
    std::getline(row, time, ',');
    std::getline(row, id, ',');
    std::getline(row, x, ',');
    std::getline(row, y, ',');
    tracks[id].emplace_back(std::stod(x), std::stod(y));
  }
  return tracks;
}

// The world, robot and four scenarios carry hall_layout.json's numbers exactly,
// and the benchmark's durations, robot and laser.
TEST(HallBenchTest, ShippedFilesHoldTheLayout) {
  const nlohmann::json layout = Layout();
  const sim::WorldDescription world = LoadWorldFile(ResolveWorldPath("hall"));
  ASSERT_EQ(world.walls.size(), layout["walls"].size());
  for (std::size_t k = 0; k < world.walls.size(); ++k) {
    const sim::Wall& w = world.walls[k];
    const auto& l = layout["walls"][k];  // centre x, centre y, size x, size y
    ASSERT_EQ(w.points_m.size(), 2u);
    const Eigen::Vector2d lo = w.points_m[0].cwiseMin(w.points_m[1]);
    const Eigen::Vector2d hi = w.points_m[0].cwiseMax(w.points_m[1]);
    const bool along_x = l[2].get<double>() >= l[3].get<double>();
    const Eigen::Vector2d half(along_x ? 0.5 * (hi - lo).x() : 0.5 * w.thickness_m,
                               along_x ? 0.5 * w.thickness_m : 0.5 * (hi - lo).y());
    EXPECT_NEAR(0.5 * (lo + hi).x(), l[0].get<double>(), 1e-12) << w.id;
    EXPECT_NEAR(0.5 * (lo + hi).y(), l[1].get<double>(), 1e-12) << w.id;
    EXPECT_NEAR(2.0 * half.x(), l[2].get<double>(), 1e-12) << w.id;
    EXPECT_NEAR(2.0 * half.y(), l[3].get<double>(), 1e-12) << w.id;
    EXPECT_EQ(w.height_m, 0.5);
  }
  ASSERT_EQ(world.boxes.size(), 15u);
  for (std::size_t k = 0; k < world.boxes.size(); ++k) {
    const sim::Box& b = world.boxes[k];
    EXPECT_EQ(b.pose.x_m, layout["boxes"][k][0].get<double>());
    EXPECT_EQ(b.pose.y_m, layout["boxes"][k][1].get<double>());
    EXPECT_EQ(b.pose.theta_rad, 0.0);
    EXPECT_EQ(b.size_m, Eigen::Vector3d(1.0, 1.0, 0.5));
  }
  for (const auto& [name, m] : world.materials) EXPECT_EQ(m.friction, 0.8) << name;

  const sim::RobotConfig robot = LoadRobotFile(ResolveRobotPath("hall_bot"));
  const sim::RobotDescription& d = robot.description;
  EXPECT_NEAR(d.chassis_mass_kg, 5.0, 1e-12);
  EXPECT_EQ(d.left_wheel.radius_m, 0.05);
  EXPECT_EQ(d.left_wheel.mass_kg, 0.5);
  EXPECT_EQ(d.left_wheel.position_m.y(), 0.12);
  EXPECT_EQ(d.right_wheel.position_m.y(), -0.12);
  EXPECT_NEAR(d.chassis_height_m, 0.20, 1e-12);
  ASSERT_EQ(robot.lasers.size(), 1u);
  const sim::LaserMount& laser = robot.lasers[0];
  EXPECT_EQ(laser.robot_from_sensor, (core::Pose2{0.10, 0.0, 0.0}));
  EXPECT_NEAR(laser.z_m, 0.15, 1e-12);
  EXPECT_NEAR(laser.options.fov_rad, std::numbers::pi, 1e-12);
  EXPECT_EQ(laser.options.beams, 361);
  EXPECT_EQ(laser.options.max_range_m, 8.0);
  EXPECT_EQ(laser.options.scan_rate_hz, 10.0);
  EXPECT_FALSE(laser.options.noise);
  EXPECT_FALSE(laser.options.effects);

  const std::map<int, double> durations = {{1, 600}, {10, 600}, {100, 60}, {1000, 5}};
  for (const auto& [n, duration] : durations) {
    SCOPED_TRACE(n);
    const Scenario s =
        LoadScenarioFile((kDir / ("hall_bench_" + std::to_string(n) + ".yaml")).string());
    EXPECT_EQ(s.duration_s, duration);
    EXPECT_EQ(s.world.name, "hall");
    EXPECT_EQ(s.outputs.scan_log, ScanLogMode::kOff);
    const auto& poses = layout["robots"][std::to_string(n)];
    ASSERT_EQ(s.robots.size(), static_cast<std::size_t>(n));
    for (int k = 0; k < n; ++k) {
      const RobotEntry& r = s.robots[k];
      EXPECT_EQ(r.model, "hall_bot");
      ASSERT_TRUE(r.wander.has_value());
      EXPECT_TRUE(r.drive.empty());
      EXPECT_EQ(r.pose.x_m, poses[k][0].get<double>());
      EXPECT_EQ(r.pose.y_m, poses[k][1].get<double>());
      EXPECT_NEAR(r.pose.theta_rad, poses[k][2].get<double>() * std::numbers::pi / 180.0, 1e-15);
    }
  }
}

// The benchmark robot drives straight and turns as commanded: 0.4 m/s for 5 s
// covers 2 m without veering, and a turn on
// the spot at 0.5 rad/s keeps that rate and its place.
TEST(HallBenchTest, HallBotDrivesStraightAndTurns) {
  const fs::path dir = pavilion::testing::TestDir();
  const std::string path =
      pavilion::testing::WriteFile(dir, "drive.yaml",
                                   "kind: scenario\n"
                                   "name: hall_bot_drive\n"
                                   "world: hall\n"
                                   "duration_s: 12\n"
                                   "outputs: {trajectory_rate_hz: 50, scan_log: false}\n"
                                   "robots:\n"
                                   "  - id: bot\n"
                                   "    model: hall_bot\n"
                                   "    pose: [-3, -3, 0]\n"
                                   "    drive:\n"
                                   "      - {at_s: 0, speed_mps: 0.4, turn_radps: 0}\n"
                                   "      - {at_s: 5, speed_mps: 0, turn_radps: 0}\n"
                                   "      - {at_s: 6, speed_mps: 0, turn_radps: 0.5}\n");
  RunScenario(LoadScenarioFile(path), RunOptions{(dir / "out").string(), false});
  std::ifstream in(dir / "out" / "trajectories.csv");
  std::string line;
  std::getline(in, line);
  std::map<int, core::Pose2> at;  // by time in 20 ms steps
  while (std::getline(in, line)) {
    std::stringstream row(line);
    std::string f[5];
    for (auto& field : f) std::getline(row, field, ',');
    at[static_cast<int>(std::lround(std::stod(f[0]) * 50.0))] = {std::stod(f[2]), std::stod(f[3]),
                                                                 std::stod(f[4])};
  }
  const core::Pose2 stopped = at.at(300);  // 6 s: after the straight drive and its braking
  // The 0.2 s ramps up and down cancel: 2 m.
  EXPECT_NEAR(stopped.x_m - -3.0, 0.4 * 5.0, 0.01);
  EXPECT_NEAR(stopped.y_m, -3.0, 0.005);
  EXPECT_NEAR(stopped.theta_rad, 0.0, 0.005);
  // From 8 to 12 s the turn is at full rate: 2 rad.
  const core::Pose2 a = at.at(400), b = at.at(600);
  EXPECT_NEAR(core::NormalizeAngle(b.theta_rad - a.theta_rad), core::NormalizeAngle(2.0), 0.03);
  EXPECT_LT((b.translation() - stopped.translation()).norm(), 0.02);
}

struct HallRun {
  fs::path out;
  nlohmann::json metrics;
};

HallRun RunHall10(const std::string& name, double duration_s, std::uint64_t seed,
                  double trajectory_rate_hz) {
  ScenarioOverrides overrides;
  overrides.seed = seed;
  overrides.duration_s = duration_s;
  overrides.assignments = {"outputs.trajectory_rate_hz=" + std::to_string(trajectory_rate_hz)};
  const Scenario s = LoadScenarioFile((kDir / "hall_bench_10.yaml").string(), overrides);
  const fs::path out = pavilion::testing::TestDir() / name;
  RunScenario(s, RunOptions{out.string(), false});
  std::ifstream in(out / "metrics.json");
  return {out, nlohmann::json::parse(in)};
}

// Ten robots wander for 30 s: each drives a few metres, every sampled pose
// (20 Hz) keeps the chassis inside the hall's walls and out of every exhibit
// (no robot drives through a box), and none collides with a wall or exhibit —
// the wander stops at 0.3 m and turns away from anything within 1 m ahead.
TEST(HallBenchTest, TenRobotsWanderInsideTheHallClearOfTheExhibits) {
  const HallRun run = RunHall10("wander", 30.0, 1, 20.0);
  const nlohmann::json layout = Layout();
  const auto tracks = Tracks(run.out / "trajectories.csv");
  ASSERT_EQ(tracks.size(), 10u);
  // The hall's inner faces: walls centred at x = +-10, y = +-8, 0.2 m thick.
  const double inner_x = 10.0 - 0.1, inner_y = 8.0 - 0.1;
  for (const auto& [id, track] : tracks) {
    SCOPED_TRACE(id);
    const double distance = run.metrics["robots"][id]["distance_m"].get<double>();
    std::printf("[ info ] %s drove %.2f m, %d collisions, %d scans\n", id.c_str(), distance,
                run.metrics["robots"][id]["collisions"].get<int>(),
                run.metrics["robots"][id]["scans"].get<int>());
    EXPECT_GT(distance, 2.0);  // cruising at 0.4 m/s when free, 0.05 m/s when avoiding
    EXPECT_EQ(run.metrics["robots"][id]["scans"].get<int>(), 300);  // 10 Hz for 30 s
    EXPECT_GT((track.back() - track.front()).norm(), 0.5);
    for (const Eigen::Vector2d& p : track) {
      ASSERT_LT(std::abs(p.x()), inner_x - kHalfChassisM + kPenetrationM) << p.transpose();
      ASSERT_LT(std::abs(p.y()), inner_y - kHalfChassisM + kPenetrationM) << p.transpose();
      for (const auto& box : layout["boxes"]) {
        const Eigen::Vector2d c(box[0].get<double>(), box[1].get<double>());
        // Distance from the robot's centre to the box; the chassis holds a disc
        // of its half width around the centre.
        const Eigen::Vector2d gap =
            ((p - c).cwiseAbs() - Eigen::Vector2d::Constant(kBoxHalfM)).cwiseMax(0.0);
        ASSERT_GT(gap.norm(), kHalfChassisM - kPenetrationM) << p.transpose() << " box " << c;
      }
    }
  }
  // Collisions with the hall (robots may still bump into each other: the
  // laser sees 180 degrees ahead only, as the peers').
  std::ifstream events(run.out / "events.jsonl");
  std::string line;
  int static_hits = 0;
  while (std::getline(events, line)) {
    const nlohmann::json e = nlohmann::json::parse(line);
    if (e["type"] != "collision") continue;
    for (const char* side : {"a", "b"}) {
      const std::string element = e[side].get<std::string>();
      if (element.starts_with("wall_") || element.starts_with("exhibit_")) ++static_hits;
    }
  }
  EXPECT_EQ(static_hits, 0);
}

// The same seed gives byte-identical outputs (every file but
// performance.json), run after run of the `pavilion` binary. Two runs inside
// one process are not compared: Bullet's dynamic bounding-volume tree orders
// nodes by their heap addresses when it re-balances (btDbvt::optimizeIncremental),
// so with many robots the order of contacts, and the last digits of the
// results, can depend on what the process allocated before.
TEST(HallBenchTest, SameSeedSameOutputs) {
  const fs::path dir = pavilion::testing::TestDir();
  for (const char* name : {"a", "b"}) {
    const auto r = pavilion::testing::RunPavilion(
        {"run", (kDir / "hall_bench_10.yaml").string(), "--out", (dir / name).string(), "--seed",
         "5", "--duration", "8", "--set", "outputs.trajectory_rate_hz=10"},
        dir);
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  for (const char* file : {"metrics.json", "events.jsonl", "trajectories.csv"}) {
    const std::string ta = ReadText(dir / "a" / file), tb = ReadText(dir / "b" / file);
    EXPECT_FALSE(ta.empty()) << file;
    EXPECT_TRUE(ta == tb) << file << " differs between two runs with the same seed";
  }
}

// `pavilion bench hall` runs the scenario the requested number of times and
// reports each run; the world's ray counter agrees with N x 361 x 10 rays per
// simulated second. Robot counts without a layout are usage errors.
TEST(HallBenchTest, BenchCommandReportsEveryRun) {
  const fs::path dir = pavilion::testing::TestDir();
  const fs::path json = dir / "bench.json";
  // 0.95 s: the sweeps starting at 0, 0.1, ..., 0.9 s.
  const auto r = pavilion::testing::RunPavilion({"bench", "hall", "--robots", "10", "--runs", "2",
                                                 "--duration", "0.95", "--json", json.string()},
                                                dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("run 2"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("median"), std::string::npos) << r.out;
  std::ifstream in(json);
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["robots"], 10);
  EXPECT_EQ(j["duration_s"], 0.95);
  ASSERT_EQ(j["runs"].size(), 2u);
  for (const auto& run : j["runs"]) {
    EXPECT_NEAR(run["sim_s"].get<double>(), 0.95, 1e-9);
    EXPECT_EQ(run["rays"].get<std::int64_t>(), 10 * 361 * 10);  // ten scans a robot
    EXPECT_GT(run["real_time_factor"].get<double>(), 0.0);
    EXPECT_NEAR(run["rays_per_s"].get<double>(),
                10 * 361 * 10 * run["real_time_factor"].get<double>(), 1e-6);
    EXPECT_GT(run["peak_rss_mb"].get<double>(), 0.0);
    EXPECT_GT(run["startup_s"].get<double>(), 0.0);
  }
  EXPECT_GE(j["best"]["real_time_factor"].get<double>(),
            j["median"]["real_time_factor"].get<double>());

  const auto bad = pavilion::testing::RunPavilion({"bench", "hall", "--robots", "7"}, dir);
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
}

}  // namespace
}  // namespace pavilion::scenarios
