// report.html: numbers for people, the run's series read back streaming and
// bounded, the charts' data embedded safely, the expectation table, the files
// listed, and the same bytes for the same inputs.

#include "scenarios/output/report.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "scenarios/output/report_charts.h"
#include "scenarios/output/report_data.h"

namespace pavilion::scenarios {
namespace {

std::filesystem::path FreshDir(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

std::size_t Count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// localization.csv as the run writes it (the columns the report reads, and others).
void WriteLocalizationCsv(const std::filesystem::path& path, int cycles_per_robot) {
  std::ofstream out(path);
  out << "time_s,id,cycle,position_error_m,nees,two_sigma_frontal_m,two_sigma_lateral_m,state\n";
  for (int k = 0; k < cycles_per_robot; ++k) {
    for (const char* id : {"robox_2", "robox_1"}) {
      const double error = k == cycles_per_robot / 3 ? 4.5 : 0.01 + 0.001 * (k % 7);
      out << k * 0.5 << ',' << id << ',' << k << ',' << error << ",3.0,0.013,0.014,localized\n";
    }
  }
  out << "12.5,robox_1,17,not-a-number,3,0.1,0.1,localized\n";  // skipped
}

// Numbers keep three significant digits but never lose integer digits.
TEST(ReportTest, HumanNumbers) {
  EXPECT_EQ(HumanNumber(17.513708), "17.5");
  EXPECT_EQ(HumanNumber(0.0131234), "0.0131");
  EXPECT_EQ(HumanNumber(145433.2), "145,433");
  EXPECT_EQ(HumanNumber(5013.0), "5,013");
  EXPECT_EQ(HumanNumber(2.0), "2");
  EXPECT_EQ(HumanNumber(0.5), "0.5");
  EXPECT_EQ(HumanNumber(9.996), "10");
  EXPECT_EQ(HumanNumber(0.09996), "0.1");
  EXPECT_EQ(HumanNumber(-1234.7), "-1,235");
  EXPECT_EQ(HumanNumber(-0.0004), "-0.0004");
  EXPECT_EQ(HumanNumber(0.0), "0");
  EXPECT_EQ(HumanNumber(-1e-9 * 0.0), "0");
  EXPECT_EQ(HumanNumber(1.23456e-7), "1.23e-07");
  EXPECT_EQ(HumanNumber(17.513708, 5), "17.514");
  EXPECT_EQ(HumanCount(145433), "145,433");
  EXPECT_EQ(HumanCount(-1000), "-1,000");
  EXPECT_EQ(HumanCount(999), "999");
  EXPECT_EQ(HumanDistance(17.513708), "17.5 m");
  EXPECT_EQ(HumanDistance(5013.0), "5.01 km");
  EXPECT_EQ(HumanDuration(45.0), "45 s");
  EXPECT_EQ(HumanDuration(750.0), "12.5 min");
  EXPECT_EQ(HumanDuration(28.0 * 3600.0), "28 h");
}

// localization.csv is read per robot in the given order, thinned to the
// budget with the error's spike kept; bad rows are skipped.
TEST(ReportTest, ReadsLocalizationSeriesBounded) {
  const std::filesystem::path dir = FreshDir("report_localization");
  WriteLocalizationCsv(dir / "localization.csv", 30000);
  ReportSeriesOptions options;
  options.max_points = 500;
  const std::vector<RobotErrorSeries> series =
      ReadLocalizationSeries(dir / "localization.csv", {"robox_1"}, options);
  ASSERT_EQ(series.size(), 2u);
  EXPECT_EQ(series[0].robot_id, "robox_1");
  EXPECT_EQ(series[1].robot_id, "robox_2");  // not in the order: after, by id
  for (const RobotErrorSeries& s : series) {
    EXPECT_EQ(s.position_error_m.samples(), 30000);
    const std::vector<SeriesPoint> p = s.position_error_m.points();
    EXPECT_LE(p.size(), 500u);
    const auto spike =
        std::find_if(p.begin(), p.end(), [](const SeriesPoint& q) { return q.value == 4.5; });
    ASSERT_NE(spike, p.end());
    EXPECT_EQ(spike->t, 10000 * 0.5);
  }
  EXPECT_TRUE(ReadLocalizationSeries(dir / "missing.csv", {}).empty());
}

// events.jsonl: missions counted over time, a lane per kind (collisions by
// class when the record has one), markers where events happened, and a cut
// last line skipped.
TEST(ReportTest, ReadsEventSeries) {
  const std::filesystem::path dir = FreshDir("report_events");
  {
    std::ofstream out(dir / "events.jsonl");
    out << R"({"time_s":0,"type":"run_started"})"
        << "\n"
        << R"({"time_s":1.5,"type":"mission_started","robot":"r"})"
        << "\n"
        << R"({"time_s":2,"type":"collision","a":"r","b":"wall","point_m":[1,2,0.3]})"
        << "\n"
        << R"({"time_s":2.5,"type":"collision","with":"visitor","point_m":[3,4,0.3]})"
        << "\n"
        << R"({"time_s":2.6,"type":"collision","with":"wall_or_exhibit_visible","point_m":[5,6,0]})"
        << "\n"
        << R"({"time_s":3,"type":"kidnap","robot":"r","after":[7,8,0.1]})"
        << "\n"
        << R"({"time_s":4,"type":"mission_completed","robot":"r"})"
        << "\n"
        << R"({"time_s":5,"type":"lost","robot":"r"})"
        << "\n"
        << R"({"time_s":6,"type":"run_finished"})"
        << "\n"
        << R"({"time_s":6.1,"type":"coll)";
  }
  const EventSeries e = ReadEventSeries(dir / "events.jsonl");
  EXPECT_EQ(e.events, 9);
  EXPECT_EQ(e.skipped_lines, 1);
  EXPECT_EQ(e.end_s, 6.0);
  std::vector<std::string> lanes;
  for (const EventLane& l : e.lanes) lanes.push_back(l.label);
  EXPECT_EQ(lanes, (std::vector<std::string>{"collision: visible wall or exhibit",
                                             "collision: visitor", "collision", "lost", "kidnap"}));
  const std::vector<SeriesPoint> started = e.missions_started.points();
  ASSERT_EQ(started.size(), 3u);  // 0 at the start, 1 at 1.5 s, 1 at the end
  EXPECT_EQ(started[1].t, 1.5);
  EXPECT_EQ(started.back().t, 6.0);
  EXPECT_EQ(started.back().value, 1.0);
  EXPECT_EQ(e.missions_completed.points().back().value, 1.0);
  EXPECT_EQ(e.missions_aborted.points().back().value, 0.0);
  ASSERT_EQ(e.markers.size(), 4u);  // three collisions and the kidnap
  EXPECT_EQ(e.markers[1].label, "collision: visitor");
  EXPECT_EQ(e.markers[1].markers[0].x_m, 3.0);
  EXPECT_EQ(e.markers[3].markers[0].y_m, 8.0);
}

// Markers stay within their budget: every stride-th kept, the stride doubling.
TEST(ReportTest, MapMarkersBounded) {
  MapMarkers m;
  for (int i = 0; i < 100000; ++i) m.Add({static_cast<double>(i), 0.0, 0.0}, 100);
  EXPECT_LE(m.markers.size(), 100u);
  EXPECT_EQ(m.seen, 100000);
  for (std::size_t k = 0; k < m.markers.size(); ++k) {
    EXPECT_EQ(m.markers[k].t_s, static_cast<double>(k * m.stride));
  }
}

// No "</script" or "<!--" can come out of embedded JSON, and it parses back.
TEST(ReportTest, JsonForScriptEscapes) {
  const nlohmann::json value{{"name", "</script><script>alert(1)</script><!--"}};
  const std::string text = JsonForScript(value);
  EXPECT_EQ(text.find('<'), std::string::npos);
  EXPECT_EQ(nlohmann::json::parse(text), value);
}

ReportContent ContentWithSeries(const ReportSeries* series) {
  ReportContent content;
  content.topdown_png = {1, 2, 3};
  content.topdown_extent = PictureExtent{-1, -1, 10, 10};
  content.series = series;
  content.files = {"metrics.json", "snapshots/topdown_final.png"};
  return content;
}

// With series, the page carries one canvas per chart, Chart.js once, data
// whose robot ids cannot close the script, the files given and no others.
TEST(ReportTest, PageWithCharts) {
  const std::filesystem::path dir = FreshDir("report_page");
  WriteLocalizationCsv(dir / "localization.csv", 50);
  {
    std::ofstream out(dir / "events.jsonl");
    out << R"({"time_s":2,"type":"collision","with":"robot","point_m":[1,2,0.3]})"
        << "\n"
        << R"({"time_s":3,"type":"mission_started","robot":"</script>"})"
        << "\n";
  }
  const ReportSeries series = ReadReportSeries(dir, {"robox_1", "robox_2"});
  Scenario scenario;
  scenario.name = "page <test>";
  RunMetrics metrics;
  metrics.sim_duration_s = 25.0;
  ReportContent content = ContentWithSeries(&series);
  SeriesDecimator visitors;
  for (int k = 0; k <= 25; ++k) visitors.Add(k, 10 + k % 3);
  content.visitors_present = &visitors;
  const std::string html = RenderReportHtml(scenario, metrics, content);
  // Two robots, visitors, missions, timeline, map.
  EXPECT_EQ(Count(html, "<canvas"), 6u);
  EXPECT_EQ(Count(html, "id=\"pavilion-chart-data\""), 1u);
  EXPECT_EQ(Count(html, "<script"), Count(html, "</script>"));
  EXPECT_EQ(Count(html, "<script"), 3u);  // data, Chart.js, drawing
  EXPECT_NE(html.find("Pavilion run: page &lt;test&gt;"), std::string::npos);
  EXPECT_NE(html.find("<a href=\"metrics.json\">"), std::string::npos);
  EXPECT_EQ(html.find("<a href=\"scans.bin\">"), std::string::npos);
  EXPECT_NE(html.find("Visitors present"), std::string::npos);
  EXPECT_NE(html.find("collision: robot"), std::string::npos);
  EXPECT_EQ(html, RenderReportHtml(scenario, metrics, content));  // same bytes
  EXPECT_EQ(html.find("Expectations"), std::string::npos);        // none given
}

// Without series or pictures' extent: no chart and no script at all.
TEST(ReportTest, PageWithoutSeriesHasNoScripts) {
  Scenario scenario;
  RunMetrics metrics;
  ReportContent content;
  const std::string html = RenderReportHtml(scenario, metrics, content);
  EXPECT_EQ(html.find("<canvas"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_NE(html.find("performance.json"), std::string::npos);
}

// The expectation table: one row per expectation with its outcome, measured
// value and bound, and the verdict above it.
TEST(ReportTest, ExpectationTable) {
  Scenario scenario;
  RunMetrics metrics;
  ExpectationResults results;
  results.results.push_back({"robots.robox_1.localization.position_rmse_m < 0.05",
                             ExpectationStatus::kPass, "0.031", "< 0.05", "", 40});
  results.results.push_back({"never: {event: collision, with: visitor}", ExpectationStatus::kFail,
                             "2", "never", "collision at 12.5 s with visitor_3", 41});
  results.results.push_back({"robots.*.navigation.missions_completed >= 1",
                             ExpectationStatus::kMissing, "", ">= 1", "", 42});
  ReportContent content;
  content.expectations = &results;
  const std::string html = RenderReportHtml(scenario, metrics, content);
  EXPECT_NE(html.find("2 of 3 expectations failed"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"fail\">missing</td>"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"pass\">pass</td>"), std::string::npos);
  EXPECT_NE(html.find("collision at 12.5 s with visitor_3"), std::string::npos);
  ExpectationResults empty;
  content.expectations = &empty;
  EXPECT_EQ(RenderReportHtml(scenario, metrics, content).find("Expectations"), std::string::npos);
}

// The run table after Table 4.3: hours, distance, missions, cycles, lost
// situations and collisions by class, in people's numbers.
TEST(ReportTest, RunTableInPeoplesNumbers) {
  Scenario scenario;
  RunMetrics metrics;
  metrics.sim_duration_s = 100800.0;  // 28 h
  RobotMetrics robot;
  robot.id = "pygmalion";
  robot.distance_m = 5013.4;
  robot.collisions_by_class.by_class = {10, 50, 0, 0};
  LocalizationFigures l;
  l.cycles = 145433;
  robot.localization = l;
  nav::NavigationFigures n;
  n.missions_started = 724;
  n.missions_completed = 720;
  robot.navigation = n;
  metrics.robots.push_back(robot);
  const std::string html = RenderReportHtml(scenario, metrics, ReportContent{});
  for (const char* text : {"28 h", "5.01 km", "724 / 720 / 0", "145,433", ">60<",
                           "object invisible to the laser", "0.0497 m/s"}) {
    EXPECT_NE(html.find(text), std::string::npos) << text;
  }
}

}  // namespace
}  // namespace pavilion::scenarios
