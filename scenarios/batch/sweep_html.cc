#include "scenarios/batch/sweep_html.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "scenarios/output/chart_js.h"
#include "scenarios/output/report_charts.h"
#include "scenarios/version.h"

namespace pavilion::scenarios {
namespace {

using Json = nlohmann::json;

// Plotted metrics: at most this many; without a grid, fewer (per-seed charts).
constexpr std::size_t kMaxGridCharts = 12;
constexpr std::size_t kMaxSeedCharts = 6;
// Leaf names of the key figures (../shared/docs/metrics.md), most telling first.
constexpr const char* kKeyLeafNames[] = {
    "position_rmse_m",           "heading_rmse_deg",    "anees",
    "lost_situations",           "recovered_ratio",     "missions_completed_ratio",
    "missions_completed",        "time_blocked_s",      "two_sigma_frontal_m",
    "two_sigma_lateral_m",       "position_max_m",      "nees_below_95_bound_ratio",
    "matched_lines_per_cycle",   "distance_m",          "final_odometry_error_m",
    "mean_time_to_relocalize_s", "personal_intrusions", "sim_duration_s"};

constexpr const char* kStyle =
    "body{font-family:sans-serif;max-width:1200px;margin:2em auto;padding:0 1em;color:#222}"
    "table{border-collapse:collapse;margin:1em 0}th,td{border:1px solid #ccc;padding:3px 8px;"
    "text-align:left}th{background:#f3f3f3}td.num{text-align:right;font-variant-numeric:"
    "tabular-nums}.note{color:#666;font-size:90%}.grid{display:grid;grid-template-columns:"
    "1fr 1fr;gap:1em}.chart-box{position:relative;height:300px}"
    "h2{margin-top:1.6em;border-bottom:1px solid #ddd}.fail{background:#fbe1e1}"
    ".wide{overflow-x:auto}tr.first td{border-top:2px solid #999}.grid>div{min-width:0}";

// Draws every chart of the page's JSON: per series a mean line and, where
// given, the 95 % interval as a band between its low and high datasets.
constexpr const char* kDrawChartsJs = R"JS(
(function () {
  const data = JSON.parse(document.getElementById('sweep-data').textContent);
  const palette = ['#1f77b4', '#d62728', '#2ca02c', '#ff7f0e', '#9467bd', '#8c564b',
                   '#e377c2', '#17becf'];
  for (const c of data.charts) {
    const pts = (a) => c.numeric ? a.map((y, i) => ({x: c.xs[i], y: y})) : a;
    const sets = [];
    c.series.forEach((s, k) => {
      const col = s.color || palette[k % palette.length];
      if (s.low) {
        sets.push({label: s.label + ' 95% low', band: true, data: pts(s.low), borderWidth: 0,
                   pointRadius: 0, fill: false});
        sets.push({label: s.label + ' 95% interval', band: true, data: pts(s.high),
                   borderWidth: 0, pointRadius: 0, backgroundColor: col + '33', fill: '-1'});
      }
      sets.push({label: s.label, data: pts(s.mean), borderColor: col, backgroundColor: col,
                 showLine: s.line !== false, pointRadius: s.markers === false ? 0 : 4,
                 fill: false});
    });
    new Chart(document.getElementById(c.id), {
      type: 'line',
      data: {labels: c.numeric ? undefined : c.labels, datasets: sets},
      options: {
        animation: false, maintainAspectRatio: false,
        scales: {x: {type: c.numeric ? 'linear' : 'category', title: {display: true, text: c.x_label}},
                 y: {title: {display: true, text: c.y_label}}},
        plugins: {title: {display: true, text: c.title},
                  legend: {labels: {filter: (item, d) => !d.datasets[item.datasetIndex].band}},
                  tooltip: {filter: (item) => !item.dataset.band}}
      }
    });
  }
})();
)JS";

std::string E(const std::string& text) { return EscapeHtml(text); }

// A number for people: 4 significant digits.
std::string N(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", v == 0.0 ? 0.0 : v);
  return text;
}
std::string N(const std::optional<double>& v) { return v ? N(*v) : "–"; }

Json OptionalJson(const std::optional<double>& v) { return v ? Json(*v) : Json(nullptr); }

std::string Settings(const SweepCell& cell) {
  std::string text;
  for (const auto& [key, value] : cell.settings)
    text += (text.empty() ? "" : ", ") + key + "=" + value;
  return text.empty() ? "all runs" : text;
}

bool AllNumeric(const std::vector<std::string>& values, std::vector<double>* xs) {
  for (const std::string& v : values) {
    char* end = nullptr;
    const double x = std::strtod(v.c_str(), &end);
    if (end == v.c_str() || *end != '\0' || !std::isfinite(x)) return false;
    xs->push_back(x);
  }
  return true;
}

// One chart of `metric` against the first grid key, a series per combination
// of the other keys (cells are ordered with the first key slowest).
Json GridChart(const SweepPlan& plan, const SweepAggregate& a, const std::string& metric,
               const std::string& id) {
  const GridAxis& axis = plan.spec.grid.front();
  const std::size_t per_value = plan.cells.size() / axis.values.size();
  std::vector<double> xs;
  const bool numeric = AllNumeric(axis.values, &xs);
  Json series = Json::array();
  for (std::size_t r = 0; r < per_value; ++r) {
    Json mean = Json::array(), low = Json::array(), high = Json::array();
    for (std::size_t i = 0; i < axis.values.size(); ++i) {
      const auto& m = a.cells[i * per_value + r].metrics;
      const auto it = m.find(metric);
      mean.push_back(it == m.end() ? Json(nullptr) : Json(it->second.mean));
      low.push_back(it == m.end() ? Json(nullptr) : OptionalJson(it->second.ci95_low));
      high.push_back(it == m.end() ? Json(nullptr) : OptionalJson(it->second.ci95_high));
    }
    std::string label;
    for (std::size_t k = 1; k < plan.spec.grid.size(); ++k) {
      const auto& s = plan.cells[r].settings[k];
      label += (label.empty() ? "" : ", ") + s.first + "=" + s.second;
    }
    series.push_back(
        {{"label", label.empty() ? "mean" : label}, {"mean", mean}, {"low", low}, {"high", high}});
  }
  return {{"id", id},
          {"title", metric},
          {"x_label", axis.key},
          {"y_label", "mean, 95% interval"},
          {"numeric", numeric},
          {"xs", xs},
          {"labels", axis.values},
          {"series", series}};
}

// Without a grid: each seed's value, and the mean with its interval.
Json SeedChart(const SweepPlan& plan, const CellAggregate& cell, const std::string& metric,
               const std::string& id) {
  Json labels = Json::array(), values = Json::array();
  const auto& v = cell.values.at(metric);
  for (std::size_t k = 0; k < cell.runs.size(); ++k) {
    labels.push_back("seed " + std::to_string(plan.runs[cell.runs[k]].seed));
    values.push_back(std::isnan(v[k]) ? Json(nullptr) : Json(v[k]));
  }
  const MetricSummary& s = cell.metrics.at(metric);
  const std::size_t n = cell.runs.size();
  Json series = Json::array();
  series.push_back({{"label", "run"}, {"mean", values}, {"line", false}});
  Json mean_line = {{"label", "mean"},
                    {"color", "#555555"},
                    {"markers", false},
                    {"mean", Json(std::vector<double>(n, s.mean))}};
  if (s.ci95_low) {
    mean_line["low"] = std::vector<double>(n, *s.ci95_low);
    mean_line["high"] = std::vector<double>(n, *s.ci95_high);
  }
  series.push_back(mean_line);
  return {{"id", id},         {"title", metric},  {"x_label", "run"}, {"y_label", "value"},
          {"numeric", false}, {"labels", labels}, {"series", series}};
}

void SummarySection(std::ostringstream& html, const SweepPlan& plan, const SweepStatus& status) {
  const SweepSpec& s = plan.spec;
  html << "<table>\n<tr><th>scenario</th><td>" << E(s.scenario) << "</td></tr>\n"
       << "<tr><th>seeds</th><td>" << E(SeedsText(s.seeds)) << "</td></tr>\n";
  for (const GridAxis& axis : s.grid) {
    std::string values;
    for (const std::string& v : axis.values) values += (values.empty() ? "" : ", ") + v;
    html << "<tr><th>grid</th><td>" << E(axis.key) << " = " << E(values) << "</td></tr>\n";
  }
  for (const std::string& set : s.set) html << "<tr><th>set</th><td>" << E(set) << "</td></tr>\n";
  if (s.duration_s > 0) html << "<tr><th>duration</th><td>" << N(s.duration_s) << " s</td></tr>\n";
  html << "<tr><th>runs</th><td>" << status.finished << " of " << status.planned << " finished";
  if (!status.failed.empty()) html << ", " << status.failed.size() << " failed";
  if (!status.not_run.empty()) html << ", " << status.not_run.size() << " not run";
  html << "</td></tr>\n</table>\n";
  if (!status.failed.empty()) {
    html << "<p class=\"fail\">Failed runs (see runs/&lt;id&gt;.failed/failure.txt): ";
    for (const std::string& id : status.failed) html << E(id) << " ";
    html << "</p>\n";
  }
}

// "[low, high]" of a summary that has an interval.
std::string Interval(const MetricSummary& s) {
  std::string text = "[";
  text.append(N(s.ci95_low)).append(", ").append(N(s.ci95_high)).append("]");
  return text;
}

std::string Rate(int part, int whole) {
  if (whole == 0) return "–";
  std::string text = std::to_string(part);
  text.append("/").append(std::to_string(whole)).append(" (").append(N(100.0 * part / whole));
  return text.append(" %)");
}

void ExpectationsSection(std::ostringstream& html, const SweepPlan& plan, const SweepAggregate& a) {
  html << "<h2>Expectations</h2>\n";
  if (!a.any_expectations) {
    html << "<p class=\"note\">No run wrote expectations.json: the scenario has no "
            "<code>expect:</code> block.</p>\n";
    return;
  }
  std::vector<std::pair<std::string, int>> names;  // (name, line), first seen order
  for (const CellAggregate& cell : a.cells) {
    for (const ExpectationTally& t : cell.expectations) {
      if (std::find(names.begin(), names.end(), std::pair{t.name, t.line}) == names.end()) {
        names.emplace_back(t.name, t.line);
      }
    }
  }
  html << "<table>\n<tr><th>expectation</th>";
  for (const SweepCell& cell : plan.cells) html << "<th>" << E(Settings(cell)) << "</th>";
  html << "</tr>\n<tr><th>all (run passed)</th>";
  for (const CellAggregate& cell : a.cells) {
    html << "<td class=\"num\">" << Rate(cell.runs_passed, cell.runs_with_expectations) << "</td>";
  }
  html << "</tr>\n";
  for (const auto& [name, line] : names) {
    html << "<tr><th>" << E(name) << (line > 0 ? " (line " + std::to_string(line) + ")" : "")
         << "</th>";
    for (const CellAggregate& cell : a.cells) {
      const auto it =
          std::find_if(cell.expectations.begin(), cell.expectations.end(),
                       [&](const ExpectationTally& t) { return t.name == name && t.line == line; });
      html << "<td class=\"num\">"
           << (it == cell.expectations.end()
                   ? std::string("–")
                   : Rate(it->pass, it->pass + it->fail + it->missing) +
                         (it->missing > 0 ? ", " + std::to_string(it->missing) + " missing" : ""))
           << "</td>";
    }
    html << "</tr>\n";
  }
  html << "</table>\n";
}

// The last part of a key path, with the whole path as its tooltip.
std::string ShortKey(const std::string& key) {
  std::string html = "<span title=\"";
  html.append(E(key)).append("\">").append(E(key.substr(key.rfind('.') + 1)));
  return html.append("</span>");
}

void StatisticsTable(std::ostringstream& html, const SweepPlan& plan, const SweepAggregate& a) {
  html << "<h2>Every metric</h2>\n<p class=\"note\">Per grid cell: runs (n), mean, sample "
          "standard deviation, min, max and the 95 % Student-t interval of the mean (none "
          "for n = 1). Also in sweep.csv and sweep.json.</p>\n<div class=\"wide\"><table>\n"
          "<tr><th>metric</th>";
  for (const GridAxis& axis : plan.spec.grid) html << "<th>" << ShortKey(axis.key) << "</th>";
  html << "<th>n</th><th>mean</th><th>std</th><th>min</th><th>max</th><th>95 % interval</th>"
          "</tr>\n";
  for (const std::string& metric : a.metric_names) {
    bool first = true;
    for (std::size_t c = 0; c < plan.cells.size(); ++c) {
      const auto it = a.cells[c].metrics.find(metric);
      if (it == a.cells[c].metrics.end()) continue;
      const MetricSummary& s = it->second;
      html << (first ? "<tr class=\"first\"><td>" : "<tr><td>") << (first ? E(metric) : "")
           << "</td>";
      first = false;
      for (const auto& setting : plan.cells[c].settings)
        html << "<td>" << E(setting.second) << "</td>";
      html << "<td class=\"num\">" << s.n << "</td><td class=\"num\">" << N(s.mean)
           << "</td><td class=\"num\">" << N(s.std) << "</td><td class=\"num\">" << N(s.min)
           << "</td><td class=\"num\">" << N(s.max) << "</td><td class=\"num\">"
           << (s.ci95_low ? Interval(s) : std::string("–")) << "</td></tr>\n";
    }
  }
  html << "</table></div>\n";
}

// The plotted charts' canvases and their JSON.
Json ChartsSection(std::ostringstream& html, const SweepPlan& plan, const SweepAggregate& a) {
  const bool grid = !plan.spec.grid.empty();
  const std::vector<std::string> metrics = KeyMetrics(a, grid ? kMaxGridCharts : kMaxSeedCharts);
  Json charts = Json::array();
  html << "<h2>"
       << (grid ? "Main metrics against " + E(plan.spec.grid.front().key)
                : std::string("Main metrics per seed"))
       << "</h2>\n<p class=\"note\">"
       << (grid ? "Mean over the seeds with its 95 % interval (band)."
                : "Each run's value, and the mean with its 95 % interval (band).")
       << "</p>\n<div class=\"grid\">\n";
  for (const std::string& metric : metrics) {
    const std::string id = "chart-" + std::to_string(charts.size());
    if (!grid && a.cells.front().values.count(metric) == 0) continue;
    charts.push_back(grid ? GridChart(plan, a, metric, id)
                          : SeedChart(plan, a.cells.front(), metric, id));
    html << "<div class=\"chart-box\"><canvas id=\"" << id << "\" role=\"img\" aria-label=\""
         << E(metric) << "\"></canvas></div>\n";
  }
  html << "</div>\n";
  if (charts.empty())
    html << "<p class=\"note\">No metric differs between the runs: see the table.</p>\n";
  return charts;
}

}  // namespace

std::vector<std::string> KeyMetrics(const SweepAggregate& aggregate, std::size_t max_count) {
  std::set<std::string> changing;  // differs between runs of a cell or between cells
  for (const std::string& name : aggregate.metric_names) {
    std::set<double> means;
    for (const CellAggregate& cell : aggregate.cells) {
      const auto it = cell.metrics.find(name);
      if (it == cell.metrics.end()) continue;
      means.insert(it->second.mean);
      if (it->second.max > it->second.min) changing.insert(name);
    }
    if (means.size() > 1) changing.insert(name);
  }
  std::vector<std::string> chosen;
  const auto leaf = [](const std::string& path) { return path.substr(path.rfind('.') + 1); };
  for (const char* key : kKeyLeafNames) {  // the key figures first
    for (const std::string& name : aggregate.metric_names) {
      if (chosen.size() < max_count && leaf(name) == key && changing.count(name) != 0) {
        chosen.push_back(name);
      }
    }
  }
  for (const std::string& name : aggregate.metric_names) {  // then anything that changes
    if (chosen.size() < max_count && changing.count(name) != 0 &&
        std::find(chosen.begin(), chosen.end(), name) == chosen.end()) {
      chosen.push_back(name);
    }
  }
  return chosen;
}

std::string SweepHtml(const SweepPlan& plan, const SweepAggregate& aggregate,
                      const SweepStatus& status) {
  std::ostringstream html;
  const std::string name = std::filesystem::path(plan.spec.scenario).stem().string();
  html << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>Sweep: "
       << E(name) << "</title><style>" << kStyle << "</style></head><body>\n<h1>Sweep: " << E(name)
       << "</h1>\n";
  SummarySection(html, plan, status);
  const Json charts = ChartsSection(html, plan, aggregate);
  ExpectationsSection(html, plan, aggregate);
  StatisticsTable(html, plan, aggregate);
  html << "<p class=\"note\">pavilion " << E(kVersion)
       << " · plan.json, sweep.json, sweep.csv</p>\n";
  std::string data = Json{{"charts", charts}}.dump();
  for (std::size_t at = data.find('<'); at != std::string::npos; at = data.find('<', at)) {
    data.replace(at, 1, "\\u003c");
  }
  html << "<script type=\"application/json\" id=\"sweep-data\">" << data << "</script>\n"
       << ChartJsScriptTag() << "<script>" << kDrawChartsJs << "</script>\n</body></html>\n";
  return html.str();
}

}  // namespace pavilion::scenarios
