// Thesis Table 4.1 / Fig. 4.4, second run (issue 19, scenarios/corridor_vision.yaml):
// the corridor with only its parallel lines in the map, plus the camera's
// vertical edges. The laser alone lets the frontal 2 sigma grow with the
// distance driven (corridor_laser_only); the door frames' and corners' edges
// keep it bounded: at the corridor's end it is at most half the laser-only
// run's, and the true error there is not worse.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "scenarios/config/scenario.h"
#include "scenarios/run/scenario_runner.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

namespace fs = std::filesystem;

struct End {
  double frontal_two_sigma_m = 0.0;
  double position_error_m = 0.0;
  int rows = 0;
  int matched_edges = 0;  // summed over the run
};

// The last localization cycle's frontal 2 sigma and true error.
End RunToTheEnd(const std::string& scenario, const std::string& name) {
  const Scenario s = LoadScenarioFile(std::string(PAVILION_SOURCE_DIR) + "/scenarios/" + scenario);
  const fs::path out = pavilion::testing::TestDir() / name;
  RunScenario(s, RunOptions{out.string(), false});
  std::ifstream in(out / "localization.csv");
  std::string line;
  std::getline(in, line);
  std::map<std::string, std::size_t> column;
  std::stringstream header(line);
  std::size_t k = 0;
  for (std::string field; std::getline(header, field, ',');) column[field] = k++;
  End end;
  while (std::getline(in, line)) {
    std::vector<std::string> fields;
    std::stringstream row(line);
    for (std::string f; std::getline(row, f, ',');) fields.push_back(f);
    end.frontal_two_sigma_m = std::stod(fields.at(column.at("two_sigma_frontal_m")));
    end.position_error_m = std::stod(fields.at(column.at("position_error_m")));
    end.matched_edges += std::stoi(fields.at(column.at("matched_edges")));
    ++end.rows;
  }
  return end;
}

TEST(CorridorVision, EdgesBoundTheFrontalUncertainty) {
  const End laser = RunToTheEnd("corridor_laser_only.yaml", "laser");
  const End vision = RunToTheEnd("corridor_vision.yaml", "vision");
  ASSERT_GT(laser.rows, 40);
  ASSERT_GT(vision.rows, 40);
  EXPECT_EQ(laser.matched_edges, 0);
  EXPECT_GT(vision.matched_edges, vision.rows / 2);  // edges are matched along the way
  EXPECT_LE(vision.frontal_two_sigma_m, 0.5 * laser.frontal_two_sigma_m)
      << "vision " << vision.frontal_two_sigma_m << " m, laser " << laser.frontal_two_sigma_m;
  EXPECT_LE(vision.position_error_m, laser.position_error_m)
      << "vision " << vision.position_error_m << " m, laser " << laser.position_error_m;
}

}  // namespace
}  // namespace pavilion::scenarios
