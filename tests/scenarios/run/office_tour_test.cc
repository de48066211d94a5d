// CI's shortened office tour (the five full tours are office_tour_acceptance_test):
// the office tour of thesis §4.5.2 (Fig. 4.8, Table 4.2) in the
// simulator. Pygmalion follows the tour from its own estimate and localizes at
// 2 Hz with its two LMS 200 against the derived office_floor map; the run is
// compared with ground truth (metrics.md, "Localization").
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "scenarios/config/scenario.h"
#include "scenarios/run/scenario_runner.h"
#include "tests/support/csv_column.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

// The first 150 s of the 470 s tour: lab, corridor and the first offices.
constexpr double kShortTourS = 150.0;

// Runs the tour with `seed`, writing into dir/tour_<seed>; returns its metrics.
RunMetrics RunTour(std::uint64_t seed, const std::filesystem::path& dir) {
  ScenarioOverrides overrides;
  overrides.seed = seed;
  overrides.duration_s = kShortTourS;
  const Scenario s =
      LoadScenarioFile(std::string(PAVILION_SOURCE_DIR) + "/scenarios/office_tour.yaml", overrides);
  const std::string out = (dir / ("tour_" + std::to_string(seed))).string();
  return RunScenario(s, RunOptions{out, false}).metrics;
}

// One seed, the tour's first 150 s, read from the run's typed metrics and
// localization.csv: the same bounds per run as the acceptance test.
TEST(OfficeTour, ShortTourLocalizesToACentimetre) {
  const std::filesystem::path dir = pavilion::testing::TestDir();
  const RunMetrics metrics = RunTour(1, dir);
  ASSERT_EQ(metrics.robots.size(), 1u);
  const RobotMetrics& m = metrics.robots.front();
  ASSERT_TRUE(m.localization);
  const LocalizationFigures& l = *m.localization;
  EXPECT_EQ(m.collisions, 0);
  EXPECT_GT(m.distance_m, 40.0);
  // 2 Hz for 150 s.
  EXPECT_GT(l.cycles, 280);
  EXPECT_LT(l.cycles, 320);
  EXPECT_EQ(l.lost_situations, 0);
  EXPECT_LE(l.position_rmse_m, 0.015);
  EXPECT_LE(l.heading_rmse_deg, 0.5);
  EXPECT_GT(l.matched_lines_per_cycle, 2.0);
  // One run's ANEES over ~300 cycles: far from the five-run band's precision,
  // but an overconfident filter (ANEES ~30 without the map correlations) fails.
  const std::vector<double> nees =
      pavilion::testing::ReadCsvColumn(dir / "tour_1" / "localization.csv", "nees");
  ASSERT_EQ(static_cast<int>(nees.size()), l.cycles);
  EXPECT_GT(l.anees, 1.0);
  EXPECT_LT(l.anees, 8.0);
}

}  // namespace
}  // namespace pavilion::scenarios
