// Acceptance (make acceptance; not in CI): the office tour of thesis §4.5.2 (Fig. 4.8, Table 4.2)
// in the simulator. Pygmalion follows the tour from its own estimate and localizes at 2 Hz with its
// two LMS 200 against the derived office_floor map; the run is compared with ground truth
// (metrics.md, "Localization").
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

// Runs the tour with `seed`, writing into dir/tour_<seed>.
nlohmann::json RunTour(std::uint64_t seed, const std::filesystem::path& dir) {
  ScenarioOverrides overrides;
  overrides.seed = seed;
  const Scenario s =
      LoadScenarioFile(std::string(PAVILION_SOURCE_DIR) + "/scenarios/office_tour.yaml", overrides);
  const std::string out = (dir / ("tour_" + std::to_string(seed))).string();
  RunScenario(s, RunOptions{out, false});
  std::ifstream in(out + "/metrics.json");
  return nlohmann::json::parse(in);
}

// The acceptance of issue 6 over five seeds; each seed also draws a fresh
// survey of the office (the scenario's `map: derive`), so the map's error is
// sampled like the sensors' noise.
TEST(OfficeTour, FiveSeedsLocalizeToACentimetreAndTheFilterIsConsistent) {
  constexpr int kRuns = 5;
  // Two-sided 95% band of the mean of five chi^2(3) NEES: chi^2(15)/5 at
  // 2.5% and 97.5% (metrics.md).
  constexpr double kBandLow = 6.2621 / kRuns;
  constexpr double kBandHigh = 27.4884 / kRuns;
  const std::filesystem::path dir = pavilion::testing::TestDir();
  std::vector<std::vector<double>> nees;
  double pooled_sum = 0.0;
  long pooled_count = 0;
  for (int seed = 1; seed <= kRuns; ++seed) {
    const nlohmann::json m = RunTour(seed, dir)["robots"]["pygmalion"];
    const nlohmann::json& l = m["localization"];
    std::printf(
        "[ info ] seed %d: tour %.1f m in %.1f s, %d cycles; RMSE %.2f mm, %.3f deg (max %.1f mm); "
        "2 sigma frontal %.2f mm, lateral %.2f mm, heading %.3f deg; %.2f lines per cycle; "
        "ANEES %.2f\n",
        seed, m["distance_m"].get<double>(), m["route"]["done_at_s"].get<double>(),
        l["cycles"].get<int>(), 1e3 * l["position_rmse_m"].get<double>(),
        l["heading_rmse_deg"].get<double>(), 1e3 * l["position_max_m"].get<double>(),
        1e3 * l["two_sigma_frontal_m"].get<double>(), 1e3 * l["two_sigma_lateral_m"].get<double>(),
        l["two_sigma_heading_deg"].get<double>(), l["matched_lines_per_cycle"].get<double>(),
        l["anees"].get<double>());
    EXPECT_TRUE(m["route"]["done"].get<bool>()) << "seed " << seed;
    EXPECT_EQ(m["collisions"].get<int>(), 0) << "seed " << seed;
    EXPECT_GT(m["distance_m"].get<double>(), 140.0) << "seed " << seed;
    // About 950 cycles at 2 Hz, as in the thesis.
    EXPECT_GT(l["cycles"].get<int>(), 850) << "seed " << seed;
    EXPECT_LT(l["cycles"].get<int>(), 1050) << "seed " << seed;
    EXPECT_EQ(l["lost_situations"].get<int>(), 0) << "seed " << seed;
    EXPECT_LE(l["position_rmse_m"].get<double>(), 0.015) << "seed " << seed;  // measured 1.3-1.9 mm
    EXPECT_LE(l["heading_rmse_deg"].get<double>(), 0.5) << "seed " << seed;   // 0.014-0.019 deg
    EXPECT_GT(l["matched_lines_per_cycle"].get<double>(), 2.0) << "seed " << seed;
    nees.push_back(pavilion::testing::ReadCsvColumn(
        dir / ("tour_" + std::to_string(seed)) / "localization.csv", "nees"));
    for (const double e : nees.back()) pooled_sum += e;
    pooled_count += static_cast<long>(nees.back().size());
  }
  // The NEES averaged over the runs at each cycle (the runs' cycles align to a
  // few at the end: compared up to the shortest run).
  std::size_t cycles = nees.front().size();
  for (const std::vector<double>& run : nees) cycles = std::min(cycles, run.size());
  ASSERT_GT(cycles, 850u);
  std::size_t inside = 0, above = 0;
  for (std::size_t k = 0; k < cycles; ++k) {
    double mean = 0.0;
    for (const std::vector<double>& run : nees) mean += run[k] / kRuns;
    inside += mean >= kBandLow && mean <= kBandHigh ? 1 : 0;
    above += mean > kBandHigh ? 1 : 0;
  }
  const double inside_ratio = static_cast<double>(inside) / static_cast<double>(cycles);
  const double anees = pooled_sum / static_cast<double>(pooled_count);
  std::printf(
      "[ info ] five runs: mean NEES inside [%.2f, %.2f] for %.1f%% of %zu cycles (%.1f%% above); "
      "pooled ANEES %.2f (consistent: 3)\n"
      "[ info ] thesis Table 4.2 (laser only): 2 sigma frontal 13.1 mm, lateral 13.5 mm, heading "
      "0.92 deg, 2.73 lines per cycle\n",
      kBandLow, kBandHigh, 100.0 * inside_ratio, cycles,
      100.0 * static_cast<double>(above) / static_cast<double>(cycles), anees);
  // Measured 96.6% inside, pooled ANEES 2.79: consistent since the map's
  // error is modelled as one draw (core/localization/map_cross_covariance.h)
  // and the extraction's covariance has its floor (LineExtractionOptions::
  // SickLms200); without the floor 88.9% and 3.25.
  EXPECT_GE(inside_ratio, 0.90);
  EXPECT_GT(anees, kBandLow);
  EXPECT_LT(anees, kBandHigh);
}

}  // namespace
}  // namespace pavilion::scenarios
