// Snapshots (issue 19): a scenario's `snapshots:` pictures — a robot's camera
// and the overview — are written under snapshots/ and shown in the report,
// the cap holds, bad requests are input errors naming the key, taking
// pictures changes no other output, and `pavilion snapshot` writes one PNG.
#include "scenarios/output/camera_snapshots.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "scenarios/config/input_error.h"
#include "scenarios/config/scenario.h"
#include "scenarios/run/scenario_runner.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

namespace fs = std::filesystem;

const std::string kScenario = std::string(PAVILION_SOURCE_DIR) + "/scenarios/corridor_vision.yaml";

std::string Read(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

Scenario Load(const std::string& snapshots) {
  ScenarioOverrides o;
  o.duration_s = 2.5;
  if (!snapshots.empty()) o.assignments = {"snapshots=" + snapshots};
  return LoadScenarioFile(kScenario, o);
}

// Runs `s` into dir/name (dir: the test's TestDir(), made once per test).
fs::path RunIn(const Scenario& s, const fs::path& dir, const std::string& name) {
  const fs::path out = dir / name;
  RunScenario(s, RunOptions{out.string(), false});
  return out;
}

bool IsPng(const fs::path& path) { return Read(path).rfind("\x89PNG\r\n\x1a\n", 0) == 0; }

TEST(CameraSnapshotsTest, PicturesAreWrittenShownAndChangeNothingElse) {
  const fs::path dir = pavilion::testing::TestDir();
  const fs::path with =
      RunIn(Load("{at: [{at_s: 1, camera: pygmalion}, {at_s: 2, camera: overview}], width_px: 320, "
                 "height_px: 200}"),
            dir, "with");
  const fs::path without = RunIn(Load(""), dir, "without");
  EXPECT_TRUE(IsPng(with / "snapshots/camera_01_pygmalion_forward.png"));
  EXPECT_TRUE(IsPng(with / "snapshots/camera_02_overview.png"));
  EXPECT_FALSE(fs::exists(without / "snapshots/camera_01_pygmalion_forward.png"));
  const std::string report = Read(with / "report.html");
  EXPECT_TRUE(pavilion::testing::Contains(report, "pygmalion's camera forward, t = 1 s"));
  EXPECT_TRUE(pavilion::testing::Contains(report, "Overview, t = 2 s"));
  for (const char* f : {"localization.csv", "trajectories.csv", "events.jsonl", "metrics.json"}) {
    EXPECT_EQ(Read(with / f), Read(without / f)) << f;
  }
}

TEST(CameraSnapshotsTest, TheCapHolds) {
  const fs::path out =
      RunIn(Load("{max: 1, at: [{at_s: 1, camera: overview}, {at_s: 2, camera: pygmalion}]}"),
            pavilion::testing::TestDir(), "cap");
  EXPECT_TRUE(fs::exists(out / "snapshots/camera_01_overview.png"));
  EXPECT_FALSE(fs::exists(out / "snapshots/camera_02_pygmalion_forward.png"));
}

TEST(CameraSnapshotsTest, BadRequestsNameTheirKey) {
  try {
    Load("{at: [{at_s: 1, camera: nobody}], on: [bump]}");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    ASSERT_EQ(e.diagnostics().size(), 2u);
    EXPECT_EQ(e.diagnostics()[0].key_path, "snapshots.at[0].camera");
    EXPECT_EQ(e.diagnostics()[1].key_path, "snapshots.on[0]");
  }
  EXPECT_THROW(Load("{max: 5000}"), InputError);
}

TEST(CameraSnapshotsTest, TheCommandWritesOnePicture) {
  const fs::path dir = pavilion::testing::TestDir();
  const fs::path png = dir / "shot.png";
  const std::string ok = std::string("'") + PAVILION_BINARY + "' snapshot '" + kScenario +
                         "' --at 1 --camera pygmalion --out '" + png.string() + "' > /dev/null";
  EXPECT_EQ(std::system(ok.c_str()), 0);
  EXPECT_TRUE(IsPng(png));
  const std::string bad = std::string("'") + PAVILION_BINARY + "' snapshot '" + kScenario +
                          "' --at 1 --camera nobody > /dev/null 2>&1";
  EXPECT_EQ(WEXITSTATUS(std::system(bad.c_str())), 1);
}

}  // namespace
}  // namespace pavilion::scenarios
