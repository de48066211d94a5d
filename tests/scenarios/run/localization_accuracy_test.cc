// Issue 6, acceptance tests of the EKF pose tracking in the simulator (thesis
// chapter 4): with the laser's noise off and a perfect map the estimate follows
// the truth to the millimetre while driving, and a start 30 cm / 5 deg off
// converges within ten cycles where three non-parallel walls are in view.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "scenarios/config/data_paths.h"
#include "scenarios/config/scenario.h"
#include "scenarios/config/world_loader.h"
#include "scenarios/maps/map_derivation.h"
#include "scenarios/maps/map_file.h"
#include "scenarios/run/scenario_runner.h"
#include "sim/world/world.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

namespace fs = std::filesystem;

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// The rows of localization.csv as numbers by column name (the `id` column is dropped).
std::vector<std::map<std::string, double>> ReadLocalizationCsv(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  std::stringstream header(line);
  for (std::string name; std::getline(header, name, ',');) names.push_back(name);
  std::vector<std::map<std::string, double>> rows;
  while (std::getline(in, line)) {
    std::stringstream fields(line);
    std::map<std::string, double> row;
    std::string field;
    for (std::size_t k = 0; k < names.size() && std::getline(fields, field, ','); ++k) {
      if (names[k] != "id" && names[k] != "state")
        row[names[k]] = std::stod(field);  // text columns
    }
    rows.push_back(row);
  }
  return rows;
}

// Writes the exact map of office_floor (no tape-measure noise) into `dir`.
std::string DerivePerfectMap(const fs::path& dir) {
  const sim::World world(LoadWorldFile(ResolveWorldPath("office_floor")), {});
  MapDerivationOptions options;
  options.noise_sigma_m = 0.0;
  const std::string path = (dir / "perfect_map.yaml").string();
  WriteMapFile(path, DeriveRobotMap(world, options));
  return path;
}

// Runs a Pygmalion scenario in office_floor whose robot entry continues with
// `robot_tail` (indented four spaces) into dir/name; returns that folder.
fs::path RunOfficeFloor(const fs::path& dir, const std::string& name, const std::string& robot_tail,
                        double duration_s) {
  const std::string text =
      "kind: scenario\n"
      "name: localization_accuracy\n"
      "world: office_floor\n"
      "seed: 1\n"
      "duration_s: " +
      std::to_string(duration_s) +
      "\n"
      "end_when_routes_done: true\n"
      "physics: {rate_hz: 200}\n"
      "outputs: {trajectory_rate_hz: 2, scan_log: false}\n"
      "robots:\n"
      "  - id: pygmalion\n"
      "    model: pygmalion\n" +
      robot_tail;
  const std::string path = pavilion::testing::WriteFile(dir, name + ".yaml", text);
  const fs::path out = dir / name;
  RunScenario(LoadScenarioFile(path), RunOptions{out.string(), false});
  return out;
}

struct ErrorMaxima {
  double position_m = 0.0;
  double heading_deg = 0.0;
  int position_cycle = -1;  // where the maxima occur
  int heading_cycle = -1;
};

ErrorMaxima MaximaFrom(const std::vector<std::map<std::string, double>>& rows, int first_cycle) {
  ErrorMaxima m;
  for (const auto& row : rows) {
    const int cycle = static_cast<int>(row.at("cycle"));
    if (cycle < first_cycle) continue;
    const double p = row.at("position_error_m");
    const double h = std::abs(row.at("heading_error_rad")) * kDegPerRad;
    if (p > m.position_m) m = {p, m.heading_deg, cycle, m.heading_cycle};
    if (h > m.heading_deg) m = {m.position_m, h, m.position_cycle, cycle};
  }
  return m;
}

// Issue 6: "Drives 20 m in office_floor with laser noise off and a perfect map:
// after every update the estimate is within 2 mm and 0.1 deg of the truth."
TEST(LocalizationAccuracyTest, TracksWithinTwoMillimetresWithExactLaserAndMap) {
  const fs::path dir = pavilion::testing::TestDir();
  const std::string map = DerivePerfectMap(dir);
  const fs::path out = RunOfficeFloor(dir, "drive",
                                      "    pose: [7.0, 7.25, 0.0]\n"
                                      "    laser_noise: false\n"
                                      "    localization:\n"
                                      "      map: " +
                                          map +
                                          "\n"
                                          "      rate_hz: 2\n"
                                          "      initial_sigma: [0.005, 0.005, 0.005]\n"
                                          "    route:\n"
                                          "      stops: [lab, office_06]\n"
                                          "      max_speed_mps: 0.4\n"
                                          "      max_accel_mps2: 0.3\n"
                                          "      max_turn_rate_radps: 0.4\n"
                                          "      max_turn_accel_radps2: 0.5\n"
                                          "      max_lateral_accel_mps2: 0.05\n"
                                          "      lookahead_m: 0.3\n",
                                      200.0);
  std::ifstream in(out / "metrics.json");
  const nlohmann::json m = nlohmann::json::parse(in)["robots"]["pygmalion"];
  const auto rows = ReadLocalizationCsv(out / "localization.csv");
  const ErrorMaxima e = MaximaFrom(rows, 0);
  std::printf(
      "[ info ] route %.2f m (driven %.2f m) in %.1f s, %zu cycles; max error %.3f mm (cycle %d), "
      "%.4f deg (cycle %d); RMSE %.3f mm, %.4f deg; ANEES %.1f\n",
      m["route"]["length_m"].get<double>(), m["distance_m"].get<double>(),
      m["route"]["done_at_s"].get<double>(), rows.size(), 1e3 * e.position_m, e.position_cycle,
      e.heading_deg, e.heading_cycle, 1e3 * m["localization"]["position_rmse_m"].get<double>(),
      m["localization"]["heading_rmse_deg"].get<double>(),
      m["localization"]["anees"].get<double>());
  EXPECT_TRUE(m["route"]["done"].get<bool>());
  EXPECT_GE(m["distance_m"].get<double>(), 19.0);
  EXPECT_GT(rows.size(), 50u);
  // Measured max 0.95 mm and 0.008 deg, RMSE 0.54 mm, ANEES 3.0 (with the
  // friction pyramid of sim/world/world.cc; before it the robot crept sideways and the
  // same route ended 3.4 mm / 0.33 deg off).
  EXPECT_LE(e.position_m, 0.002);
  EXPECT_LE(e.heading_deg, 0.1);
}

// Issue 6: "Starting with a 30 cm / 5 deg error, with at least three non-parallel
// walls in view, converges to within 2 cm / 0.5 deg in at most 10 cycles." The
// robot stands in the laboratory (walls east, west, north and south in view of
// its two lasers); every cycle from the tenth on must be within the bounds.
TEST(LocalizationAccuracyTest, ConvergesFromThirtyCentimetresAndFiveDegreesInTenCycles) {
  constexpr int kCycles = 10;
  const fs::path dir = pavilion::testing::TestDir();
  const std::vector<std::string> offsets = {"[0.3, 0.0, 0.0873]", "[-0.2, 0.224, -0.0873]"};
  for (std::size_t run = 0; run < offsets.size(); ++run) {
    const std::string& offset = offsets[run];
    SCOPED_TRACE(offset);
    const fs::path out = RunOfficeFloor(dir, "offset_" + std::to_string(run),
                                        "    pose: [7.0, 7.25, 0.0]\n"
                                        "    localization:\n"
                                        "      rate_hz: 2\n"
                                        "      initial_offset: " +
                                            offset +
                                            "\n"
                                            "      initial_sigma: [0.3, 0.3, 0.1]\n",
                                        15.0);
    const auto rows = ReadLocalizationCsv(out / "localization.csv");
    ASSERT_GE(rows.size(), static_cast<std::size_t>(kCycles + 5));
    std::string per_cycle;
    for (std::size_t k = 0; k < 12 && k < rows.size(); ++k) {
      char buf[64];
      std::snprintf(buf, sizeof buf, " %.1f mm/%.3f deg", 1e3 * rows[k].at("position_error_m"),
                    std::abs(rows[k].at("heading_error_rad")) * kDegPerRad);
      per_cycle += buf;
    }
    const ErrorMaxima e = MaximaFrom(rows, kCycles - 1);
    std::printf(
        "[ info ] offset %s: errors per cycle%s\n[ info ] from cycle %d on: max %.2f mm, "
        "%.3f deg\n",
        offset.c_str(), per_cycle.c_str(), kCycles, 1e3 * e.position_m, e.heading_deg);
    EXPECT_LE(e.position_m, 0.02);
    EXPECT_LE(e.heading_deg, 0.5);
  }
}

}  // namespace
}  // namespace pavilion::scenarios
