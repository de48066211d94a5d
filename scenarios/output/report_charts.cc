#include "scenarios/output/report_charts.h"

#include <algorithm>
#include <map>

#include "scenarios/metrics/run_metrics.h"
#include "scenarios/output/chart_js.h"

namespace pavilion::scenarios {
namespace {

// Time axes switch to minutes past this run length, to hours past the next.
constexpr double kMinutesFromS = 600.0;
constexpr double kHoursFromS = 3.0 * 3600.0;
// Decimals the embedded data keeps (the line files' own: mm, ms).
constexpr int kDataDecimals = 6;
// Marker sizes, px.
constexpr double kTimelineMarkerPx = 3.5;
constexpr double kMapMarkerPx = 6.0;
// The localization chart starts on a logarithmic axis when the largest error
// exceeds this many times the median 2 sigma.
constexpr double kLogAxisRatio = 10.0;

// Tableau 10: lanes without a colour of their own, by their index.
constexpr const char* kPalette[] = {"#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#59a14f",
                                    "#edc948", "#b07aa1", "#ff9da7", "#9c755f", "#bab0ac"};

// The colours of the kinds of event a reader looks for first.
const std::map<std::string, std::string>& LaneColours() {
  static const std::map<std::string, std::string> colours{
      {"collision: visible wall or exhibit", "#e15759"},
      {"collision: invisible object", "#9c755f"},
      {"collision: visitor", "#f28e2b"},
      {"collision: robot", "#b07aa1"},
      {"collision", "#e15759"},
      {"lost", "#222222"},
      {"relocalized", "#59a14f"},
      {"localized", "#8cd17d"},
      {"hypotheses", "#76b7b2"},
      {"kidnap", "#4e79a7"},
      {"push", "#edc948"},
      {"mission_aborted", "#d37295"},
  };
  return colours;
}

std::string LaneColour(const std::string& label, std::size_t index) {
  const auto it = LaneColours().find(label);
  return it != LaneColours().end() ? it->second
                                   : kPalette[index % (sizeof kPalette / sizeof *kPalette)];
}

// A series as chart points, time in `unit`; `y` replaces the values when given.
std::vector<std::array<double, 3>> Points(const SeriesDecimator& series, const TimeUnit& unit,
                                          std::optional<double> y = std::nullopt) {
  std::vector<std::array<double, 3>> out;
  for (const SeriesPoint& p : series.points()) {
    out.push_back({RoundForJson(p.t / unit.seconds, kDataDecimals),
                   y ? *y : RoundForJson(p.value, kDataDecimals), 0.0});
  }
  return out;
}

ChartDataset Line(std::string label, std::string color, std::vector<std::array<double, 3>> points,
                  bool stepped = false) {
  return {std::move(label), std::move(color), std::move(points), true, stepped, 0.0};
}

const char* KindName(ChartSpec::Kind kind) {
  switch (kind) {
    case ChartSpec::Kind::kLine:
      return "line";
    case ChartSpec::Kind::kTimeline:
      return "timeline";
    case ChartSpec::Kind::kMap:
      return "map";
  }
  return "line";
}

nlohmann::json ToJson(const ChartSpec& c) {
  nlohmann::json datasets = nlohmann::json::array();
  for (const ChartDataset& d : c.datasets) {
    nlohmann::json points = nlohmann::json::array();
    for (const auto& p : d.points) {
      points.push_back(c.kind == ChartSpec::Kind::kMap ? nlohmann::json{p[0], p[1], p[2]}
                                                       : nlohmann::json{p[0], p[1]});
    }
    datasets.push_back({{"label", d.label},
                        {"color", d.color},
                        {"points", std::move(points)},
                        {"line", d.line},
                        {"stepped", d.stepped},
                        {"radius", d.radius_px}});
  }
  nlohmann::json j{{"id", c.id},           {"kind", KindName(c.kind)},
                   {"x_label", c.x_label}, {"y_label", c.y_label},
                   {"x_unit", c.x_unit},   {"datasets", datasets},
                   {"lanes", c.lanes},     {"background", c.background_image_id},
                   {"counts", c.counts},   {"log_y", c.log_y}};
  if (c.x_max) j["x_max"] = *c.x_max;
  if (c.extent) {
    j["extent"] = {c.extent->min_x_m, c.extent->min_y_m, c.extent->max_x_m, c.extent->max_y_m};
  }
  return j;
}

ChartSpec TimeChart(const TimeUnit& unit, const std::string& id, std::string y_label) {
  ChartSpec c;
  c.id = id;
  c.x_label = "simulated time (" + unit.name + ")";
  c.y_label = std::move(y_label);
  c.x_unit = unit.name;
  if (unit.end > 0.0) c.x_max = unit.end;
  return c;
}

// The median of a series' positive values (0 when none).
double PositiveMedian(const SeriesDecimator& s) {
  std::vector<double> v;
  for (const SeriesPoint& p : s.points()) {
    if (p.value > 0.0) v.push_back(p.value);
  }
  if (v.empty()) return 0.0;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  return v[v.size() / 2];
}

// The largest value of a series (0 when empty).
double Largest(const SeriesDecimator& s) {
  double m = 0.0;
  for (const SeriesPoint& p : s.points()) m = std::max(m, p.value);
  return m;
}

// Draws every chart of the page's data once the page and its images loaded.
constexpr const char* kDrawChartsJs = R"JS(
(function () {
  'use strict';
  const data = JSON.parse(document.getElementById('pavilion-chart-data').textContent);
  const nice = (v) => {
    if (v === 0) return '0';
    if (Math.abs(v) >= 1000) return Math.round(v).toLocaleString('en-US');
    return String(Number(v.toPrecision(3)));
  };
  // The top-down picture under a map's markers, stretched to the axes' ranges.
  const background = {
    id: 'pavilionBackground',
    beforeDatasetsDraw(chart, args, options) {
      const img = options.image ? document.getElementById(options.image) : null;
      if (!img || !img.complete || !img.naturalWidth) return;
      const a = chart.chartArea;
      chart.ctx.drawImage(img, a.left, a.top, a.right - a.left, a.bottom - a.top);
    }
  };
  const axis = (title) => ({ type: 'linear', title: { display: title !== '', text: title } });
  function tooltip(spec, c) {
    const r = c.raw;
    if (spec.kind === 'timeline') return spec.lanes[r.y] + ' at ' + nice(r.x) + ' ' + spec.x_unit;
    if (spec.kind === 'map') {
      return c.dataset.label + ' at ' + nice(r.t) + ' s, (' + nice(r.x) + ', ' + nice(r.y) + ') m';
    }
    return c.dataset.label + ': ' + nice(r.y) + ' at ' + nice(r.x) + ' ' + spec.x_unit;
  }
  function draw(spec) {
    const canvas = document.getElementById(spec.id);
    const width = canvas.parentElement.clientWidth || 900;
    const x = axis(spec.x_label);
    const y = axis(spec.y_label);
    let aspect = 2.6;
    if (spec.x_max !== undefined) Object.assign(x, { min: 0, max: spec.x_max });
    if (spec.kind === 'line') y.beginAtZero = true;
    if (spec.counts) y.ticks = { precision: 0 };
    if (spec.kind === 'line') {
      // Logarithmic axes label the powers of ten only, in people's numbers.
      y.ticks = Object.assign(y.ticks || {}, {
        callback: function (v) {
          if (this.type !== 'logarithmic') return nice(v);
          const e = Math.log10(v);
          return Math.abs(e - Math.round(e)) < 1e-9 ? nice(v) : '';
        }
      });
    }
    if (spec.log_y) y.type = 'logarithmic';
    if (spec.kind === 'timeline') {
      const n = spec.lanes.length;
      Object.assign(y, { min: -0.5, max: n - 0.5, reverse: true, grid: { offset: false },
                         afterBuildTicks: (scale) => {
                           scale.ticks = spec.lanes.map((label, i) => ({ value: i }));
                         },
                         ticks: { autoSkip: false, callback: (v) => spec.lanes[v] } });
      aspect = width / Math.max(160, 70 + 26 * n);
    }
    if (spec.kind === 'map') {
      const e = spec.extent;
      Object.assign(x, { min: e[0], max: e[2], grid: { display: false } });
      Object.assign(y, { min: e[1], max: e[3], grid: { display: false } });
      aspect = width / ((width - 70) * (e[3] - e[1]) / (e[2] - e[0]) + 100);
    }
    const datasets = spec.datasets.map((d) => ({
      label: d.label,
      data: d.points.map((p) => ({ x: p[0], y: p[1], t: p[2] })),
      borderColor: d.color, backgroundColor: d.color, showLine: d.line, stepped: d.stepped,
      pointRadius: d.radius, pointHoverRadius: d.radius + 2, borderWidth: d.line ? 1.5 : 1,
      // Markers on the picture get a white rim.
      pointBorderColor: spec.kind === 'map' ? '#ffffff' : d.color,
      pointBorderWidth: spec.kind === 'map' ? 1.5 : 1
    }));
    const chart = new Chart(canvas, {
      type: 'scatter',
      data: { datasets },
      options: {
        animation: false, parsing: false, normalized: true, responsive: true, aspectRatio: aspect,
        interaction: spec.kind === 'line' ? { mode: 'nearest', axis: 'x', intersect: false }
                                          : { mode: 'nearest', intersect: true },
        scales: { x, y },
        plugins: {
          legend: { display: spec.kind !== 'timeline' },
          tooltip: { callbacks: { label: (c) => tooltip(spec, c) } },
          pavilionBackground: { image: spec.background }
        }
      },
      plugins: [background]
    });
    if (spec.kind === 'line' && !spec.counts) scaleButton(chart, canvas);
  }
  // A button above a chart switching its y axis between linear and logarithmic.
  function scaleButton(chart, canvas) {
    const button = document.createElement('button');
    const label = () => (chart.options.scales.y.type === 'logarithmic'
                         ? 'linear y axis' : 'logarithmic y axis');
    button.type = 'button';
    button.className = 'axis-switch';
    button.textContent = label();
    button.addEventListener('click', () => {
      const y = chart.options.scales.y;
      y.type = y.type === 'logarithmic' ? 'linear' : 'logarithmic';
      chart.update();
      button.textContent = label();
    });
    canvas.parentElement.before(button);
  }
  window.addEventListener('load', () => data.charts.forEach(draw));
})();
)JS";

}  // namespace

TimeUnit TimeUnit::For(double duration_s) {
  TimeUnit u;
  if (duration_s > kHoursFromS) {
    u = {"h", 3600.0, 0.0};
  } else if (duration_s > kMinutesFromS) {
    u = {"min", 60.0, 0.0};
  }
  u.end = duration_s > 0.0 ? RoundForJson(duration_s / u.seconds, kDataDecimals) : 0.0;
  return u;
}

ChartSpec LocalizationChart(const RobotErrorSeries& s, const TimeUnit& unit,
                            const std::string& id) {
  ChartSpec c = TimeChart(unit, id, "m");
  // An error far beyond the 2-sigma bounds (a kidnap, a loss) would flatten
  // them on a linear axis.
  const double bound_m =
      std::max(PositiveMedian(s.two_sigma_frontal_m), PositiveMedian(s.two_sigma_lateral_m));
  c.log_y = bound_m > 0.0 && Largest(s.position_error_m) > kLogAxisRatio * bound_m;
  c.datasets.push_back(
      Line("true position error (m)", "#222222", Points(s.position_error_m, unit)));
  c.datasets.push_back(Line("2σ frontal (m)", "#4e79a7", Points(s.two_sigma_frontal_m, unit)));
  c.datasets.push_back(Line("2σ lateral (m)", "#e15759", Points(s.two_sigma_lateral_m, unit)));
  return c;
}

ChartSpec VisitorsChart(const SeriesDecimator& visitors, const TimeUnit& unit,
                        const std::string& id) {
  ChartSpec c = TimeChart(unit, id, "visitors");
  c.counts = true;
  c.datasets.push_back(Line("visitors present", "#f28e2b", Points(visitors, unit), true));
  return c;
}

ChartSpec MissionsChart(const EventSeries& e, const TimeUnit& unit, const std::string& id) {
  ChartSpec c = TimeChart(unit, id, "missions so far");
  c.counts = true;
  c.datasets.push_back(Line("started", "#4e79a7", Points(e.missions_started, unit), true));
  c.datasets.push_back(Line("completed", "#59a14f", Points(e.missions_completed, unit), true));
  c.datasets.push_back(Line("aborted", "#e15759", Points(e.missions_aborted, unit), true));
  return c;
}

ChartSpec TimelineChart(const EventSeries& e, const TimeUnit& unit, const std::string& id) {
  ChartSpec c = TimeChart(unit, id, "");
  c.kind = ChartSpec::Kind::kTimeline;
  for (std::size_t k = 0; k < e.lanes.size(); ++k) {
    const EventLane& lane = e.lanes[k];
    c.lanes.push_back(lane.label);
    c.datasets.push_back({lane.label, LaneColour(lane.label, k),
                          Points(lane.times, unit, static_cast<double>(k)), false, false,
                          kTimelineMarkerPx});
  }
  return c;
}

ChartSpec EventMapChart(const EventSeries& e, const PictureExtent& extent,
                        const std::string& image_id, const std::string& id) {
  ChartSpec c;
  c.kind = ChartSpec::Kind::kMap;
  c.id = id;
  c.x_label = "x (m)";
  c.y_label = "y (m)";
  c.x_unit = "m";
  c.background_image_id = image_id;
  c.extent = extent;
  for (const MapMarkers& m : e.markers) {
    std::size_t lane = 0;
    while (lane < e.lanes.size() && e.lanes[lane].label != m.label) ++lane;
    ChartDataset d{m.label, LaneColour(m.label, lane), {}, false, false, kMapMarkerPx};
    for (const MapMarkers::Marker& p : m.markers) {
      d.points.push_back({RoundForJson(p.x_m, 3), RoundForJson(p.y_m, 3), RoundForJson(p.t_s, 3)});
    }
    if (m.stride > 1) d.label += " (one in " + std::to_string(m.stride) + " shown)";
    c.datasets.push_back(std::move(d));
  }
  return c;
}

std::string ChartCanvas(const ChartSpec& chart, const std::string& description) {
  return "<div class=\"chart-box\"><canvas id=\"" + EscapeHtml(chart.id) +
         "\" role=\"img\" aria-label=\"" + EscapeHtml(description) + "\"></canvas></div>\n";
}

std::string ChartScripts(const std::vector<ChartSpec>& charts) {
  if (charts.empty()) return "";
  nlohmann::json specs = nlohmann::json::array();
  for (const ChartSpec& c : charts) specs.push_back(ToJson(c));
  return "<script type=\"application/json\" id=\"pavilion-chart-data\">" +
         JsonForScript({{"charts", specs}}) + "</script>\n" + ChartJsScriptTag() + "<script>" +
         kDrawChartsJs + "</script>\n";
}

std::string EscapeHtml(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char ch : text) {
    switch (ch) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += ch;
    }
  }
  return out;
}

std::string JsonForScript(const nlohmann::json& value) {
  // Invalid UTF-8 in a name becomes U+FFFD rather than an exception.
  const std::string text = value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  std::string out;
  out.reserve(text.size());
  for (char ch : text) {
    if (ch == '<') {
      out += "\\u003c";  // '<' occurs only inside JSON strings
    } else {
      out += ch;
    }
  }
  return out;
}

}  // namespace pavilion::scenarios
