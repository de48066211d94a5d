// `pavilion sweep` end to end with the real binary and short office tours: the
// plan file, statistics equal to those recomputed from the run folders, resuming
// after killed and failed runs, refusing another sweep's folder, and Ctrl-C.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "tests/support/run_pavilion.h"
#include "tests/support/test_files.h"

namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;
using pavilion::testing::Contains;
using pavilion::testing::ReadTextFile;
using pavilion::testing::RunPavilion;
using pavilion::testing::TestDir;

const std::string kScenario = std::string(PAVILION_SOURCE_DIR) + "/scenarios/office_tour.yaml";
const std::string kSpeedKey = "robots.0.route.max_speed_mps";

std::vector<std::string> SweepArgs(const fs::path& out, const std::string& seeds,
                                   const std::string& duration = "3") {
  return {"sweep",  kScenario, "--seeds", seeds,   "--duration",
          duration, "--jobs",  "2",       "--out", out.string()};
}

Json ReadJson(const fs::path& path) { return Json::parse(ReadTextFile(path)); }

// The numeric leaves of a metrics.json, written here independently of the
// library: objects by key, arrays of objects with ids by id, else by index.
void Leaves(const Json& node, const std::string& path, std::map<std::string, double>* out) {
  const auto join = [&](const std::string& k) { return path.empty() ? k : path + "." + k; };
  if (node.is_number()) (*out)[path] = node.get<double>();
  if (node.is_object()) {
    for (auto it = node.begin(); it != node.end(); ++it) Leaves(*it, join(it.key()), out);
  }
  if (node.is_array()) {
    bool ids = !node.empty();
    for (const auto& e : node) ids = ids && e.is_object() && e.contains("id");
    for (std::size_t i = 0; i < node.size(); ++i) {
      const Json& e = node[i];
      Leaves(e,
             join(ids ? (e["id"].is_string() ? e["id"].get<std::string>() : e["id"].dump())
                      : std::to_string(i)),
             out);
    }
  }
}

// Plan, run folders and sweep.json/csv/html: every statistic equals the one
// recomputed from the runs' metrics.json (3 seeds: t(0.975, 2) = 4.302653).
TEST(SweepTest, WritesPlanRunsAndStatistics) {
  const fs::path dir = TestDir();
  const fs::path out = dir / "sweep";
  std::vector<std::string> args = SweepArgs(out, "1-3");
  args.insert(args.end(), {"--grid", kSpeedKey + "=0.4,0.6"});
  const auto r = RunPavilion(args, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Contains(r.out, "6 runs planned (2 cells x 3 seeds), 0 done, 6 to run"));

  const Json plan = ReadJson(out / "plan.json");
  EXPECT_EQ(plan["format"], "pavilion-sweep-plan");
  EXPECT_EQ(plan["arguments"][0], "sweep");
  ASSERT_EQ(plan["runs"].size(), 6u);
  EXPECT_EQ(plan["runs"][4]["id"], "c01-s0002");
  EXPECT_EQ(plan["runs"][4]["seed"], 2);
  EXPECT_EQ(plan["runs"][4]["overrides"][0], kSpeedKey + "=0.6");
  EXPECT_EQ(plan["cells"][1]["settings"][kSpeedKey], "0.6");

  const Json sweep = ReadJson(out / "sweep.json");
  EXPECT_EQ(sweep["runs"]["finished"], 6);
  EXPECT_TRUE(sweep["expectations"].is_null());
  const double t = 0.95 / std::sqrt(2 * 0.975 * 0.025);  // t(0.975, 2), closed form
  std::size_t checked = 0;
  for (int c = 0; c < 2; ++c) {
    std::map<std::string, std::vector<double>> values;
    for (const auto& id : plan["cells"][c]["runs"]) {
      const fs::path run = out / "runs" / id.get<std::string>();
      ASSERT_TRUE(fs::exists(run / "metrics.json")) << run;
      std::map<std::string, double> leaves;
      Leaves(ReadJson(run / "metrics.json"), "", &leaves);
      leaves.erase("seed");
      leaves.erase("schema_version");
      for (const auto& [k, v] : leaves) values[k].push_back(v);
    }
    const Json& metrics = sweep["cells"][c]["metrics"];
    EXPECT_EQ(metrics.size(), values.size());
    for (const auto& [name, v] : values) {
      ASSERT_TRUE(metrics.contains(name)) << name;
      const Json& s = metrics[name];
      const double mean = (v[0] + v[1] + v[2]) / 3.0;
      double ss = 0.0;
      for (double x : v) ss += (x - mean) * (x - mean);
      const double sd = std::sqrt(ss / 2.0);
      const double tol = 1e-9 * std::max(1.0, std::fabs(mean));
      EXPECT_EQ(s["n"], 3) << name;
      EXPECT_NEAR(s["mean"].get<double>(), mean, tol) << name;
      EXPECT_NEAR(s["std"].get<double>(), sd, tol) << name;
      EXPECT_EQ(s["min"].get<double>(), *std::min_element(v.begin(), v.end())) << name;
      EXPECT_EQ(s["max"].get<double>(), *std::max_element(v.begin(), v.end())) << name;
      EXPECT_NEAR(s["ci95"][0].get<double>(), mean - t * sd / std::sqrt(3.0), tol) << name;
      EXPECT_NEAR(s["ci95"][1].get<double>(), mean + t * sd / std::sqrt(3.0), tol) << name;
      ++checked;
    }
  }
  EXPECT_GT(checked, 40u);
  // The faster cell drives farther in the same time.
  const std::string distance = "robots.pygmalion.distance_m";
  EXPECT_GT(sweep["cells"][1]["metrics"][distance]["mean"].get<double>(),
            sweep["cells"][0]["metrics"][distance]["mean"].get<double>());
  const auto csv = pavilion::testing::SplitLines(ReadTextFile(out / "sweep.csv"));
  EXPECT_EQ(csv[0], "cell," + kSpeedKey + ",metric,n,mean,std,min,max,ci95_low,ci95_high");
  EXPECT_EQ(csv.size(), 1 + checked);
  const std::string html = ReadTextFile(out / "sweep.html");
  EXPECT_TRUE(Contains(html, "<canvas id=\"chart-0\""));
  EXPECT_TRUE(Contains(html, "Chart.js"));
}

// A rerun skips finished runs, redoes a killed one (a stale .tmp folder) and
// retries a failed one, listing its stderr tail; expectations.json files are
// counted as pass rates.
TEST(SweepTest, ResumesAfterKilledAndFailedRuns) {
  const fs::path dir = TestDir();
  const fs::path out = dir / "sweep";
  ASSERT_EQ(RunPavilion(SweepArgs(out, "1-3"), dir).exit_code, 0);
  const fs::path runs = out / "runs";
  pavilion::testing::WriteFile(runs / "c00-s0001", "kept.txt", "untouched\n");
  const std::string first_metrics = ReadTextFile(runs / "c00-s0001" / "metrics.json");
  fs::rename(runs / "c00-s0002", runs / "c00-s0002.tmp");  // killed mid-run
  fs::remove(runs / "c00-s0002.tmp" / "metrics.json");
  fs::rename(runs / "c00-s0003", runs / "c00-s0003.failed");  // failed before
  pavilion::testing::WriteFile(runs / "c00-s0003.failed", "stderr.log", "boom: it broke\n");
  pavilion::testing::WriteFile(runs / "c00-s0001", "expectations.json",
                               R"({"passed": false, "results": [{"name": "rmse < 1",)"
                               R"( "status": "fail", "measured": "2", "bound": "1", "line": 9}]})");

  const auto r = RunPavilion(SweepArgs(out, "1-3"), dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Contains(r.out, "3 runs planned (1 cell x 3 seeds), 1 done, 2 to run"));
  EXPECT_TRUE(Contains(r.out, "retrying c00-s0003, which failed before"));
  EXPECT_TRUE(Contains(r.out, "boom: it broke"));
  EXPECT_FALSE(Contains(r.out, "c00-s0001 done"));
  EXPECT_EQ(ReadTextFile(runs / "c00-s0001" / "kept.txt"), "untouched\n");
  EXPECT_EQ(ReadTextFile(runs / "c00-s0001" / "metrics.json"), first_metrics);
  for (const char* id : {"c00-s0002", "c00-s0003"}) {
    EXPECT_TRUE(fs::exists(runs / id / "metrics.json")) << id;
    EXPECT_FALSE(fs::exists(runs / (std::string(id) + ".tmp"))) << id;
    EXPECT_FALSE(fs::exists(runs / (std::string(id) + ".failed"))) << id;
  }
  const Json sweep = ReadJson(out / "sweep.json");
  EXPECT_EQ(sweep["runs"]["finished"], 3);
  const Json& e = sweep["cells"][0]["expectations"];
  EXPECT_EQ(e["runs"], 1);
  EXPECT_EQ(e["passed"], 0);
  EXPECT_EQ(e["by_expectation"][0]["name"], "rmse < 1");
  EXPECT_EQ(e["by_expectation"][0]["fail"], 1);
}

// Another sweep on the same folder is refused with one line (exit 2), as is a
// folder of runs without its plan; the same sweep with another --jobs is continued.
TEST(SweepTest, RefusesChangedArguments) {
  const fs::path dir = TestDir();
  const fs::path out = dir / "sweep";
  ASSERT_EQ(RunPavilion(SweepArgs(out, "1-2"), dir).exit_code, 0);
  const std::string plan = ReadTextFile(out / "plan.json");
  for (const auto& args : {SweepArgs(out, "1-3"), SweepArgs(out, "1-2", "4")}) {
    const auto r = RunPavilion(args, dir);
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_TRUE(Contains(r.err, "holds another sweep"));
    EXPECT_EQ(pavilion::testing::SplitLines(r.err).size(), 1u) << r.err;
  }
  std::vector<std::string> grid = SweepArgs(out, "1-2");
  grid.insert(grid.end(), {"--grid", kSpeedKey + "=0.4,0.6"});
  EXPECT_EQ(RunPavilion(grid, dir).exit_code, 2);
  std::vector<std::string> jobs = SweepArgs(out, "1-2");
  jobs[7] = "1";  // --jobs 1
  const auto again = RunPavilion(jobs, dir);
  EXPECT_EQ(again.exit_code, 0) << again.err;
  EXPECT_TRUE(Contains(again.out, "2 done, 0 to run"));
  EXPECT_EQ(ReadTextFile(out / "plan.json"), plan);
  fs::remove(out / "plan.json");  // runs without a plan: whose are they?
  const auto orphan = RunPavilion(SweepArgs(out, "1-2"), dir);
  EXPECT_EQ(orphan.exit_code, 2);
  EXPECT_TRUE(Contains(orphan.err, "no plan.json"));
}

// Bad usage exits 2, a bad scenario key exits 1, both before anything runs.
TEST(SweepTest, RejectsBadArgumentsBeforeRunning) {
  const fs::path dir = TestDir();
  const fs::path out = dir / "sweep";
  EXPECT_EQ(RunPavilion(SweepArgs(out, "3-1"), dir).exit_code, 2);
  std::vector<std::string> grid = SweepArgs(out, "1");
  grid.insert(grid.end(), {"--grid", "no_values"});
  EXPECT_EQ(RunPavilion(grid, dir).exit_code, 2);
  std::vector<std::string> set = SweepArgs(out, "1");
  set.insert(set.end(), {"--set", "robots.0.no_such_key=1"});
  const auto r = RunPavilion(set, dir);
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_TRUE(Contains(r.err, "no_such_key"));
  EXPECT_FALSE(fs::exists(out / "runs"));
}

// Starts `pavilion args...` with output in files; its pid.
pid_t Start(const std::vector<std::string>& args, const fs::path& dir) {
  std::vector<std::string> all = {PAVILION_BINARY};
  all.insert(all.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : all) argv.push_back(a.data());
  argv.push_back(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int out = ::open((dir / "bg.out").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open((dir / "bg.err").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(out, 1);
    ::dup2(err, 2);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return pid;
}

// The pid of the process whose command line contains `part`; -1 when none.
pid_t FindProcess(const std::string& part) {
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::string cmdline = ReadTextFile(entry.path() / "cmdline");
    std::replace(cmdline.begin(), cmdline.end(), '\0', ' ');
    if (cmdline.find(part) != std::string::npos) return static_cast<pid_t>(std::stoi(name));
  }
  return -1;
}

// A run killed mid-way (SIGKILL to its process) is a failure kept as
// runs/<id>.failed/ with failure.txt; the others finish, the sweep exits 1, and
// a rerun retries the killed run alone.
TEST(SweepTest, ResumesAfterARunIsKilled) {
  const fs::path dir = TestDir();
  const fs::path out = dir / "sweep";
  std::vector<std::string> args = SweepArgs(out, "1-2", "40");
  args[7] = "1";  // --jobs 1
  const pid_t pid = Start(args, dir);
  pid_t child = -1;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (child < 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    // The full path: another sweep test running beside this one (ctest -j)
    // has a c00-s0001.tmp of its own, which must not be the one killed.
    child = FindProcess((out / "runs" / "c00-s0001.tmp").string());
  }
  ASSERT_GT(child, 0);
  ::kill(child, SIGKILL);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1) << ReadTextFile(dir / "bg.err");
  EXPECT_TRUE(Contains(ReadTextFile(dir / "bg.out"), "c00-s0001 FAILED (killed by signal 9)"));
  const fs::path failed = out / "runs" / "c00-s0001.failed";
  EXPECT_TRUE(Contains(ReadTextFile(failed / "failure.txt"), "killed by signal 9"));
  EXPECT_FALSE(fs::exists(out / "runs" / "c00-s0001"));
  EXPECT_TRUE(fs::exists(out / "runs" / "c00-s0002" / "metrics.json"));
  EXPECT_EQ(ReadJson(out / "sweep.json")["runs"]["failed"][0], "c00-s0001");

  const auto r = RunPavilion(args, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(Contains(r.out, "1 done, 1 to run"));
  EXPECT_TRUE(
      Contains(r.out, "retrying c00-s0001, which failed before (run failed: killed by signal 9"));
  EXPECT_FALSE(fs::exists(failed));
  EXPECT_EQ(ReadJson(out / "sweep.json")["runs"]["finished"], 2);
}

// A second sweep on a folder in use is refused; Ctrl-C while a run is going:
// exit 130, no folder that looks like a finished run without being one, and a
// rerun finishes the sweep.
TEST(SweepTest, InterruptLeavesNoHalfRun) {
  const fs::path dir = TestDir();
  const fs::path out = dir / "sweep";
  std::vector<std::string> args = SweepArgs(out, "1-3", "40");
  args[7] = "1";  // --jobs 1
  const pid_t pid = Start(args, dir);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!fs::exists(out / "runs" / "c00-s0001.stderr.log") &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  const auto second = RunPavilion(args, dir);  // the folder is taken
  EXPECT_EQ(second.exit_code, 2);
  EXPECT_TRUE(Contains(second.err, "another `pavilion sweep` is running"));
  while (!fs::exists(out / "runs" / "c00-s0002.stderr.log") &&
         std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // into the run
  ::kill(pid, SIGINT);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130) << ReadTextFile(dir / "bg.err");
  for (const auto& entry : fs::directory_iterator(out / "runs")) {
    const std::string name = entry.path().filename().string();
    EXPECT_EQ(name.find(".tmp"), std::string::npos) << name;
    if (name.find('.') == std::string::npos) {  // looks done: must be done
      EXPECT_TRUE(fs::exists(entry.path() / "metrics.json")) << name;
      EXPECT_FALSE(ReadJson(entry.path() / "metrics.json").value("interrupted", false)) << name;
    }
  }
  EXPECT_FALSE(fs::exists(out / "runs" / "c00-s0003"));
  EXPECT_FALSE(fs::exists(out / "sweep.json"));
  const auto r = RunPavilion(args, dir);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(ReadJson(out / "sweep.json")["runs"]["finished"], 3);
}

}  // namespace
