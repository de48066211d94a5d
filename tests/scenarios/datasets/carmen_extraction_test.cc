// Line extraction on fixed scans of two real CARMEN logs, against expectations
// checked by hand on `pavilion extract --scan K --png` pictures: the long walls
// each scan shows are found, and nothing absurd (a line through the sensor).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>

#include "core/features/line_extraction.h"
#include "scenarios/datasets/carmen_log.h"
#include "tests/support/test_files.h"

namespace pavilion {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

struct ExpectedWall {
  double alpha_deg;
  double r_m;
  double min_length_m;
};

// Options of `pavilion extract` for real logs: LMS 200 preset, 1 cm range
// sigma, covariance floor 5 mm and 0.2 degrees (§2.2.1.3).
core::LineExtractionOptions RealLogOptions() {
  core::LineExtractionOptions o = core::LineExtractionOptions::SickLms200();
  o.range_sigma_m = 0.01;
  o.r_sigma_floor_m = 0.005;
  o.alpha_sigma_floor_rad = 0.2 * kDeg;
  return o;
}

void CheckScan(const std::string& log_name, scenarios::CarmenAngleStep step, int scan_index,
               const std::vector<ExpectedWall>& walls) {
  const std::string path = pavilion::testing::CarmenDataDir() + "/" + log_name;
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "no " << path;
  scenarios::CarmenLog log = scenarios::ReadCarmenLog(path, scenarios::CarmenOptions{});
  scenarios::SetCarmenAngleStep(step, &log);
  ASSERT_GT(static_cast<int>(log.scans.size()), scan_index);
  const std::vector<core::Segment> segments =
      core::ExtractLines(log.scans[scan_index].scan, RealLogOptions());
  for (const ExpectedWall& wall : walls) {
    // Seen length per extracted line: pieces of one line (eq. 5.17) add up.
    std::map<int, double> seen_m;
    for (const core::Segment& s : segments) {
      const double dalpha =
          std::remainder(s.line.alpha_rad - wall.alpha_deg * kDeg, 2 * std::numbers::pi);
      if (std::abs(dalpha) < 2.0 * kDeg && std::abs(s.line.r_m - wall.r_m) < 0.05) {
        seen_m[s.line_id] += s.length_m;
      }
    }
    bool found = false;
    for (const auto& [line_id, length_m] : seen_m) found = found || length_m >= wall.min_length_m;
    EXPECT_TRUE(found) << log_name << " scan " << scan_index << ": wall alpha " << wall.alpha_deg
                       << " deg, r " << wall.r_m << " m";
  }
  for (const core::Segment& s : segments) {
    EXPECT_GT(s.line.r_m, 0.2) << "a line through the sensor";
    EXPECT_LT(s.length_m, 15.0);
  }
}

TEST(CarmenExtraction, IntelCorridorWallsOfScan5) {
  // A corridor about 2.1 m wide: walls on both sides of the robot.
  CheckScan("intel-corrected.log.gz", scenarios::CarmenAngleStep::kFovOverN, 5,
            {{-94.8, 1.04, 1.0}, {84.5, 1.07, 1.0}});
}

TEST(CarmenExtraction, CsailWallsOfScan100) {
  // The right-hand wall along the robot (2.3 m seen), the left one (3.7 m), and
  // the far wall ahead at 10.9 m.
  CheckScan("csail-corrected.log.gz", scenarios::CarmenAngleStep::kFovOverNMinus1, 100,
            {{-94.4, 1.14, 2.0}, {85.4, 0.545, 3.0}, {-4.3, 10.87, 1.0}});
}

}  // namespace
}  // namespace pavilion
