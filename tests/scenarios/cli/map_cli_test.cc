// Runs the real `pavilion map derive` and `pavilion map render`: exit codes,
// outputs, and the one-line error for a bad map.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
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
using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

bool IsPng(const fs::path& path) {
  const std::string bytes = ReadFile(path);
  return bytes.size() > 8 && bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") == 0;
}

// derive writes a valid map, twice the same bytes; render draws it with and
// without the world underneath; validate accepts it.
TEST(MapCliTest, DeriveAndRenderSucceed) {
  const fs::path dir = TestDir();
  const std::string map = (dir / "lab" / "map.yaml").string();
  Result r = RunPavilion({"map", "derive", "small_lab", "--out", map}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Contains(r.out, "17 segments"));
  const std::string first = ReadFile(map);
  r = RunPavilion({"map", "derive", "small_lab", "--out", map}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(ReadFile(map), first);

  r = RunPavilion({"map", "render", map, "--png", (dir / "map.png").string()}, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(IsPng(dir / "map.png"));
  r = RunPavilion({"map", "render", map, "--png", (dir / "over.png").string(), "--world",
                   "small_lab", "--width", "300"},
                  dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(IsPng(dir / "over.png"));

  r = RunPavilion({"validate", map}, dir);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Contains(r.out, ": ok"));
}

// Noise off and a different seed are options; the exact map differs from the noisy one.
TEST(MapCliTest, DeriveOptions) {
  const fs::path dir = TestDir();
  const std::string exact = (dir / "exact.yaml").string();
  const std::string noisy = (dir / "noisy.yaml").string();
  ASSERT_EQ(
      RunPavilion({"map", "derive", "small_lab", "--out", exact, "--noise-cm", "0"}, dir).exit_code,
      0);
  ASSERT_EQ(
      RunPavilion({"map", "derive", "small_lab", "--out", noisy, "--seed", "7"}, dir).exit_code, 0);
  EXPECT_NE(ReadFile(exact), ReadFile(noisy));
  EXPECT_TRUE(Contains(ReadFile(exact), "from: [-1.9, 2.16]"));  // corner B, exact
}

// --keep-direction keeps only the lines along it: fewer segments, a valid map
// whose description records the filter.
TEST(MapCliTest, DeriveKeepDirection) {
  const fs::path dir = TestDir();
  const std::string along_x = (dir / "along_x.yaml").string();
  const Result r = RunPavilion({"map", "derive", "small_lab", "--out", along_x, "--keep-direction",
                                "0", "--tolerance-deg", "5"},
                               dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(Contains(r.out, "17 segments"));
  EXPECT_TRUE(Contains(r.out, "0 points, 0 beacons"));
  EXPECT_TRUE(
      Contains(ReadFile(along_x), "Kept only the lines within 5 deg of the direction 0 deg"));
  EXPECT_EQ(RunPavilion({"validate", along_x}, dir).exit_code, 0);
  EXPECT_EQ(RunPavilion({"map", "derive", "small_lab", "--out", along_x, "--keep-direction", "0",
                         "--tolerance-deg", "0"},
                        dir)
                .exit_code,
            2);
}

// A bad map: exit 1 and a single line naming file, line and key.
TEST(MapCliTest, BadMapFailsWithOneLine) {
  const fs::path dir = TestDir();
  const std::string map = WriteFile(dir, "bad.yaml",
                                    "kind: map\n"
                                    "name: bad\n"
                                    "beam_height: 0.5\n"
                                    "features:\n"
                                    "  - type: point\n"
                                    "    id: p\n"
                                    "    position: [0, 1]\n"
                                    "    cov: [1e-4, 0, -1e-4]\n");
  const Result r = RunPavilion({"map", "render", map, "--png", (dir / "x.png").string()}, dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(Contains(r.err, map + ":8: features[0].cov: covariance is not positive definite"));
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_FALSE(fs::exists(dir / "x.png"));

  const Result v = RunPavilion({"validate", map}, dir);
  EXPECT_EQ(v.exit_code, 1);
  EXPECT_TRUE(Contains(v.err, map + ":8: features[0].cov:"));
}

// Bad usage exits 2; an unknown world exits 1 with one line.
TEST(MapCliTest, UsageAndInputErrors) {
  const fs::path dir = TestDir();
  EXPECT_EQ(RunPavilion({"map", "derive", "small_lab"}, dir).exit_code, 2);  // no --out
  EXPECT_EQ(RunPavilion({"map"}, dir).exit_code, 2);
  EXPECT_EQ(RunPavilion({"map", "derive", "small_lab", "--out", "x.yaml", "--noise-cm", "-1"}, dir)
                .exit_code,
            2);
  const Result r =
      RunPavilion({"map", "derive", "no_such_world", "--out", (dir / "m.yaml").string()}, dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_TRUE(Contains(r.err, "cannot open file"));
  EXPECT_TRUE(Contains(RunPavilion({"map", "derive", "--help"}, dir).out, "Example"));
}

}  // namespace
