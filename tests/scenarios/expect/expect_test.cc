// Scenario expectations (issue 17): reading and checking `expect:` before the
// run, judging metric and event expectations, and the JUnit XML.
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "scenarios/config/scenario.h"
#include "scenarios/events/event_types.h"
#include "scenarios/expect/expect_eval.h"
#include "scenarios/expect/junit.h"
#include "scenarios/expect/metrics_schema.h"
#include "scenarios/run/scenario_runner.h"
#include "tests/support/load_errors.h"
#include "tests/support/test_files.h"

namespace pavilion::scenarios {
namespace {

using Json = nlohmann::ordered_json;
using pavilion::testing::Contains;
using pavilion::testing::ExpectOneLoadError;
using pavilion::testing::TestDir;
using pavilion::testing::WriteFile;

const std::string kWorld = pavilion::testing::WalledRoomWorld("expect_room");

std::string Write(const std::string& expect) {
  const auto dir = TestDir();
  WriteFile(dir, "world.yaml", kWorld);
  return WriteFile(dir, "scenario.yaml",
                   "kind: scenario\n"
                   "name: expect_test\n"
                   "duration_s: 4\n"
                   "world: world.yaml\n"
                   "robots:\n"
                   "  - {id: r1, model: robox, pose: [0, 0, 0.3],\n"
                   "     drive: [{at_s: 0, speed_mps: 0.0, turn_radps: 0.0}]}\n"
                   "expect:\n" +
                       expect);
}

TEST(ExpectReaderTest, ReadsEveryKind) {
  const Scenario s = LoadScenarioFile(
      Write("  - robots.r1.distance_m < 0.5\n"
            "  - any: robots.*.collisions == 0\n"
            "  - never: {event: collision, with: visitor}\n"
            "  - within: {after: kidnap, motion_s: 30, event: relocalized, correct: true}\n"
            "  - events.bumper >= 0\n"));
  ASSERT_EQ(s.expectations.size(), 5u);
  const auto& m = std::get<MetricExpectation>(s.expectations[0].kind);
  EXPECT_EQ(m.path, (std::vector<std::string>{"robots", "r1", "distance_m"}));
  EXPECT_EQ(m.comparison, Comparison::kLess);
  EXPECT_DOUBLE_EQ(m.bound, 0.5);
  EXPECT_FALSE(m.any);
  EXPECT_TRUE(std::get<MetricExpectation>(s.expectations[1].kind).any);
  const auto& never = std::get<NeverExpectation>(s.expectations[2].kind);
  EXPECT_EQ(never.event.type, "collision");
  EXPECT_EQ(never.event.fields.at("with"), "visitor");
  const auto& within = std::get<WithinExpectation>(s.expectations[3].kind);
  EXPECT_EQ(within.after.type, "kidnap");
  EXPECT_EQ(within.event.fields.at("correct"), true);
  EXPECT_TRUE(within.motion_time);
  EXPECT_DOUBLE_EQ(within.limit_s, 30.0);
  EXPECT_EQ(s.expectations[3].line, 12);
}

// Paths and names are checked against the typed metrics and the run's event
// types before anything runs.
TEST(ExpectReaderTest, BadExpectationsAreOneLineErrors) {
  ExpectOneLoadError(Write("  - robots.r1.localisation.position_rmse_m < 0.05\n"), "expect[0]",
                     "robots.r1.localisation: unknown metric");
  ExpectOneLoadError(Write("  - robots.r9.distance_m < 1\n"), "expect[0]", "no robots entry 'r9'");
  ExpectOneLoadError(Write("  - robots.r1.localization < 1\n"), "expect[0]",
                     "names a section, not a figure");
  ExpectOneLoadError(Write("  - robots.r1.distance_m ~ 1\n"), "expect[0]", "OP one of");
  ExpectOneLoadError(Write("  - robots.r1.distance_m < lots\n"), "expect[0]",
                     "'lots' is not a number");
  ExpectOneLoadError(Write("  - never: {event: colision}\n"), "expect[0].never.event",
                     "unknown event 'colision'");
  ExpectOneLoadError(Write("  - never: {event: collision, with: wall}\n"), "expect[0].never.with",
                     "unknown collision class 'wall'");
  ExpectOneLoadError(Write("  - within: {after: kidnap, event: relocalized}\n"), "expect[0].within",
                     "exactly one of motion_s");
  ExpectOneLoadError(Write("  - sometimes: {event: collision}\n"), "expect[0].sometimes",
                     "unknown expectation kind");
}

// Every figure a real run writes can be named in an expectation.
void Leaves(const Json& node, const std::vector<std::string>& path,
            std::vector<std::vector<std::string>>* out) {
  if (node.is_object()) {
    for (const auto& [key, child] : node.items()) {
      std::vector<std::string> next = path;
      next.push_back(key);
      Leaves(child, next, out);
    }
  } else if (node.is_number() || node.is_boolean()) {
    out->push_back(path);
  }
}

TEST(MetricsSchemaTest, EveryFigureOfARunIsKnown) {
  const Scenario s = LoadScenarioFile(Write("  - robots.r1.distance_m < 0.5\n"));
  const auto out = TestDir() / "out";
  RunScenario(s, RunOptions{out.string(), false, 1});
  std::ifstream in(out / "metrics.json");
  const Json metrics = Json::parse(in);
  std::vector<std::vector<std::string>> leaves;
  Leaves(metrics, {}, &leaves);
  ASSERT_GT(leaves.size(), 10u);
  const MetricIds ids{{"r1"}, {}, KnownEventTypes()};
  for (const auto& path : leaves) {
    if (path[0] == "robots" && path.size() > 3 && path[2] == "estimator_counters") continue;
    EXPECT_EQ(CheckMetricPath(path, ids), "");
  }
  EXPECT_EQ(CheckMetricPath({"robots", "*", "localization", "position_rmse_m"}, ids), "");
  EXPECT_EQ(CheckMetricPath({"robots", "r1", "navigation", "missions_completed"}, ids), "");
  EXPECT_EQ(CheckMetricPath({"events", "collision"}, ids), "");
  EXPECT_NE(CheckMetricPath({"events", "crash"}, ids), "");
  EXPECT_TRUE(Contains(CheckMetricPath({"robots", "*", "relocalization", "per_kidnap", "0"}, ids),
                       "is a list"));
}

Expectation Metric(const std::string& text, std::vector<std::string> path, Comparison c,
                   double bound, bool any = false) {
  return Expectation{text, 1, MetricExpectation{std::move(path), c, bound, any}};
}

TEST(ExpectEvalTest, MetricsPassFailAndMissing) {
  const Json metrics = Json::parse(R"({"robots": {
      "a": {"collisions": 0, "localization": {"position_rmse_m": 0.03}},
      "b": {"collisions": 2}}, "events": {"collision": 2}})");
  const std::vector<Expectation> list{
      Metric("a rmse", {"robots", "a", "localization", "position_rmse_m"}, Comparison::kLess, 0.05),
      Metric("all collisions", {"robots", "*", "collisions"}, Comparison::kEqual, 0),
      Metric("any collisions", {"robots", "*", "collisions"}, Comparison::kEqual, 0, true),
      Metric("all rmse", {"robots", "*", "localization", "position_rmse_m"}, Comparison::kLess,
             0.05),
      Metric("b rmse", {"robots", "b", "localization", "position_rmse_m"}, Comparison::kLess, 0.05),
      Metric("bumpers", {"events", "bumper"}, Comparison::kEqual, 0),
  };
  const EventExpectationMonitor monitor(list, {"a", "b"});
  const ExpectationResults r = EvaluateExpectations(list, metrics, monitor);
  ASSERT_EQ(r.results.size(), list.size());
  EXPECT_EQ(r.results[0].status, ExpectationStatus::kPass);
  EXPECT_EQ(r.results[0].measured, "0.03");
  EXPECT_EQ(r.results[0].bound, "< 0.05");
  EXPECT_EQ(r.results[1].status, ExpectationStatus::kFail);
  EXPECT_TRUE(Contains(r.results[1].detail, "robots.b.collisions = 2"));
  EXPECT_EQ(r.results[2].status, ExpectationStatus::kPass);
  // Robot b does not localize: "all" cannot pass on a section the run left out.
  EXPECT_EQ(r.results[3].status, ExpectationStatus::kMissing);
  EXPECT_EQ(r.results[4].status, ExpectationStatus::kMissing);
  EXPECT_TRUE(Contains(r.results[4].detail, "robots.b.localization.position_rmse_m"));
  // An event type never emitted was counted zero times.
  EXPECT_EQ(r.results[5].status, ExpectationStatus::kPass);
  EXPECT_EQ(r.failures(), 3);
  EXPECT_FALSE(r.passed());
}

TEST(ExpectEvalTest, NeverCountsMatchingEvents) {
  EventFilter f{"collision", Json{{"with", "visitor"}}};
  const std::vector<Expectation> list{Expectation{"never", 1, NeverExpectation{f}}};
  EventExpectationMonitor monitor(list, {"r1"});
  monitor.OnEvent(1.0, "collision", Json{{"robot", "r1"}, {"with", "robot"}});
  EXPECT_EQ(monitor.Judge(0, list[0]).status, ExpectationStatus::kPass);
  monitor.OnEvent(2.5, "collision", Json{{"robot", "r1"}, {"with", "visitor"}});
  const ExpectationResult r = monitor.Judge(0, list[0]);
  EXPECT_EQ(r.status, ExpectationStatus::kFail);
  EXPECT_EQ(r.measured, "1 event");
  EXPECT_TRUE(Contains(r.detail, "at 2.5 s"));
}

// `within` pairs each anchor with the same robot's next matching event and
// counts that robot's motion time, not the clock.
TEST(ExpectEvalTest, WithinCountsEachRobotsMotionTime) {
  WithinExpectation w{EventFilter{"kidnap", Json::object()},
                      EventFilter{"relocalized", Json{{"correct", true}}}, 30.0, true};
  const std::vector<Expectation> list{Expectation{"within", 1, w}};
  EventExpectationMonitor monitor(list, {"r1", "r2"});
  monitor.OnEvent(10.0, "kidnap", Json{{"robot", "r1"}});
  monitor.OnEvent(10.0, "kidnap", Json{{"robot", "r2"}});
  // r1 moves 20 s of the next 100 s; r2 moves 40 s.
  for (int i = 0; i < 20; ++i) monitor.AddMotion(0, 1.0);
  for (int i = 0; i < 40; ++i) monitor.AddMotion(1, 1.0);
  monitor.OnEvent(110.0, "relocalized", Json{{"robot", "r2"}, {"correct", false}});
  EXPECT_EQ(monitor.Judge(0, list[0]).status, ExpectationStatus::kFail);  // r1 and r2 open
  monitor.OnEvent(110.0, "relocalized", Json{{"robot", "r1"}, {"correct", true}});
  monitor.OnEvent(111.0, "relocalized", Json{{"robot", "r2"}, {"correct", true}});
  const ExpectationResult r = monitor.Judge(0, list[0]);
  EXPECT_EQ(r.status, ExpectationStatus::kFail);
  EXPECT_EQ(r.measured, "1 of 2 (longest 20 s)");
  EXPECT_TRUE(Contains(r.detail, "r2 kidnap at 10 s: relocalized only after 40 s")) << r.detail;
}

TEST(ExpectEvalTest, WithinWithoutAnAnchorIsMissing) {
  WithinExpectation w{EventFilter{"kidnap", Json::object()},
                      EventFilter{"relocalized", Json::object()}, 30.0, false};
  const std::vector<Expectation> list{Expectation{"within", 1, w}};
  EventExpectationMonitor monitor(list, {"r1"});
  EXPECT_EQ(monitor.Judge(0, list[0]).status, ExpectationStatus::kMissing);
  monitor.OnEvent(5.0, "kidnap", Json{{"robot", "r1"}});
  monitor.OnEvent(20.0, "run_finished", Json::object());
  const ExpectationResult r = monitor.Judge(0, list[0]);
  EXPECT_EQ(r.status, ExpectationStatus::kFail);
  EXPECT_TRUE(Contains(r.detail, "before the run ended (15 s into the window)")) << r.detail;
}

TEST(JUnitTest, FailuresCarryMeasuredAndBound) {
  JUnitSuite passed{"tour", "scenarios/tour.yaml", 12.5, {}, "", ""};
  passed.results.results = {{"a < 1", ExpectationStatus::kPass, "0.5", "< 1", "", 3}};
  JUnitSuite failed{"crowd", "scenarios/crowd.yaml", 3.0, {}, "", ""};
  failed.results.results = {
      {"robots.r1.collisions == 0", ExpectationStatus::kFail, "2", "== 0", "r1 <b>", 7},
      {"robots.r1.localization.nees < 3", ExpectationStatus::kMissing, "", "< 3", "no section", 8}};
  JUnitSuite crashed{"broken", "scenarios/broken.yaml", 0.2,
                     {},       "killed by signal 9",    "last words & <more>"};
  const std::string xml = JUnitXml({passed, failed, crashed});
  EXPECT_TRUE(
      Contains(xml, "<testsuites name=\"pavilion\" tests=\"4\" failures=\"2\" errors=\"1\""));
  EXPECT_TRUE(Contains(xml, "<testsuite name=\"crowd\" tests=\"2\" failures=\"2\" errors=\"0\""));
  EXPECT_TRUE(Contains(xml, "name=\"robots.r1.collisions == 0\""));
  EXPECT_TRUE(Contains(xml, "message=\"measured 2, expected == 0\""));
  EXPECT_TRUE(Contains(xml, "scenarios/crowd.yaml:7:"));
  EXPECT_TRUE(Contains(xml, "r1 &lt;b&gt;"));
  EXPECT_TRUE(Contains(xml, "message=\"missing: no section\""));
  EXPECT_TRUE(Contains(xml, "<error message=\"killed by signal 9\">last words &amp; &lt;more&gt;"));
}

}  // namespace
}  // namespace pavilion::scenarios
