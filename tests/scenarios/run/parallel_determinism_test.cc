// Issue 7: the robots' per-tick work (scans, localization) runs on a worker
// pool, and the outputs are byte-identical for 1, 2 and 8 threads — with the
// planar laser, with Bullet, and through a push that makes scans fall back to
// Bullet while the other robots cast in parallel.
#include <gtest/gtest.h>

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/support/run_pavilion.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

namespace fs = std::filesystem;

// Six robots of both models in the expo hall among 10 walkers and a crowd of
// 40 visitors (every behaviour towards robots on), four robots localizing; a
// push tilts one robot (fallback scans) while a teleport moves another.
const char* const kScenario =
    "kind: scenario\n"
    "name: parallel_robots\n"
    "world: expo_hall\n"
    "seed: 11\n"
    "duration_s: 8\n"
    "materials:\n"
    "  visitor: {friction: 0.6, color: [0.85, 0.55, 0.35]}\n"
    "groups:\n"
    "  - id: walker\n"
    "    count: 10\n"
    "    area: [[-12.4, -1.9], [-3.9, -2.0], [11.9, -1.0], [17.3, -0.8], [17.3, 8.0],\n"
    "           [14.3, 9.0], [-1.9, 8.6], [-9.8, 8.5], [-12.9, 5.8], [-13.4, 0.5]]\n"
    "    shape: {type: cylinder, radius: 0.22, height: 1.7}\n"
    "    mass_kg: 70\n"
    "    material: visitor\n"
    "    motion: {type: random_walk, speed_mps: 0.8, mean_leg_s: 5}\n"
    "crowd:\n"
    "  present: 40\n"
    "  arrivals_per_hour: 400\n"
    "  max_present: 45\n"
    "  roam_area: [[-12.4, -1.9], [-3.9, -2.0], [11.9, -1.0], [17.3, -0.8], [17.3, 8.0],\n"
    "              [14.3, 9.0], [-1.9, 8.6], [-9.8, 8.5], [-12.9, 5.8], [-13.4, 0.5]]\n"
    "  behaviours: {curious: 0.2, crowding: 0.2, blocking: 0.1, following: 0.1, pushing: 0.2}\n"
    "robots:\n"
    "  - {id: r1, model: robox, pose: [16.3, -0.5, 1.5708], localization: {},\n"
    "     drive: [{at_s: 0, speed_mps: 0.4, turn_radps: 0.0}]}\n"
    "  - {id: r2, model: pygmalion, pose: [0.0, 3.0, 0.0], localization: {},\n"
    "     drive: [{at_s: 0, speed_mps: 0.3, turn_radps: 0.2}]}\n"
    "  - {id: r3, model: robox, pose: [-6.0, 3.0, 3.1416], localization: {},\n"
    "     drive: [{at_s: 0, speed_mps: 0.3, turn_radps: -0.1}]}\n"
    "  - {id: r4, model: pygmalion, pose: [6.0, 6.0, 0.0], localization: {},\n"
    "     drive: [{at_s: 0, speed_mps: 0.0, turn_radps: 0.5}]}\n"
    "  - {id: r5, model: robox, pose: [-10.0, 6.5, 0.0],\n"
    "     drive: [{at_s: 0, speed_mps: 0.4, turn_radps: 0.0}]}\n"
    "  - {id: r6, model: pygmalion, pose: [10.0, 2.0, 1.5708],\n"
    "     drive: [{at_s: 0, speed_mps: 0.2, turn_radps: 0.0}]}\n"
    "events:\n"
    "  - {at_s: 3, type: push, body: r5, impulse: [60, 0]}\n"
    "  - {at_s: 4, type: teleport, body: r6, pose: [8.0, 1.0, 0.0]}\n"
    "outputs:\n"
    "  trajectory_rate_hz: 10\n";

// One `pavilion run` process per run: Bullet's broadphase tree orders some
// nodes by memory address, so two multi-robot worlds built one after the
// other in one process can step differently; separate processes allocate
// alike (the CLI's determinism test relies on the same).
fs::path RunWithThreads(const fs::path& dir, const std::string& backend, int threads) {
  const fs::path out = dir / ("threads_" + std::to_string(threads));
  const pavilion::testing::PavilionResult r = pavilion::testing::RunPavilion(
      {"run", (dir / "scenario.yaml").string(), "--out", out.string(), "--set",
       "laser_backend=" + backend, "--threads", std::to_string(threads)},
      dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  const nlohmann::json perf =
      nlohmann::json::parse(pavilion::testing::ReadTextFile(out / "performance.json"));
  EXPECT_EQ(perf.at("threads").get<int>(), threads);
  return out;
}

void ExpectSameOutputs(const std::string& backend) {
  SCOPED_TRACE(backend);
  const fs::path dir = pavilion::testing::TestDir() / backend;
  fs::create_directories(dir);
  pavilion::testing::WriteFile(dir, "scenario.yaml", kScenario);
  const fs::path one = RunWithThreads(dir, backend, 1);
  const nlohmann::json metrics =
      nlohmann::json::parse(pavilion::testing::ReadTextFile(one / "metrics.json"));
  EXPECT_GT(metrics.at("robots").at("r1").at("localization").at("cycles").get<int>(), 10);
  EXPECT_GT(metrics.at("crowd").at("mean_present").get<double>(), 30.0);
  if (backend == "planar") {
    // The push tilts r5: its scans fall back to Bullet while others cast planar.
    EXPECT_GT(metrics.at("laser").at("fallback_scans").get<int>(), 0);
  }
  for (const int threads : {2, 8}) {
    const fs::path other = RunWithThreads(dir, backend, threads);
    for (const char* name : {"metrics.json", "events.jsonl", "trajectories.csv", "localization.csv",
                             "scans.bin", "report.html"}) {
      SCOPED_TRACE(std::string(name) + ", " + std::to_string(threads) + " threads");
      const std::string a = pavilion::testing::ReadTextFile(one / name);
      EXPECT_FALSE(a.empty());
      EXPECT_TRUE(a == pavilion::testing::ReadTextFile(other / name));
    }
  }
}

TEST(ParallelDeterminism, SameBytesForOneTwoAndEightThreadsWithPlanarLaser) {
  ExpectSameOutputs("planar");
}

TEST(ParallelDeterminism, SameBytesForOneTwoAndEightThreadsWithBulletLaser) {
  ExpectSameOutputs("bullet");
}

}  // namespace
}  // namespace pavilion::scenarios
