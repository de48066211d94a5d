// `pavilion extract` with --score, --compare and --png, on a scans.bin written
// by `pavilion run` in the shipped small_lab world.
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "core/types/sensor_data.h"
#include "scenarios/output/scan_log.h"
#include "tests/support/run_pavilion.h"
#include "tests/support/test_files.h"

namespace {

namespace fs = std::filesystem;
using pavilion::testing::Contains;
using pavilion::testing::PavilionResult;
using pavilion::testing::RunPavilion;
using pavilion::testing::SplitLines;
using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

// Pygmalion (two SICK LMS 200 at 0.5 m, 10 Hz) stands at the start of
// small_lab for 2 s: 40 scans with ground truth. Standing: the scoring takes
// the true lines in the frame of a scan's first reading (exact when static).
const std::string kScenario =
    "kind: scenario\n"
    "name: extract_small_lab\n"
    "seed: 3\n"
    "duration_s: 2\n"
    "world: small_lab\n"
    "outputs: {image_width_px: 200}\n"
    "robots:\n"
    "  - id: pyg\n"
    "    model: pygmalion\n"
    "    pose: [0, 0, 0]\n"
    "    drive: [{at_s: 0, left: 0, right: 0}]\n";

// Runs the scenario into dir/run (each test its own: ctest runs tests in
// parallel processes); returns the scans.bin.
fs::path SmallLabScans(const fs::path& dir) {
  const fs::path run = dir / "run";
  fs::create_directories(run);
  const std::string scenario = WriteFile(run, "scenario.yaml", kScenario);
  const PavilionResult r = RunPavilion({"run", scenario, "--out", (run / "out").string()}, run);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return run / "out" / "scans.bin";
}

// The values after `label` on the line of `text` starting with it.
std::vector<double> RowValues(const std::string& text, const std::string& label) {
  for (const std::string& line : SplitLines(text)) {
    if (line.rfind(label, 0) != 0) continue;
    std::stringstream in(line.substr(label.size()));
    std::vector<double> values;
    for (double v; in >> v;) values.push_back(v);
    return values;
  }
  ADD_FAILURE() << "no row '" << label << "' in\n" << text;
  return {};
}

// --score --compare prints the metrics.md figures of both methods, one column
// each, on the same 40 scans. In a static room of 17 walls, noise 1 cm, both
// find nearly every wall in view and extract almost nothing else, and
// ExtractLines' covariances are consistent (95% gate; 40 scans of the same few
// walls are not independent, hence the margin).
TEST(ExtractCommandTest, ScoreAndCompareBothMethods) {
  const fs::path dir = TestDir();
  const fs::path scans = SmallLabScans(dir);
  ASSERT_TRUE(fs::exists(scans));
  const PavilionResult r =
      RunPavilion({"extract", "--log", scans.string(), "--score", "small_lab", "--compare"}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Contains(r.out, "ground truth: world ")) << r.out;
  EXPECT_TRUE(Contains(r.out, "split-and-merge: split 50.0 mm")) << r.out;
  EXPECT_EQ(RowValues(r.out, "scans "), (std::vector<double>{40, 40}));
  const std::vector<double> in_view = RowValues(r.out, "walls in view ");
  ASSERT_EQ(in_view.size(), 2u);
  EXPECT_GE(in_view[0], 40);  // a wall within 6 m in front of every scan
  EXPECT_EQ(in_view[0], in_view[1]) << "the same scans, the same truth";
  for (const char* row : {"TP rate ", "FP rate ", "in 95% gate ", "scans per second ",
                          "time per scan, median (us) ", "sigma delta-r (mm) "}) {
    SCOPED_TRACE(row);
    EXPECT_EQ(RowValues(r.out, row).size(), 2u);
  }
  const std::vector<double> tp = RowValues(r.out, "TP rate ");
  const std::vector<double> fp = RowValues(r.out, "FP rate ");
  ASSERT_EQ(tp.size(), 2u);
  ASSERT_EQ(fp.size(), 2u);
  EXPECT_GE(tp[0], 0.9);
  EXPECT_LE(fp[0], 0.1);
  EXPECT_GE(tp[1], 0.9);
  EXPECT_LE(fp[1], 0.1);
  const std::vector<double> gate = RowValues(r.out, "in 95% gate ");
  ASSERT_EQ(gate.size(), 2u);
  EXPECT_GE(gate[0], 0.8);
  // sigma_r = 1 cm per reading: the fitted r of a wall of tens of readings is
  // good to a few mm, far inside the 5 cm match gate.
  const std::vector<double> sigma_r = RowValues(r.out, "sigma delta-r (mm) ");
  ASSERT_EQ(sigma_r.size(), 2u);
  EXPECT_LT(sigma_r[0], 10.0);

  // Without --compare: the same figures for ExtractLines as `key: value` lines.
  const PavilionResult one =
      RunPavilion({"extract", "--log", scans.string(), "--score", "small_lab"}, dir);
  ASSERT_EQ(one.exit_code, 0) << one.err;
  for (const char* part : {"scans: 40\n", "walls in view: ", ": TP rate ", ": FP rate ", "scans/s)",
                           "sigma delta-r ", "in 95% gate: "}) {
    EXPECT_TRUE(Contains(one.out, part)) << part;
  }
}

// --scan K with --score and --png lists scan K's lines, scores that scan and
// draws it.
TEST(ExtractCommandTest, OneScanScoredAndDrawn) {
  const fs::path dir = TestDir();
  const fs::path scans = SmallLabScans(dir);
  const fs::path png = dir / "scan.png";
  const PavilionResult r = RunPavilion({"extract", "--log", scans.string(), "--score", "small_lab",
                                        "--scan", "3", "--png", png.string()},
                                       dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Contains(r.out, "scan 3 of 40 (pyg/")) << r.out;
  EXPECT_TRUE(Contains(r.out, "summary of scan 3:\nscans: 1\n")) << r.out;
  EXPECT_TRUE(Contains(r.out, "scene: \"")) << r.out;
  ASSERT_TRUE(fs::exists(png));
  EXPECT_GT(fs::file_size(png), 1000u);
}

// --score on a CARMEN log, a scans.bin without ground truth, or the wrong
// world is one error line and exit 1; --beam-height without --score is bad usage.
TEST(ExtractCommandTest, ScoreRejectsLogsItCannotScore) {
  const fs::path dir = TestDir();
  std::string carmen = "FLASER 181";
  for (int i = 0; i < 181; ++i) carmen += " 2.0";
  carmen += " 0 0 0 0 0 0 0 host 0\n";
  const std::string log = WriteFile(dir, "tiny.log", carmen);
  const PavilionResult on_carmen =
      RunPavilion({"extract", "--log", log, "--score", "small_lab"}, dir);
  EXPECT_EQ(on_carmen.exit_code, 1);
  ASSERT_EQ(SplitLines(on_carmen.err).size(), 1u) << on_carmen.err;
  EXPECT_TRUE(Contains(on_carmen.err, "--score")) << on_carmen.err;
  EXPECT_TRUE(Contains(on_carmen.err, "tiny.log")) << on_carmen.err;

  // A scan log whose records carry no truth.
  const std::string bare = (dir / "bare.bin").string();
  {
    pavilion::scenarios::ScanLogWriter writer(bare, {"floor", "room"});
    pavilion::core::LaserScan scan;
    scan.sensor_id = "front";
    scan.max_range_m = 8.0;
    for (int i = 0; i < 181; ++i) {
      pavilion::core::LaserReading reading;
      reading.bearing_rad = -1.5707963 + i * 0.0174533;
      reading.range_m = 2.0;
      reading.valid = true;
      scan.readings.push_back(reading);
    }
    writer.Append("robot", scan, pavilion::core::LaserScanTruth{});
    writer.Close();
  }
  const PavilionResult no_truth =
      RunPavilion({"extract", "--log", bare, "--score", "small_lab"}, dir);
  EXPECT_EQ(no_truth.exit_code, 1);
  ASSERT_EQ(SplitLines(no_truth.err).size(), 1u) << no_truth.err;
  EXPECT_TRUE(Contains(no_truth.err, "no ground truth")) << no_truth.err;

  const fs::path scans = SmallLabScans(dir);
  const PavilionResult wrong_world =
      RunPavilion({"extract", "--log", scans.string(), "--score", "office_floor"}, dir);
  EXPECT_EQ(wrong_world.exit_code, 1);
  ASSERT_EQ(SplitLines(wrong_world.err).size(), 1u) << wrong_world.err;
  EXPECT_TRUE(Contains(wrong_world.err, "office_floor")) << wrong_world.err;

  const PavilionResult usage =
      RunPavilion({"extract", "--log", scans.string(), "--beam-height", "0.4"}, dir);
  EXPECT_EQ(usage.exit_code, 2);
  EXPECT_EQ(SplitLines(usage.err).size(), 1u) << usage.err;
}

}  // namespace
