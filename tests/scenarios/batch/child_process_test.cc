// Child processes of the batch commands: exit codes, signals, the jobs limit,
// captured output, and a clean stop on SIGINT.
#include "scenarios/batch/child_process.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/run_pavilion.h"
#include "tests/support/test_files.h"

namespace {

namespace fs = std::filesystem;
using pavilion::scenarios::ChildJob;
using pavilion::scenarios::ChildResult;
using pavilion::scenarios::RunChildren;
using pavilion::testing::ReadTextFile;
using pavilion::testing::TestDir;

// Strings joined by appending (GCC 12 warns falsely, -Wrestrict, on `"..." + string`).
template <typename... Parts>
std::string Cat(const Parts&... parts) {
  std::string text;
  (text.append(parts), ...);
  return text;
}

ChildJob Shell(const std::string& script, const fs::path& dir, const std::string& name) {
  return {{"/bin/sh", "-c", script},
          (dir / (name + ".out")).string(),
          (dir / (name + ".err")).string()};
}

// Runs the jobs; the result of each, by index.
std::map<std::size_t, ChildResult> RunAll(const std::vector<ChildJob>& jobs, int at_once,
                                          int* stopped_by = nullptr) {
  std::map<std::size_t, ChildResult> results;
  const int signal_number = RunChildren(jobs, at_once, [&](std::size_t i, const ChildResult& r) {
    EXPECT_EQ(results.count(i), 0u) << "job " << i << " reported twice";
    results[i] = r;
  });
  if (stopped_by != nullptr) *stopped_by = signal_number;
  return results;
}

// Exit codes come back per job, with stdout and stderr in their files.
TEST(ChildProcessTest, ReportsExitCodesAndCapturesOutput) {
  const fs::path dir = TestDir();
  const std::vector<ChildJob> jobs = {Shell("echo hello", dir, "a"),
                                      Shell("echo oops >&2; exit 7", dir, "b"),
                                      Shell("exit 3", dir, "c")};
  int stopped_by = -1;
  const auto results = RunAll(jobs, 2, &stopped_by);
  EXPECT_EQ(stopped_by, 0);
  ASSERT_EQ(results.size(), 3u);
  EXPECT_EQ(results.at(0).exit_code, 0);
  EXPECT_EQ(results.at(1).exit_code, 7);
  EXPECT_EQ(results.at(2).exit_code, 3);
  for (const auto& [i, r] : results) {
    EXPECT_EQ(r.signal, 0);
    EXPECT_FALSE(r.interrupted);
    EXPECT_GE(r.wall_s, 0.0);
  }
  EXPECT_EQ(ReadTextFile(dir / "a.out"), "hello\n");
  EXPECT_EQ(ReadTextFile(dir / "b.err"), "oops\n");
  EXPECT_EQ(ReadTextFile(dir / "b.out"), "");
}

// A child killed by a signal reports the signal and no exit code.
TEST(ChildProcessTest, ReportsTheSignalThatKilledAChild) {
  const fs::path dir = TestDir();
  const auto results =
      RunAll({Shell("kill -KILL $$", dir, "k"), Shell("kill -SEGV $$", dir, "s")}, 1);
  EXPECT_EQ(results.at(0).signal, SIGKILL);
  EXPECT_EQ(results.at(0).exit_code, -1);
  EXPECT_EQ(results.at(1).signal, SIGSEGV);
}

// A program that does not exist exits 127 with the reason on its stderr.
TEST(ChildProcessTest, AMissingProgramExits127) {
  const fs::path dir = TestDir();
  const auto results = RunAll({{{"/nonexistent/program"}, "", (dir / "err").string()}}, 1);
  EXPECT_EQ(results.at(0).exit_code, 127);
  EXPECT_NE(ReadTextFile(dir / "err").find("cannot start"), std::string::npos);
}

// Never more than `jobs` children at once: each child appends + at its start
// and - at its end to one file; the running count never passes the limit.
TEST(ChildProcessTest, HonoursTheJobsLimit) {
  const fs::path dir = TestDir();
  const fs::path log = dir / "log";
  for (const int limit : {1, 2}) {
    fs::remove(log);
    std::vector<ChildJob> jobs;
    for (int k = 0; k < 6; ++k) {
      jobs.push_back(
          Shell(Cat("echo + >> '", log.string(), "'; sleep 0.1; echo - >> '", log.string(), "'"),
                dir, Cat("j", std::to_string(k))));
    }
    const auto results = RunAll(jobs, limit);
    ASSERT_EQ(results.size(), 6u);
    int running = 0;
    int most = 0;
    for (const char c : ReadTextFile(log)) {
      if (c == '+') most = std::max(most, ++running);
      if (c == '-') --running;
    }
    EXPECT_EQ(running, 0);
    EXPECT_LE(most, limit) << "jobs " << limit;
    EXPECT_GE(most, 1);
  }
}

// With jobs = 2, two children run at the same time: each waits (up to 20 s) for
// the other to have started, which only ends when both run together.
TEST(ChildProcessTest, RunsJobsSideBySide) {
  const fs::path dir = TestDir();
  const auto waiter = [&](const std::string& mine, const std::string& other) {
    return Cat("touch '", (dir / mine).string(), "'; for i in $(seq 2000); do [ -e '",
               (dir / other).string(), "' ] && exit 0; sleep 0.01; done; exit 1");
  };
  const auto results =
      RunAll({Shell(waiter("a", "b"), dir, "a"), Shell(waiter("b", "a"), dir, "b")}, 2);
  EXPECT_EQ(results.at(0).exit_code, 0);
  EXPECT_EQ(results.at(1).exit_code, 0);
}

// SIGINT to this process: running children get SIGTERM, pending jobs never
// start, every job is reported as interrupted, the signal comes back, and the
// previous SIGINT handler is in place again.
TEST(ChildProcessTest, StopsCleanlyOnSigint) {
  const fs::path dir = TestDir();
  const fs::path started = dir / "started";
  struct sigaction before {};
  before.sa_handler = SIG_IGN;
  sigemptyset(&before.sa_mask);
  ASSERT_EQ(::sigaction(SIGINT, &before, nullptr), 0);
  std::vector<ChildJob> jobs;
  for (int k = 0; k < 3; ++k) {
    jobs.push_back(Shell(Cat("touch '", started.string(), std::to_string(k), "'; sleep 30"), dir,
                         Cat("s", std::to_string(k))));
  }
  std::atomic<bool> done{false};
  std::thread interrupter([&] {  // once both running children started
    while (!done && !(fs::exists(started.string() + "0") && fs::exists(started.string() + "1"))) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (!done) ::kill(::getpid(), SIGINT);
  });
  int stopped_by = 0;
  const auto results = RunAll(jobs, 2, &stopped_by);
  done = true;
  interrupter.join();
  EXPECT_EQ(stopped_by, SIGINT);
  ASSERT_EQ(results.size(), 3u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_TRUE(results.at(k).interrupted);
    EXPECT_EQ(results.at(k).signal, SIGTERM);
    EXPECT_LT(results.at(k).wall_s, 25.0);
  }
  EXPECT_TRUE(results.at(2).interrupted);
  EXPECT_EQ(results.at(2).exit_code, -1);
  EXPECT_EQ(results.at(2).signal, 0);
  EXPECT_FALSE(fs::exists(started.string() + "2"));
  struct sigaction after {};
  ASSERT_EQ(::sigaction(SIGINT, nullptr, &after), 0);
  EXPECT_EQ(after.sa_handler, SIG_IGN);
}

// A child that ignores SIGTERM is killed at a second SIGINT (or after the grace period).
TEST(ChildProcessTest, KillsAChildThatIgnoresSigterm) {
  const fs::path dir = TestDir();
  const fs::path started = dir / "started";
  const std::vector<ChildJob> jobs = {
      Shell("trap '' TERM; touch '" + started.string() + "'; sleep 30", dir, "stubborn")};
  std::thread interrupter([&] {
    while (!fs::exists(started)) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    ::kill(::getpid(), SIGINT);
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    ::kill(::getpid(), SIGINT);
  });
  int stopped_by = 0;
  const auto results = RunAll(jobs, 1, &stopped_by);
  interrupter.join();
  EXPECT_EQ(stopped_by, SIGINT);
  EXPECT_EQ(results.at(0).signal, SIGKILL);
  EXPECT_TRUE(results.at(0).interrupted);
}

// The tail of a file: its last lines, each ending in a newline.
TEST(ChildProcessTest, TailOfFileKeepsTheLastLines) {
  const fs::path dir = TestDir();
  std::string text;
  for (int k = 1; k <= 30; ++k) text += "line " + std::to_string(k) + "\n";
  pavilion::testing::WriteFile(dir, "log", text);
  pavilion::testing::WriteFile(dir, "short", "a\nb");
  EXPECT_EQ(pavilion::scenarios::TailOfFile((dir / "log").string(), 3),
            "line 28\nline 29\nline 30\n");
  EXPECT_EQ(pavilion::scenarios::TailOfFile((dir / "short").string(), 5), "a\nb\n");
  EXPECT_EQ(pavilion::scenarios::TailOfFile((dir / "short").string(), 1), "b\n");
  EXPECT_EQ(pavilion::scenarios::TailOfFile((dir / "missing").string()), "");
  std::string big(200000, 'x');
  big += "\nlast\n";
  pavilion::testing::WriteFile(dir, "big", big);
  EXPECT_EQ(pavilion::scenarios::TailOfFile((dir / "big").string(), 1), "last\n");
}

// The running executable is this test's binary.
TEST(ChildProcessTest, SelfExecutableIsThisProgram) {
  const std::string self = pavilion::scenarios::SelfExecutable();
  EXPECT_TRUE(fs::exists(self));
  EXPECT_EQ(fs::path(self).filename(), "child_process_test");
}

}  // namespace
