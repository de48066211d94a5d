// The sensor_fault event (issue 17's timeline): a robot's laser blacks out,
// grows noisy or sticks for a while, then recovers; the other laser goes on.
// Bad input is one line at its key.
#include "scenarios/events/sensor_fault_event.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "scenarios/config/scenario.h"
#include "scenarios/output/scan_log.h"
#include "scenarios/run/scenario_runner.h"
#include "tests/support/load_errors.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

const std::string kWorld = pavilion::testing::WalledRoomWorld("fault_room");

std::string Write(const std::string& events) {
  const auto dir = TestDir();
  WriteFile(dir, "world.yaml", kWorld);
  return WriteFile(dir, "scenario.yaml",
                   "kind: scenario\n"
                   "name: fault_test\n"
                   "seed: 3\n"
                   "duration_s: 4\n"
                   "world: world.yaml\n"
                   "robots:\n"
                   "  - {id: r1, model: robox, pose: [0, 0, 0.3],\n"
                   "     drive: [{at_s: 0, speed_mps: 0.0, turn_radps: 0.0}]}\n"
                   "events:\n" +
                       events);
}

// The robot's scans by sensor, with the run's scan log.
std::vector<ScanLogRecord> RunScans(const std::string& events) {
  const Scenario s = LoadScenarioFile(Write(events));
  const auto out = TestDir() / "out";
  RunScenario(s, RunOptions{out.string(), false, 1});
  return ReadScanLog((out / "scans.bin").string()).records;
}

bool InFault(const core::LaserScan& scan) {
  return scan.stamp_s >= 1.0 - 1e-9 && scan.stamp_s < 2.0;
}

int ValidReadings(const core::LaserScan& scan) {
  int n = 0;
  for (const core::LaserReading& r : scan.readings) n += r.valid ? 1 : 0;
  return n;
}

// A blackout of the front laser from 1 s for 1 s: its scans then have no
// valid reading, before and after they have, and the rear laser never stops.
TEST(SensorFaultEventTest, BlackoutOfOneLaser) {
  const std::vector<ScanLogRecord> scans = RunScans(
      "  - {at_s: 1, type: sensor_fault, robot: r1, sensor: front, mode: blackout, "
      "duration_s: 1}\n");
  int faulty = 0, healthy = 0;
  for (const ScanLogRecord& r : scans) {
    const bool front = r.scan.sensor_id == "front";
    if (front && InFault(r.scan)) {
      EXPECT_EQ(ValidReadings(r.scan), 0) << r.scan.stamp_s;
      ++faulty;
    } else {
      EXPECT_GT(ValidReadings(r.scan), 300) << r.scan.sensor_id << " " << r.scan.stamp_s;
      ++healthy;
    }
  }
  EXPECT_GE(faulty, 8);  // 75 Hz profile or 10 Hz: at least a handful in a second
  EXPECT_GT(healthy, faulty);
}

// Extra noise of 0.1 m: the readings' errors against the truth have a
// standard deviation near 0.1 m during the fault and near the sensor's own
// (about 1 cm) outside it.
TEST(SensorFaultEventTest, ExtraNoise) {
  const std::vector<ScanLogRecord> scans = RunScans(
      "  - {at_s: 1, type: sensor_fault, robot: r1, mode: noise, sigma_m: 0.1, duration_s: 1}\n");
  double in_sum = 0, out_sum = 0;
  long in_n = 0, out_n = 0;
  for (const ScanLogRecord& r : scans) {
    for (std::size_t i = 0; i < r.scan.readings.size(); ++i) {
      const core::LaserReading& q = r.scan.readings[i];
      if (!q.valid || r.truth.element[i] < 0) continue;
      const double e = q.range_m - r.truth.true_range_m[i];
      if (std::abs(e) > 0.5) continue;  // outliers and mixed pixels
      (InFault(r.scan) ? in_sum : out_sum) += e * e;
      ++(InFault(r.scan) ? in_n : out_n);
    }
  }
  const double in_sigma = std::sqrt(in_sum / in_n), out_sigma = std::sqrt(out_sum / out_n);
  EXPECT_NEAR(in_sigma, 0.1, 0.015);
  EXPECT_LT(out_sigma, 0.03);
}

// Stuck: every scan in the fault repeats the last one before it.
TEST(SensorFaultEventTest, StuckReadingsRepeat) {
  const std::vector<ScanLogRecord> scans = RunScans(
      "  - {at_s: 1, type: sensor_fault, robot: r1, sensor: rear, mode: stuck, duration_s: 1}\n");
  const core::LaserScan* last_good = nullptr;
  int stuck = 0;
  for (const ScanLogRecord& r : scans) {
    if (r.scan.sensor_id != "rear") continue;
    if (!InFault(r.scan)) {
      if (r.scan.stamp_s < 1.0) last_good = &r.scan;
      continue;
    }
    ASSERT_NE(last_good, nullptr);
    for (std::size_t i = 0; i < r.scan.readings.size(); ++i) {
      EXPECT_EQ(r.scan.readings[i].range_m, last_good->readings[i].range_m);
    }
    ++stuck;
  }
  EXPECT_GE(stuck, 8);
}

TEST(SensorFaultEventTest, BadInputIsAnErrorAtItsKey) {
  const auto expect_error = [](const std::string& events, const std::string& key_path,
                               const std::string& says) {
    pavilion::testing::ExpectOneLoadError(Write(events), key_path, says);
  };
  expect_error("  - {at_s: 1, type: sensor_fault, robot: r9, mode: blackout}\n", "events[0].robot",
               "no robot 'r9'");
  expect_error("  - {at_s: 1, type: sensor_fault, robot: r1, sensor: side, mode: blackout}\n",
               "events[0].sensor", "no laser 'side'");
  expect_error("  - {at_s: 1, type: sensor_fault, robot: r1, mode: smoke}\n", "events[0].mode", "");
  expect_error("  - {at_s: 1, type: sensor_fault, robot: r1, mode: blackout, duration_s: 0}\n",
               "events[0].duration_s", "");
}

}  // namespace
}  // namespace pavilion::scenarios
