// Aggregation of a sweep: the Student t quantile against tables and closed
// forms, the statistics, the flattening of metrics.json, expectation pass
// rates, sweep.json and sweep.csv.
#include "scenarios/batch/sweep_aggregate.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "scenarios/batch/sweep_html.h"
#include "tests/support/run_pavilion.h"

namespace {

using namespace pavilion::scenarios;
using Json = nlohmann::json;

// Two-sided 95 % values of printed t tables (3 decimals), and reference
// values to 15 digits (R's qt).
TEST(SweepAggregateTest, StudentTQuantileMatchesTables) {
  const std::vector<std::pair<double, double>> table = {
      {1, 12.706}, {2, 4.303},  {3, 3.182},  {4, 2.776},  {5, 2.571},  {9, 2.262},
      {10, 2.228}, {19, 2.093}, {20, 2.086}, {30, 2.042}, {60, 2.000}, {100, 1.984}};
  for (const auto& [dof, t] : table) {
    EXPECT_NEAR(StudentTQuantile(0.975, dof), t, 5e-4) << "dof " << dof;
  }
  EXPECT_NEAR(StudentTQuantile(0.975, 1), 12.7062047361747, 1e-9);
  EXPECT_NEAR(StudentTQuantile(0.975, 4), 2.77644510519779, 1e-11);
  EXPECT_NEAR(StudentTQuantile(0.975, 19), 2.09302405440831, 1e-11);
  EXPECT_NEAR(StudentTQuantile(0.975, 100), 1.98397151852355, 1e-11);
  EXPECT_NEAR(StudentTQuantile(0.95, 10), 1.812, 5e-4);  // one-sided 95 %
  EXPECT_NEAR(StudentTQuantile(0.995, 5), 4.032, 5e-4);  // two-sided 99 %
  EXPECT_NEAR(StudentTQuantile(0.9995, 1), 636.619, 5e-3);
  EXPECT_NEAR(StudentTQuantile(0.975, 1e7), 1.959964, 1e-5);  // the normal limit
  EXPECT_NEAR(StudentTQuantile(0.025, 4), -2.77644510519779, 1e-11);
  EXPECT_EQ(StudentTQuantile(0.5, 3), 0.0);
  EXPECT_THROW(StudentTQuantile(1.0, 3), std::invalid_argument);
  EXPECT_THROW(StudentTQuantile(0.9, 0), std::invalid_argument);
}

// Closed forms: Cauchy (1 dof) t = tan(pi (p - 1/2)); 2 dof t = (2p-1)/sqrt(2p(1-p)).
TEST(SweepAggregateTest, StudentTQuantileMatchesClosedForms) {
  for (const double p : {0.6, 0.75, 0.9, 0.975, 0.999, 0.2, 0.01}) {
    const double cauchy = std::tan(std::numbers::pi * (p - 0.5));
    EXPECT_NEAR(StudentTQuantile(p, 1), cauchy, 1e-10 * std::max(1.0, std::fabs(cauchy))) << p;
    const double two = (2 * p - 1) / std::sqrt(2 * p * (1 - p));
    EXPECT_NEAR(StudentTQuantile(p, 2), two, 1e-10 * std::max(1.0, std::fabs(two))) << p;
    EXPECT_NEAR(StudentTCdf(StudentTQuantile(p, 7.5), 7.5), p, 1e-12) << p;
  }
}

// I_x(a, 1) = x^a, I_x(1, b) = 1 - (1-x)^b, I_1/2(a, a) = 1/2.
TEST(SweepAggregateTest, IncompleteBetaMatchesClosedForms) {
  for (const double x : {0.01, 0.2, 0.5, 0.8, 0.99}) {
    for (const double a : {0.5, 1.0, 2.5, 10.0}) {
      EXPECT_NEAR(RegularizedIncompleteBeta(a, 1.0, x), std::pow(x, a), 1e-13);
      EXPECT_NEAR(RegularizedIncompleteBeta(1.0, a, x), 1 - std::pow(1 - x, a), 1e-13);
      EXPECT_NEAR(RegularizedIncompleteBeta(a, a, 0.5), 0.5, 1e-13);
    }
  }
  EXPECT_EQ(RegularizedIncompleteBeta(2, 3, 0.0), 0.0);
  EXPECT_EQ(RegularizedIncompleteBeta(2, 3, 1.0), 1.0);
  EXPECT_THROW(RegularizedIncompleteBeta(-1, 3, 0.5), std::invalid_argument);
}

// Mean, sample std (n-1), min, max and mean -+ t(0.975, n-1) s / sqrt(n); n = 1: no spread.
TEST(SweepAggregateTest, SummarizesValues) {
  const MetricSummary s = Summarize({1.0, 2.0, 3.0, 4.0});
  EXPECT_EQ(s.n, 4u);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  ASSERT_TRUE(s.std.has_value());
  EXPECT_NEAR(*s.std, std::sqrt(5.0 / 3.0), 1e-15);
  EXPECT_EQ(s.min, 1.0);
  EXPECT_EQ(s.max, 4.0);
  const double half = 3.18244630528371 * std::sqrt(5.0 / 3.0) / 2.0;  // qt(0.975, 3)
  EXPECT_NEAR(*s.ci95_low, 2.5 - half, 1e-12);
  EXPECT_NEAR(*s.ci95_high, 2.5 + half, 1e-12);
  const MetricSummary one = Summarize({7.0});
  EXPECT_EQ(one.n, 1u);
  EXPECT_EQ(one.mean, 7.0);
  EXPECT_FALSE(one.std.has_value());
  EXPECT_FALSE(one.ci95_low.has_value());
}

// Objects nest by key, arrays by id when every element has one, else by index;
// non-numbers and the top-level seed and schema_version are left out.
TEST(SweepAggregateTest, FlattensMetrics) {
  const Json metrics = Json::parse(R"({
    "schema_version": 1, "seed": 4, "scenario": "x", "interrupted": false,
    "sim_duration_s": 5.5,
    "robots": {"robox_1": {"distance_m": 3.25, "localization": {"anees": 2.5, "map": null}}},
    "missions": [{"id": "m1", "time_s": 10}, {"id": "m2", "time_s": 12}],
    "per_kidnap": [{"at_s": 4}, {"at_s": 9}],
    "histogram": [1, 2]})");
  const auto flat = FlattenMetrics(metrics);
  const std::map<std::string, double> expected = {{"sim_duration_s", 5.5},
                                                  {"robots.robox_1.distance_m", 3.25},
                                                  {"robots.robox_1.localization.anees", 2.5},
                                                  {"missions.m1.time_s", 10},
                                                  {"missions.m2.time_s", 12},
                                                  {"per_kidnap.0.at_s", 4},
                                                  {"per_kidnap.1.at_s", 9},
                                                  {"histogram.0", 1},
                                                  {"histogram.1", 2}};
  EXPECT_EQ(flat, expected);
}

// Two cells of two seeds; one run lacks a metric; expectations tallied per cell.
TEST(SweepAggregateTest, AggregatesCellsAndExpectations) {
  SweepSpec spec;
  spec.scenario = "/s/x.yaml";
  spec.seeds = {1, 2};
  spec.grid = {ParseGridAxis("speed=0.4,0.6")};
  const SweepPlan plan = MakeSweepPlan(spec, {});
  const auto expectations = [](bool a, const std::string& b) {
    return Json{{"passed", a && b == "pass"},
                {"results",
                 {{{"name", "rmse < 0.05"}, {"status", a ? "pass" : "fail"}, {"line", 12}},
                  {{"name", "no collision"}, {"status", b}, {"line", 13}}}}};
  };
  std::vector<RunRecord> runs = {
      {3, {{"m", 4.0}, {"k", 1.0}}, std::nullopt},
      {0, {{"m", 1.0}, {"k", 5.0}}, expectations(true, "pass")},
      {1, {{"m", 2.0}}, expectations(false, "missing")},
  };
  const SweepAggregate a = AggregateRuns(plan, runs);
  ASSERT_EQ(a.cells.size(), 2u);
  EXPECT_EQ(a.metric_names, (std::vector<std::string>{"k", "m"}));
  const CellAggregate& c0 = a.cells[0];
  EXPECT_EQ(c0.runs, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(c0.metrics.at("m").n, 2u);
  EXPECT_DOUBLE_EQ(c0.metrics.at("m").mean, 1.5);
  EXPECT_EQ(c0.metrics.at("k").n, 1u);
  EXPECT_TRUE(std::isnan(c0.values.at("k")[1]));
  EXPECT_EQ(c0.runs_with_expectations, 2);
  EXPECT_EQ(c0.runs_passed, 1);
  ASSERT_EQ(c0.expectations.size(), 2u);
  EXPECT_EQ(c0.expectations[0].pass, 1);
  EXPECT_EQ(c0.expectations[0].fail, 1);
  EXPECT_EQ(c0.expectations[1].missing, 1);
  EXPECT_EQ(a.cells[1].runs, (std::vector<std::size_t>{3}));
  EXPECT_EQ(a.cells[1].runs_with_expectations, 0);

  SweepStatus status{4, 3, {}, {"c01-s0001"}};
  const Json j = Json::parse(AggregateToJson(plan, a, status).dump());
  EXPECT_EQ(j["cells"][0]["metrics"]["m"]["n"], 2);
  EXPECT_EQ(j["cells"][0]["expectations"]["pass_rate"], 0.5);
  EXPECT_EQ(j["cells"][0]["expectations"]["by_expectation"][1]["missing"], 1);
  EXPECT_TRUE(j["cells"][1]["expectations"].is_null());
  EXPECT_TRUE(j["cells"][1]["metrics"]["m"]["ci95"].is_null());
  EXPECT_EQ(j["runs"]["not_run"][0], "c01-s0001");
  EXPECT_EQ(j["expectations"]["runs"], 2);

  const auto lines = pavilion::testing::SplitLines(AggregateToCsv(plan, a));
  ASSERT_EQ(lines.size(), 5u);  // header + 2 metrics in c00 + 2 in c01
  EXPECT_EQ(lines[0], "cell,speed,metric,n,mean,std,min,max,ci95_low,ci95_high");
  EXPECT_EQ(lines[1], "c00,0.4,k,1,5,,5,5,,");
  EXPECT_EQ(lines[2].substr(0, 18), "c00,0.4,m,2,1.5,0.");
}

// Without expectations, sweep.json says so; the page plots what changes.
TEST(SweepAggregateTest, SaysWhenNoRunHasExpectations) {
  SweepSpec spec;
  spec.scenario = "/s/x.yaml";
  spec.seeds = {1, 2, 3};
  const SweepPlan plan = MakeSweepPlan(spec, {});
  const std::vector<RunRecord> runs = {
      {0, {{"a.position_rmse_m", 0.1}, {"b.constant", 1.0}, {"c.other", 1.0}}, std::nullopt},
      {1, {{"a.position_rmse_m", 0.2}, {"b.constant", 1.0}, {"c.other", 2.0}}, std::nullopt},
      {2, {{"a.position_rmse_m", 0.3}, {"b.constant", 1.0}, {"c.other", 3.0}}, std::nullopt}};
  const SweepAggregate a = AggregateRuns(plan, runs);
  const Json j = Json::parse(AggregateToJson(plan, a, {3, 3, {}, {}}).dump());
  EXPECT_TRUE(j["expectations"].is_null());
  EXPECT_NE(j["expectations_note"].get<std::string>().find("no run wrote"), std::string::npos);
  EXPECT_EQ(KeyMetrics(a, 5), (std::vector<std::string>{"a.position_rmse_m", "c.other"}));
}

}  // namespace
