// `pavilion test` (issue 17): scenarios as parallel processes, one summary and
// one JUnit file; a crashed run is a JUnit <error> with its stderr tail.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <string>
#include <vector>

#include "scenarios/batch/test_suite.h"
#include "tests/support/run_pavilion.h"
#include "tests/support/test_files.h"

namespace {

namespace fs = std::filesystem;
using pavilion::testing::Contains;
using pavilion::testing::ReadTextFile;
using pavilion::testing::RunPavilion;
using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

const std::string kWorld = pavilion::testing::WalledRoomWorld("suite_room");

// A Robox driving 0.3 m/s for 2 s, with one expectation.
void Scenario(const fs::path& dir, const std::string& name, const std::string& expect) {
  WriteFile(dir, name + ".yaml",
            "kind: scenario\n"
            "name: " +
                name +
                "\n"
                "duration_s: 2\n"
                "world: ../world.yaml\n"
                "robots:\n"
                "  - {id: r1, model: robox, pose: [0, 0, 0],\n"
                "     drive: [{at_s: 0, speed_mps: 0.3, turn_radps: 0.0}]}\n"
                "expect:\n  - " +
                expect + "\n");
}

fs::path Suite(const fs::path& dir) {
  WriteFile(dir, "world.yaml", kWorld);
  const fs::path suite = dir / "suite";
  fs::create_directories(suite);
  Scenario(suite, "a_moves", "robots.r1.distance_m > 0.4");
  Scenario(suite, "b_too_far", "robots.r1.distance_m < 0.1");
  Scenario(suite, "c_crashes", "robots.r1.distance_m > 0.4");
  return suite;
}

// A stand-in for the binary: the real one, except that it dies of SIGSEGV
// after a last word when given the scenario c_crashes.
std::string CrashingPavilion(const fs::path& dir) {
  const std::string path = WriteFile(dir, "pavilion.sh",
                                     "#!/bin/sh\n"
                                     "case \"$2\" in *c_crashes*) echo 'segfault ahead' >&2; "
                                     "kill -SEGV $$;; esac\n"
                                     "exec '" PAVILION_BINARY "' \"$@\"\n");
  chmod(path.c_str(), 0755);
  return path;
}

TEST(TestSuiteTest, PassFailAndCrashInOneJUnitFile) {
  const fs::path dir = TestDir();
  const fs::path suite = Suite(dir);
  pavilion::scenarios::TestSuiteOptions options;
  options.out_dir = (dir / "out").string();
  options.jobs = 2;
  options.junit = (dir / "junit.xml").string();
  options.executable = CrashingPavilion(dir);
  const auto files = pavilion::scenarios::CollectScenarioFiles({suite.string()});
  ASSERT_EQ(files.size(), 3u);
  const auto result = pavilion::scenarios::RunTestSuite(files, options);
  ASSERT_EQ(result.runs.size(), 3u);
  EXPECT_FALSE(result.passed());
  EXPECT_EQ(result.runs[0].exit_code, 0);
  EXPECT_TRUE(result.runs[0].suite.results.passed());
  EXPECT_EQ(result.runs[1].exit_code, 3);
  EXPECT_EQ(result.runs[1].suite.results.failures(), 1);
  EXPECT_EQ(result.runs[2].suite.error, "killed by signal 11");
  const std::string xml = ReadTextFile(dir / "junit.xml");
  EXPECT_TRUE(Contains(xml, "tests=\"3\" failures=\"1\" errors=\"1\"")) << xml;
  EXPECT_TRUE(Contains(xml, "<error message=\"killed by signal 11\">segfault ahead")) << xml;
  EXPECT_TRUE(Contains(xml, "name=\"robots.r1.distance_m &lt; 0.1\"")) << xml;
  const std::string table = pavilion::scenarios::FormatTestSummary(result);
  EXPECT_TRUE(Contains(table, "1 of 3 scenarios passed")) << table;
  EXPECT_TRUE(Contains(table, "measured 0.5")) << table;
}

TEST(TestCommandTest, ExitCodes) {
  const fs::path dir = TestDir();
  const fs::path suite = Suite(dir);
  fs::remove(suite / "c_crashes.yaml");
  const auto some_fail =
      RunPavilion({"test", suite.string(), "--jobs", "2", "--out", (dir / "out").string()}, dir);
  EXPECT_EQ(some_fail.exit_code, 3) << some_fail.err;
  EXPECT_TRUE(Contains(some_fail.out, "1 of 2 scenarios passed")) << some_fail.out;
  const auto all_pass = RunPavilion(
      {"test", (suite / "a_moves.yaml").string(), "--out", (dir / "out2").string()}, dir);
  EXPECT_EQ(all_pass.exit_code, 0) << all_pass.err;
  // A scenario that does not load: nothing runs, exit 1 naming the file.
  WriteFile(suite, "d_bad.yaml", "kind: scenario\nname: bad\nduration_s: -1\n");
  const auto bad = RunPavilion({"test", suite.string(), "--out", (dir / "out3").string()}, dir);
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_TRUE(Contains(bad.err, "d_bad.yaml")) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "out3" / "a_moves" / "metrics.json"));
}

}  // namespace
