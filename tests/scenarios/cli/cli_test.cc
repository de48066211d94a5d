// Runs the real `pavilion` binary: exit codes, messages, and the outputs of `run`.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/run_pavilion.h"
#include "tests/support/test_files.h"

namespace {

namespace fs = std::filesystem;
using pavilion::testing::Contains;
using pavilion::testing::RunPavilion;
using Result = pavilion::testing::PavilionResult;
const auto& ReadFile = pavilion::testing::ReadTextFile;
const auto& Lines = pavilion::testing::SplitLines;
using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

// A 12 m square room of four walls with three crates and a spawn pen.
const std::string kWorld =
    "kind: world\n"
    "name: cli_room\n"
    "materials:\n"
    "  concrete: {friction: 0.8}\n"
    "  floor: {friction: 0.7}\n"
    "  wood: {friction: 0.6, restitution: 0.1}\n"
    "floor: {min: [-7, -7], max: [7, 7], material: floor}\n"
    "walls:\n"
    "  - {id: wall_s, points: [[-6, -6], [6, -6]], thickness: 0.2, height: 2, material: concrete}\n"
    "  - {id: wall_e, points: [[6, -6], [6, 6]], thickness: 0.2, height: 2, material: concrete}\n"
    "  - {id: wall_n, points: [[6, 6], [-6, 6]], thickness: 0.2, height: 2, material: concrete}\n"
    "  - {id: wall_w, points: [[-6, 6], [-6, -6]], thickness: 0.2, height: 2, material: concrete}\n"
    "boxes:\n"
    "  - {id: crate_1, pose: [2, 2, 0.3], size: [1, 0.6, 0.8], material: wood}\n"
    "  - {id: crate_2, pose: [-2, 3, 0], size: [0.8, 0.8, 1.0], material: wood}\n"
    "  - {id: crate_3, pose: [3, -3, 0.7], size: [1.2, 0.5, 0.9], material: wood}\n"
    "places:\n"
    "  pen: {area: [[-5, -5], [1, -5], [1, 1], [-5, 1]]}\n";

// Eight random walkers in the pen, a cart driven into crate_1, a barrel pushed
// into wall_e and a walker pushed mid-run: collisions early and often.
const std::string kBusyScenario =
    "kind: scenario\n"
    "name: busy_room\n"
    "seed: 1\n"
    "duration_s: 5\n"
    "world: world.yaml\n"
    "materials:\n"
    "  skin: {friction: 0.5}\n"
    "outputs: {trajectory_rate_hz: 20, image_width_px: 300}\n"
    "bodies:\n"
    "  - id: cart\n"
    "    shape: {type: box, size: [0.6, 0.4, 0.5]}\n"
    "    mass_kg: 15\n"
    "    material: wood\n"
    "    pose: [0, 2.2, 0]\n"
    "    motion: {type: scripted, segments: [{duration_s: 5, velocity: [1.0, 0]}]}\n"
    "  - id: barrel\n"
    "    shape: {type: cylinder, radius: 0.3, height: 0.9}\n"
    "    mass_kg: 10\n"
    "    material: wood\n"
    "    pose: [4.5, 0, 0]\n"
    "groups:\n"
    "  - id: walker\n"
    "    count: 8\n"
    "    shape: {type: cylinder, radius: 0.25, height: 1.7}\n"
    "    mass_kg: 70\n"
    "    material: skin\n"
    "    area: pen\n"
    "    motion: {type: random_walk, speed_mps: 1.0, mean_leg_s: 1.0}\n"
    "robots:\n"
    "  - id: robox\n"
    "    model: robox\n"
    "    pose: [-4.5, 4.5, 0]\n"
    "    encoder_noise: true\n"
    "    drive: [{at_s: 0, speed_mps: 0.5, turn_radps: 0.3}, {at_s: 3, left: 0, right: 0}]\n"
    "events:\n"
    "  - {at_s: 0.5, type: push, body: barrel, impulse: [50, 0]}\n"
    "  - {at_s: 2.0, type: push, body: walker_003, impulse: [50, 20]}\n"
    "  - {at_s: 3.5, type: push, body: robox, impulse: [0, 60]}\n";

// Confirms that `version` exits 0 and names the program.
TEST(CliTest, VersionPrintsVersion) {
  const Result r = RunPavilion({"version"}, TestDir());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(r.out.rfind("pavilion ", 0), 0u) << r.out;
}

// Confirms that every subcommand's --help exits 0 and shows that subcommand's example.
TEST(CliTest, HelpOfEverySubcommandHasExample) {
  const fs::path dir = TestDir();
  const std::map<std::vector<std::string>, std::string> cases = {
      {{"run", "--help"}, "pavilion run "},
      {{"validate", "--help"}, "pavilion validate "},
      {{"world", "render", "--help"}, "pavilion world render "},
      {{"world", "info", "--help"}, "pavilion world info "},
      {{"scan", "--help"}, "pavilion scan "},
      {{"calibrate", "--help"}, "pavilion calibrate "},
      {{"extract", "--help"}, "pavilion extract "},
      {{"--help"}, "pavilion run "},
  };
  for (const auto& [args, example] : cases) {
    SCOPED_TRACE(args.front() + " " + args.back());
    const Result r = RunPavilion(args, dir);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(Contains(r.out, "Example"));
    EXPECT_TRUE(Contains(r.out, example));
  }
}

// Confirms that `scan` writes one CSV row per reading of each laser (and the
// picture), with ground truth, and that a malformed pose is a one-line error.
TEST(CliTest, ScanWritesEveryReadingWithGroundTruth) {
  const fs::path dir = TestDir();
  WriteFile(dir, "world.yaml", kWorld);
  const Result r =
      RunPavilion({"scan", (dir / "world.yaml").string(), "robox", "--pose", "0,0,0.5", "--out",
                   (dir / "scan.csv").string(), "--png", (dir / "scan.png").string(), "--no-noise"},
                  dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::vector<std::string> lines = Lines(ReadFile(dir / "scan.csv"));
  ASSERT_EQ(lines.size(), 1u + 2 * 361);  // header, two LMS 200
  EXPECT_EQ(lines[0].rfind("sensor,index,bearing_rad,", 0), 0u);
  int walls = 0;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    std::vector<std::string> cells;
    std::stringstream in(lines[i]);
    for (std::string cell; std::getline(in, cell, ',');) cells.push_back(cell);
    ASSERT_GE(cells.size(), 9u) << lines[i];
    if (cells[5] == "1") {  // valid: without noise the range is the true range (1 mm steps)
      EXPECT_NEAR(std::stod(cells[4]), std::stod(cells[7]), 0.0006) << lines[i];
    }
    walls += cells[8].rfind("wall_", 0) == 0;
  }
  EXPECT_GT(walls, 300);
  EXPECT_TRUE(fs::exists(dir / "scan.png"));

  const Result bad = RunPavilion({"scan", (dir / "world.yaml").string(), "robox", "--pose", "0,0",
                                  "--out", (dir / "bad.csv").string()},
                                 dir);
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_EQ(Lines(bad.err).size(), 1u) << bad.err;
  EXPECT_TRUE(Contains(bad.err, "--pose"));
}

// Confirms that `validate` lists every problem as `file:line: key.path: message` and exits 1.
TEST(CliTest, ValidateReportsEveryProblemOfABadWorld) {
  const fs::path dir = TestDir();
  std::string bad = kWorld;
  bad.replace(bad.find("thickness: 0.2"), 14, "thickness: -1");
  bad.replace(bad.find("material: wood}"), 15, "material: oak}");
  const std::string bad_path = WriteFile(dir, "bad.yaml", bad);
  const std::string good_path = WriteFile(dir, "good.yaml", kWorld);
  const Result r = RunPavilion({"validate", good_path, bad_path}, dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.out, good_path + ": ok\n");
  const std::vector<std::string> lines = Lines(r.err);
  ASSERT_EQ(lines.size(), 3u) << r.err;
  EXPECT_EQ(lines[0], bad_path + ":9: walls[0].thickness: must be in [0.001, 1000], got -1");
  EXPECT_EQ(lines[1], bad_path + ":14: boxes[0].material: unknown material 'oak'");
  EXPECT_EQ(lines[2], "pavilion: 1 of 2 files have errors");

  const Result ok = RunPavilion({"validate", good_path}, dir);
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_EQ(ok.err, "");
}

// Confirms that bad usage (unknown option or subcommand, missing argument) exits 2.
TEST(CliTest, UsageErrorExitsTwo) {
  const fs::path dir = TestDir();
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"run", "x.yaml", "--out", "o", "--bogus"},
        std::vector<std::string>{"frobnicate"}, std::vector<std::string>{"run", "x.yaml"},
        std::vector<std::string>{},
        std::vector<std::string>{"run", "x.yaml", "--out", "o", "--seed", "-3"}}) {
    SCOPED_TRACE(args.empty() ? std::string("(none)") : args.back());
    const Result r = RunPavilion(args, dir);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(Lines(r.err).size(), 1u) << r.err;
    EXPECT_TRUE(Contains(r.err, "usage error"));
  }
}

// Confirms that `run` on a scenario with a bad key exits 1 with one line naming file and key.
TEST(CliTest, RunWithBadKeyPrintsOneLine) {
  const fs::path dir = TestDir();
  WriteFile(dir, "world.yaml", kWorld);
  std::string text = kBusyScenario;
  text.replace(text.find("outputs: {"), 10, "outputs: {frame_rate_hz: 5, ");
  const std::string path = WriteFile(dir, "scenario.yaml", text);
  const fs::path out = dir / "out";
  const Result r = RunPavilion({"run", path, "--out", out.string()}, dir);
  EXPECT_EQ(r.exit_code, 1);
  const std::vector<std::string> lines = Lines(r.err);
  ASSERT_EQ(lines.size(), 1u) << r.err;
  EXPECT_TRUE(Contains(lines[0], path + ":8: outputs.frame_rate_hz: unknown key"));
  EXPECT_FALSE(fs::exists(out)) << "nothing is written for a bad scenario";

  // The same for a bad key given with --set, and for an out-of-range --duration.
  const Result set =
      RunPavilion({"run", path, "--out", out.string(), "--set", "physics.rat_hz=1"}, dir);
  EXPECT_EQ(set.exit_code, 1);
  EXPECT_EQ(Lines(set.err).size(), 1u) << set.err;
  EXPECT_TRUE(Contains(set.err, "physics.rat_hz"));
}

// Runs the busy scenario with `seed` into dir/name; returns the output folder.
fs::path RunBusy(const fs::path& dir, const std::string& name, int seed) {
  const fs::path out = dir / name;
  const Result r = RunPavilion({"run", (dir / "scenario.yaml").string(), "--out", out.string(),
                                "--seed", std::to_string(seed)},
                               dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Contains(r.out, "report.html"));
  return out;
}

// Confirms that two runs with the same seed write byte-identical outputs and another seed differs.
TEST(CliTest, RunIsDeterministicForASeed) {
  const fs::path dir = TestDir();
  WriteFile(dir, "world.yaml", kWorld);
  WriteFile(dir, "scenario.yaml", kBusyScenario);
  const fs::path a = RunBusy(dir, "a", 7);
  const fs::path b = RunBusy(dir, "b", 7);
  for (const char* file : {"metrics.json", "events.jsonl", "trajectories.csv", "scans.bin",
                           "report.html", "snapshots/topdown_final.png"}) {
    SCOPED_TRACE(file);
    const std::string in_a = ReadFile(a / file);
    EXPECT_FALSE(in_a.empty());
    EXPECT_TRUE(in_a == ReadFile(b / file)) << "differs between two runs with seed 7";
  }
  for (const fs::path& out : {a, b}) {
    const nlohmann::json perf = nlohmann::json::parse(ReadFile(out / "performance.json"));
    for (const char* key : {"wall_time_s", "real_time_factor", "peak_rss_mb"}) {
      EXPECT_TRUE(perf.contains(key)) << key;
    }
  }
  // The layout is busy enough that collisions happen (so contacts are covered).
  EXPECT_TRUE(Contains(ReadFile(a / "events.jsonl"), "\"type\":\"collision\""));

  const fs::path c = RunBusy(dir, "c", 8);
  EXPECT_FALSE(ReadFile(a / "trajectories.csv") == ReadFile(c / "trajectories.csv"));
  EXPECT_FALSE(ReadFile(a / "scans.bin") == ReadFile(c / "scans.bin"));  // the noise draws
}

// Confirms the contents of metrics.json and events.jsonl.
TEST(CliTest, RunWritesWellFormedMetricsAndEvents) {
  const fs::path dir = TestDir();
  WriteFile(dir, "world.yaml", kWorld);
  WriteFile(dir, "scenario.yaml", kBusyScenario);
  const fs::path out = RunBusy(dir, "out", 7);

  const nlohmann::json metrics = nlohmann::json::parse(ReadFile(out / "metrics.json"));
  EXPECT_EQ(metrics.at("schema_version"), 1);
  EXPECT_EQ(metrics.at("seed"), 7);
  EXPECT_NEAR(metrics.at("sim_duration_s").get<double>(), 5.0, 1e-9);
  EXPECT_EQ(metrics.at("bodies_summary").at("count"), 10);

  const std::vector<std::string> lines = Lines(ReadFile(out / "events.jsonl"));
  ASSERT_GE(lines.size(), 2u);
  std::vector<nlohmann::json> events;
  for (const std::string& line : lines) {
    ASSERT_TRUE(nlohmann::json::accept(line)) << line;
    events.push_back(nlohmann::json::parse(line));
  }
  EXPECT_EQ(events.front().at("type"), "run_started");
  EXPECT_EQ(events.back().at("type"), "run_finished");
  EXPECT_NEAR(events.back().at("time_s").get<double>(), 5.0, 1e-9);
  int pushes = 0;
  double last_time = 0.0;
  for (const nlohmann::json& e : events) {
    EXPECT_GE(e.at("time_s").get<double>(), last_time);  // in time order
    last_time = e.at("time_s").get<double>();
    if (e.at("type") == "push") ++pushes;
  }
  EXPECT_EQ(pushes, 3);

  // The robot: two LMS 200 at 10 Hz for 5 s, and the sideways push at 3.5 s
  // moved it where its encoders did not follow.
  const nlohmann::json& robot = metrics.at("robots").at("robox");
  EXPECT_EQ(robot.at("model"), "robox");
  EXPECT_EQ(robot.at("scans"), 100);
  EXPECT_GT(robot.at("distance_m").get<double>(), 1.0);
  EXPECT_GT(robot.at("odometry_final_error").at("position_m").get<double>(), 0.01);
}

// Confirms that a frictionless body driven at 0.5 m/s (body frame) for 4 s travels 2 m along its
// heading.
TEST(CliTest, ScriptedBodyDrivesStraight) {
  const fs::path dir = TestDir();
  WriteFile(dir, "world.yaml", kWorld);
  const std::string path = WriteFile(dir, "scenario.yaml",
                                     "kind: scenario\n"
                                     "name: straight\n"
                                     "duration_s: 5\n"
                                     "world: world.yaml\n"
                                     "materials:\n"
                                     "  ice: {friction: 0.0}\n"
                                     "bodies:\n"
                                     "  - id: rover\n"
                                     "    shape: {type: cylinder, radius: 0.2, height: 0.5}\n"
                                     "    mass_kg: 5\n"
                                     "    material: ice\n"
                                     "    pose: [-4, -4, 0.3]\n"
                                     "    motion:\n"
                                     "      type: scripted\n"
                                     "      segments: [{duration_s: 4, velocity: [0.5, 0]}]\n");
  const fs::path out = dir / "out";
  const Result r = RunPavilion({"run", path, "--out", out.string(), "--seed", "7"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;

  const std::vector<std::string> lines = Lines(ReadFile(out / "trajectories.csv"));
  ASSERT_GE(lines.size(), 3u);
  EXPECT_EQ(lines[0],
            "time_s,id,true_x_m,true_y_m,true_theta_rad,odom_x_m,odom_y_m,odom_theta_rad,est_x_m,"
            "est_y_m,est_theta_rad,cov_xx,cov_xy,cov_xtheta,cov_yy,cov_ytheta,cov_thetatheta");
  struct Row {
    double t, x, y, theta;
  };
  std::vector<Row> rows;
  for (std::size_t i = 1; i < lines.size(); ++i) {
    std::stringstream in(lines[i]);
    std::string t, id, x, y, theta;
    std::getline(in, t, ',');
    std::getline(in, id, ',');
    std::getline(in, x, ',');
    std::getline(in, y, ',');
    std::getline(in, theta, ',');
    ASSERT_EQ(id, "rover");
    rows.push_back({std::stod(t), std::stod(x), std::stod(y), std::stod(theta)});
  }
  const Row& start = rows.front();
  const Row& end = rows.back();
  EXPECT_DOUBLE_EQ(start.t, 0.0);
  EXPECT_NEAR(end.t, 5.0, 1e-9);
  // Exact kinematics for a frictionless driven body: 0.5 m/s * 4 s along the heading.
  constexpr double kTolM = 0.02;
  EXPECT_NEAR(start.x, -4.0, 1e-9);
  EXPECT_NEAR(start.y, -4.0, 1e-9);
  EXPECT_NEAR(std::hypot(end.x - start.x, end.y - start.y), 2.0, kTolM);
  EXPECT_NEAR(end.x, -4.0 + 2.0 * std::cos(0.3), kTolM);
  EXPECT_NEAR(end.y, -4.0 + 2.0 * std::sin(0.3), kTolM);
  EXPECT_NEAR(end.theta, 0.3, 1e-3);
}

// `calibrate` drives the calibration runs, prints the `odometry:` block for
// robot.yaml and writes calibration.json; an unknown robot is one error line.
TEST(CliTest, CalibrateWritesTheOdometryBlockAndJson) {
  const fs::path dir = TestDir();
  const fs::path out = dir / "calib";
  const Result r =
      RunPavilion({"calibrate", "pygmalion", "--runs", "1", "--out", out.string()}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Contains(r.out, "odometry:\n")) << r.out;
  EXPECT_TRUE(Contains(r.out, "  wheelbase_m: 0.3")) << r.out;
  EXPECT_TRUE(Contains(r.out, "pavilion calibrate pygmalion --runs 1 --seed 1")) << r.out;
  const auto json = nlohmann::json::parse(ReadFile(out / "calibration.json"));
  EXPECT_EQ(json["robot"], "pygmalion");
  EXPECT_EQ(json["runs"].size(), 5u);  // one run of each kind
  EXPECT_NEAR(json["calibrated"]["wheelbase_m"].get<double>(), 0.38, 0.004);

  const Result bad = RunPavilion({"calibrate", "no_such_robot"}, dir);
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_EQ(Lines(bad.err).size(), 1u) << bad.err;
  EXPECT_TRUE(Contains(bad.err, "no_such_robot")) << bad.err;
}

// The CARMEN logs in ../shared/data/carmen (next to the source tree); empty if absent.
fs::path CarmenLog(const std::string& name) {
  const std::string dir = pavilion::testing::CarmenDataDir();
  if (dir.empty()) return fs::path();
  const fs::path path = fs::path(dir) / name;
  return fs::exists(path) ? path : fs::path();
}

// `extract` summarizes a whole CARMEN log, lists and draws one scan's lines, reads a
// Pavilion scans.bin, and rejects an out-of-range --scan with one line naming it.
TEST(CliTest, ExtractListsLinesOfCarmenAndScanLogs) {
  const fs::path dir = TestDir();
  const fs::path intel = CarmenLog("intel-corrected.log.gz");
  if (!intel.empty()) {
    const Result summary = RunPavilion({"extract", "--log", intel.string()}, dir);
    ASSERT_EQ(summary.exit_code, 0) << summary.err;
    EXPECT_TRUE(Contains(summary.out, "scans: 910")) << summary.out;
    EXPECT_TRUE(Contains(summary.out, "lines per scan")) << summary.out;

    const fs::path png = dir / "x.png";
    const Result one = RunPavilion(
        {"extract", "--log", intel.string(), "--scan", "5", "--png", png.string()}, dir);
    ASSERT_EQ(one.exit_code, 0) << one.err;
    EXPECT_TRUE(fs::exists(png));
    EXPECT_GT(fs::file_size(png), 1000u);
    // Rows of the table: "   1  alpha r ..." after the header line starting with "#".
    int rows = 0;
    bool in_table = false;
    for (const std::string& line : Lines(one.out)) {
      if (Contains(line, "   # ")) {
        in_table = true;
      } else if (in_table && line.find_first_not_of(' ') != std::string::npos &&
                 std::isdigit(static_cast<unsigned char>(line[line.find_first_not_of(' ')]))) {
        ++rows;
      }
    }
    EXPECT_GE(rows, 2) << one.out;

    const Result bad = RunPavilion({"extract", "--log", intel.string(), "--scan", "100000"}, dir);
    EXPECT_EQ(bad.exit_code, 1);
    EXPECT_EQ(Lines(bad.err).size(), 1u) << bad.err;
    EXPECT_TRUE(Contains(bad.err, "--scan")) << bad.err;
  }

  WriteFile(dir, "world.yaml", kWorld);
  WriteFile(dir, "scenario.yaml", kBusyScenario);
  const fs::path out = RunBusy(dir, "busy", 7);
  const Result sim = RunPavilion({"extract", "--log", (out / "scans.bin").string()}, dir);
  EXPECT_EQ(sim.exit_code, 0) << sim.err;
  EXPECT_TRUE(Contains(sim.out, "lines per scan")) << sim.out;
  const Result robot = RunPavilion(
      {"extract", "--log", (out / "scans.bin").string(), "--robot", "robox", "--scan", "0"}, dir);
  EXPECT_EQ(robot.exit_code, 0) << robot.err;
  EXPECT_TRUE(Contains(robot.out, "robox/")) << robot.out;

  WriteFile(dir, "garbage.log", "FLASER 3 1.0 2.0\n");
  const Result malformed = RunPavilion({"extract", "--log", (dir / "garbage.log").string()}, dir);
  EXPECT_EQ(malformed.exit_code, 1);
  EXPECT_EQ(Lines(malformed.err).size(), 1u) << malformed.err;

  if (intel.empty()) GTEST_SKIP() << "no ../shared/data/carmen/intel-corrected.log.gz";
}

}  // namespace
