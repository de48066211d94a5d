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

#include "tests/support/test_files.h"

namespace {

namespace fs = std::filesystem;
using pavilion::testing::Contains;
using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

std::string ReadFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// `s` quoted for /bin/sh.
std::string Quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

struct Result {
  int exit_code = -1;
  std::string out;
  std::string err;
};

// Runs `pavilion args...` with stdout and stderr captured in files of `dir`.
Result RunPavilion(const std::vector<std::string>& args, const fs::path& dir) {
  const fs::path out = dir / "stdout.txt";
  const fs::path err = dir / "stderr.txt";
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on chained `+`.
  std::string command = Quote(PAVILION_BINARY);
  for (const std::string& a : args) command.append(" ").append(Quote(a));
  command.append(" >").append(Quote(out.string()));
  command.append(" 2>").append(Quote(err.string()));
  command.append(" </dev/null");
  const int status = std::system(command.c_str());
  Result r;
  r.exit_code = status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = ReadFile(out);
  r.err = ReadFile(err);
  return r;
}

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
