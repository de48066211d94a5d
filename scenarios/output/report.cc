#include "scenarios/output/report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <sstream>

#include "scenarios/output/png.h"
#include "scenarios/output/report_run_table.h"

namespace pavilion::scenarios {
namespace {

// Crowd frame captions give whole seconds within this of one, else tenths.
constexpr double kWholeSecondS = 0.05;
// Below this magnitude HumanNumber writes an exponent.
constexpr double kSmallestFixed = 1e-4;
// Durations switch to minutes and to hours from these lengths.
constexpr double kMinutesFromS = 120.0;
constexpr double kHoursFromS = 7200.0;
// The id of the top-down picture's <img>, also the event map's background.
constexpr const char* kTopDownImageId = "topdown-picture";

// The page's look: narrow text column, tables and charts full width.
constexpr const char* kStyle =
    "body{font-family:sans-serif;max-width:1000px;margin:2em auto;padding:0 1em;color:#222}"
    "table{border-collapse:collapse;margin:1em 0}th,td{border:1px solid #ccc;padding:4px 10px;"
    "text-align:left}th{background:#f3f3f3}td.num{text-align:right}"
    "img{max-width:100%;border:1px solid #ccc}.note{color:#666;font-size:90%}"
    ".chart-box{position:relative;width:100%;margin:0.5em 0 1.5em}"
    ".verdict{font-weight:bold;padding:6px 10px;display:inline-block}"
    ".pass{background:#e3f4e1}.fail{background:#fbe1e1}"
    "h2{margin-top:1.6em;border-bottom:1px solid #ddd}"
    "table{display:block;overflow-x:auto;max-width:100%}"
    ".axis-switch{display:block;margin:0 0 0 auto;font-size:85%}";

std::string E(const std::string& s) { return EscapeHtml(s); }

std::string GroupThousands(const std::string& number) {
  const std::size_t sign = (!number.empty() && number[0] == '-') ? 1 : 0;
  const std::size_t point = std::min(number.find('.'), number.size());
  std::string out = number.substr(0, sign);
  const std::string whole = number.substr(sign, point - sign);
  for (std::size_t i = 0; i < whole.size(); ++i) {
    if (i > 0 && (whole.size() - i) % 3 == 0) out += ',';
    out += whole[i];
  }
  return out + number.substr(point);
}

std::string Fixed(double v, int decimals) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  return buf;
}

void Row(std::ostringstream& html, const std::string& name, const std::string& value) {
  html << "<tr><th>" << E(name) << "</th><td>" << E(value) << "</td></tr>\n";
}

std::string Cells(const std::vector<std::string>& cells) {
  std::string out;
  for (const std::string& c : cells) out += "<td class=\"num\">" + E(c) + "</td>";
  return out;
}

std::string Int(std::int64_t v) { return HumanCount(v); }
std::string H(double v) { return HumanNumber(v); }

void ExpectationTable(std::ostringstream& html, const ExpectationResults& e) {
  const int failed = e.failures();
  const int total = static_cast<int>(e.results.size());
  html << "<h2>Expectations</h2>\n<p class=\"verdict " << (failed == 0 ? "pass" : "fail") << "\">";
  if (failed == 0) {
    html << (total == 1 ? "The expectation passes"
                        : "All " + std::to_string(total) + " expectations pass");
  } else {
    html << failed << " of " << total << " expectation" << (total == 1 ? "" : "s") << " failed";
  }
  html << ".</p>\n<table>\n<tr><th>expectation</th><th>result</th><th>measured</th>"
          "<th>bound</th><th>detail</th><th>line</th></tr>\n";
  for (const ExpectationResult& r : e.results) {
    const bool pass = r.status == ExpectationStatus::kPass;
    html << "<tr><td><code>" << E(r.name) << "</code></td><td class=\"" << (pass ? "pass" : "fail")
         << "\">" << ToString(r.status) << "</td><td>" << E(r.measured) << "</td><td>" << E(r.bound)
         << "</td><td>" << E(r.detail) << "</td><td>" << (r.line > 0 ? std::to_string(r.line) : "")
         << "</td></tr>\n";
  }
  html << "</table>\n<p class=\"note\">The scenario's <code>expect:</code> block, evaluated on "
          "metrics.json and events.jsonl; a figure the run did not produce is missing, a "
          "failure.</p>\n";
}

void DetailsTable(std::ostringstream& html, const Scenario& scenario, const RunMetrics& m) {
  html << "<h2>Run details</h2>\n<table>\n";
  Row(html, "scenario file", scenario.source_file);
  Row(html, "world", scenario.world.name);
  Row(html, "seed", std::to_string(scenario.seed));
  Row(html, "simulated time", HumanDuration(m.sim_duration_s));
  Row(html, "physics rate", H(m.physics_rate_hz) + " Hz");
  Row(html, "pavilion version", m.pavilion_version);
  if (m.realism) {
    std::string doors;
    for (const std::string& d : m.realism->doors_opened) doors += (doors.empty() ? "" : ", ") + d;
    Row(html, "realism",
        "realistic (docs/realism.md): " + Int(m.realism->clutter_objects) + " clutter objects, " +
            Int(m.realism->carpet_squares) +
            " carpet squares, doors opened: " + (doors.empty() ? std::string("none") : doors));
  }
  if (!m.bodies.empty()) {
    Row(html, "bodies", Int(static_cast<std::int64_t>(m.bodies.size())));
    Row(html, "distance travelled by all bodies", HumanDistance(m.bodies_distance_m()));
    Row(html, "collision begins per body, summed (a body-body contact counts for both)",
        Int(m.bodies_collisions()));
  }
  html << "</table>\n";
}

void RobotTable(std::ostringstream& html, const RunMetrics& m) {
  html << "<h2>Robots</h2>\n<table>\n<tr><th>robot</th><th>model</th><th>distance (m)</th>"
          "<th>collisions</th><th>bumper presses</th><th>scans</th>"
          "<th>odometry error at the end: position (m)</th><th>heading (&deg;)</th></tr>\n";
  for (const RobotMetrics& r : m.robots) {
    html << "<tr><td>" << E(r.id) << "</td><td>" << E(r.model) << "</td>"
         << Cells({H(r.distance_m), Int(r.collisions), Int(r.bumper_presses), Int(r.scans),
                   H(r.odometry_final_position_error_m),
                   H(r.odometry_final_heading_error_rad * 180.0 / std::numbers::pi)})
         << "</tr>\n";
  }
  html << "</table>\n<p class=\"note\">Odometry: the encoder counts integrated with the "
          "robot's calibrated model from its start pose; it misses the slip of collisions "
          "and pushes.</p>\n";
}

void LocalizationTable(std::ostringstream& html, const RunMetrics& m) {
  html << "<h2>Localization</h2>\n<table>\n<tr><th>robot</th><th>cycles</th>"
          "<th>position RMSE (m)</th><th>heading RMSE (&deg;)</th><th>2&sigma; frontal "
          "(m)</th><th>2&sigma; lateral (m)</th><th>2&sigma; heading (&deg;)</th>"
          "<th>ANEES</th><th>matched lines per cycle</th><th>lost situations</th>"
          "<th>declared lost</th></tr>\n";
  for (const RobotMetrics& r : m.robots) {
    if (!r.localization) continue;
    const LocalizationFigures& l = *r.localization;
    html << "<tr><td>" << E(r.id) << "</td>"
         << Cells({Int(l.cycles), H(l.position_rmse_m), H(l.heading_rmse_deg),
                   H(l.two_sigma_frontal_m), H(l.two_sigma_lateral_m), H(l.two_sigma_heading_deg),
                   H(l.anees), H(l.matched_lines_per_cycle), Int(l.lost_situations),
                   Int(l.declared_lost_situations)})
         << "</tr>\n";
  }
  html << "</table>\n<p class=\"note\">Against ground truth, per localization cycle "
          "(localization.csv; metrics.md). A consistent filter has ANEES near 3; the "
          "thesis' Table 4.2 (laser only) gives 2&sigma; of 13.1 mm frontal, 13.5 mm "
          "lateral, 0.92&deg; and 2.73 matched lines per cycle. Lost situations: the true "
          "error beyond 0.5 m or 10&deg;, or declared; declared lost: the estimator's own "
          "transitions into lost.</p>\n";
}

void RelocalizationTable(std::ostringstream& html, const RunMetrics& m) {
  html << "<h2>Relocalization</h2>\n<table>\n<tr><th>robot</th><th>kidnaps</th>"
          "<th>recovered</th><th>lost declared within 10 s</th><th>median time to lost (s)</th>"
          "<th>median time to relocalize (s)</th><th>median distance to relocalize (m)</th>"
          "<th>false relocalizations</th><th>FBT recovered</th><th>FBT mean recovery (s)</th>"
          "<th>mean / max hypotheses</th></tr>\n";
  std::vector<std::pair<std::string, const RelocalizationFigures*>> rows;
  for (const RobotMetrics& r : m.robots) {
    if (r.relocalization) rows.emplace_back(r.id, &*r.relocalization);
    if (r.shadow && r.shadow->relocalization) {
      rows.emplace_back(r.id + " (shadow " + r.shadow->method + ")", &*r.shadow->relocalization);
    }
  }
  for (const auto& [id, figures] : rows) {
    const RelocalizationFigures& f = *figures;
    html << "<tr><td>" << E(id) << "</td>"
         << Cells({Int(f.kidnaps), Int(f.recovered) + " (" + H(f.recovered_ratio) + ")",
                   H(f.lost_declared_within_10s_ratio), H(f.median_time_to_lost_s),
                   H(f.median_time_to_relocalize_s), H(f.median_distance_to_relocalize_m),
                   Int(f.false_relocalizations), H(f.fbt_recovered_ratio), H(f.fbt_mean_recovery_s),
                   H(f.mean_hypotheses) + " / " + Int(f.max_hypotheses)})
         << "</tr>\n";
  }
  html << "</table>\n<p class=\"note\">Per kidnap (metrics.md; issue 18): recovered = declared "
          "localized within 0.2 m and 5&deg; of the truth within 30 s of motion after it; times "
          "are motion time (true speed above 0.02 m/s). False relocalization: declared localized "
          "while more than 0.5 m or 10&deg; off. FBT: Fox, Burgard &amp; Thrun (1999), within "
          "0.45 m of the truth for more than 10 s; its recovery time is simulated time.</p>\n";
}

void NavigationTable(std::ostringstream& html, const RunMetrics& m) {
  html << "<h2>Navigation</h2>\n<table>\n<tr><th>robot</th><th>missions started</th>"
          "<th>completed</th><th>aborted</th><th>mean mission (s)</th><th>mean path (m)</th>"
          "<th>min clearance (m)</th><th>time blocked (s)</th><th>replans</th>"
          "<th>hits: visible</th><th>invisible</th><th>visitor</th><th>robot</th></tr>\n";
  for (const RobotMetrics& r : m.robots) {
    if (!r.navigation) continue;
    const nav::NavigationFigures& n = *r.navigation;
    const double done = std::max(1, n.missions_completed);
    const CollisionCounts& c = r.collisions_by_class;
    html << "<tr><td>" << E(r.id) << "</td>"
         << Cells({Int(n.missions_started), Int(n.missions_completed),
                   Int(n.missions_aborted_total()), H(n.mission_time_s / done),
                   H(n.mission_path_length_m / done),
                   n.clearance_samples > 0 ? H(n.min_clearance_m) : "–", H(n.time_blocked_s),
                   Int(n.replans), Int(c.of(CollisionClass::kVisible)),
                   Int(c.of(CollisionClass::kInvisible)), Int(c.of(CollisionClass::kVisitor)),
                   Int(c.of(CollisionClass::kRobot))})
         << "</tr>\n";
  }
  html << "</table>\n<p class=\"note\">The chapter 6 navigation (docs/navigation.md): "
          "aborts by reason, band snaps and who moved into whom are in metrics.json.</p>\n";
}

// Issue 15: the fleet's nearness, deadlocks and bytes per robot.
void FleetTable(std::ostringstream& html, const RunMetrics& m) {
  html << "<h2>Fleet</h2>\n<p>Coordination " << (m.fleet->coordination ? "on" : "off")
       << "; minimum robot–robot distance "
       << (std::isfinite(m.fleet->proximity.min_distance_m)
               ? H(m.fleet->proximity.min_distance_m) + " m"
               : std::string("–"))
       << ", " << Int(m.fleet->proximity.near_misses) << " near misses, "
       << Int(m.fleet->proximity.station_conflicts) << " station conflicts.</p>\n"
       << "<table>\n<tr><th>robot</th><th>min robot distance (m)</th><th>near misses</th>"
          "<th>deadlocks detected</th><th>resolved</th><th>longest (s)</th>"
          "<th>longest still with a mission (s)</th><th>fleet replans</th><th>bytes up</th>"
          "<th>bytes down</th></tr>\n";
  for (const RobotMetrics& r : m.robots) {
    if (!r.navigation || !r.fleet) continue;
    const nav::NavigationFigures& n = *r.navigation;
    const ProximityFigures& p = r.fleet->proximity;
    html << "<tr><td>" << E(r.id) << "</td>"
         << Cells({std::isfinite(p.min_distance_m) ? H(p.min_distance_m) : "–", Int(p.near_misses),
                   Int(n.deadlocks_detected), Int(n.deadlocks_resolved), H(n.longest_deadlock_s),
                   H(n.longest_still_s), Int(n.fleet_replans), Int(r.fleet->bytes_up),
                   Int(r.fleet->bytes_down)})
         << "</tr>\n";
  }
  html << "</table>\n<p class=\"note\">Thesis §6.3.5 and §6.5 (docs/navigation.md, "
          "\"Fleet\"): near miss = hulls closer than 0.2 m (ground truth); a deadlock is a "
          "marker's virtual contour inside the robot's own hull while it stands.</p>\n";
}

void EventCountTable(std::ostringstream& html, const RunMetrics& m) {
  html << "<h2>Events</h2>\n<table>\n<tr><th>type</th><th>count</th></tr>\n";
  for (const auto& [type, n] : m.event_counts) {
    html << "<tr><td>" << E(type) << "</td>" << Cells({Int(n)}) << "</tr>\n";
  }
  html << "</table>\n";
}

// The crowd frames in one row, each with its time below; they shrink to share
// the page's width.
void CrowdStripSection(std::ostringstream& html, const RunMetrics& m,
                       const std::vector<CrowdFrame>& frames) {
  if (frames.empty()) return;
  const std::string around =
      m.robots.empty() ? std::string("the floor's centre") : E(m.robots.front().id);
  html << "<h2>The crowd around " << around << "</h2>\n"
       << "<p class=\"note\">The top-down view cropped to " << H(frames.front().size_m)
       << " m &times; " << H(frames.front().size_m) << " m around " << around
       << " at evenly spaced times of the run (snapshots/crowd_NN.png): visitors as their "
          "shoulder disc with a heading tick and their two legs cut at the section's height.</p>\n"
       << "<div style=\"display:flex;gap:6px\">\n";
  for (const CrowdFrame& f : frames) {
    const std::string caption = CrowdFrameCaption(f.time_s);
    html << "<figure style=\"flex:1 1 0;min-width:0;margin:0;text-align:center\">"
         << "<img style=\"width:100%\" alt=\"crowd at " << caption << "\" title=\"" << E(f.path)
         << "\" src=\"data:image/png;base64," << Base64(f.png) << "\">"
         << "<figcaption>" << caption << "</figcaption></figure>\n";
  }
  html << "</div>\n";
}

void DeadlockSection(std::ostringstream& html, const std::optional<DeadlockFrame>& deadlock) {
  if (!deadlock) return;
  const CrowdFrame& f = deadlock->frame;
  html << "<h2>The first overlap deadlock</h2>\n"
       << "<p class=\"note\">" << E(deadlock->robot_id)
       << " detected it: a robot's virtual contour overlapped its hull while it stood with a goal "
          "(thesis &sect;6.5). The top-down view cropped to "
       << H(f.size_m) << " m &times; " << H(f.size_m) << " m around it at "
       << CrowdFrameCaption(f.time_s) << " (" << E(f.path) << ").</p>\n"
       << "<img style=\"max-width:360px\" alt=\"first deadlock\" title=\"" << E(f.path)
       << "\" src=\"data:image/png;base64," << Base64(f.png) << "\">\n";
}

// The scenario's `snapshots:` pictures, wrapping in rows, each with its caption.
void CameraSnapshotSection(std::ostringstream& html, const std::vector<SnapshotFrame>* frames) {
  if (frames == nullptr || frames->empty()) return;
  html << "<h2>Snapshots</h2>\n"
       << "<p class=\"note\">The pictures the scenario asked for (snapshots/camera_NN_*.png): "
          "a robot's camera as its software gets it (grey levels through its lens, "
          "§2.4), or a perspective overview.</p>\n"
       << "<div style=\"display:flex;flex-wrap:wrap;gap:6px\">\n";
  for (const SnapshotFrame& f : *frames) {
    html << "<figure style=\"flex:0 1 320px;margin:0;text-align:center\">"
         << "<img style=\"width:100%\" alt=\"" << E(f.caption) << "\" title=\"" << E(f.path)
         << "\" src=\"data:image/png;base64," << Base64(f.png) << "\">"
         << "<figcaption>" << E(f.caption) << "</figcaption></figure>\n";
  }
  html << "</div>\n";
}

void HypothesisSection(std::ostringstream& html, const std::vector<HypothesisFigure>& figures) {
  for (const HypothesisFigure& f : figures) {
    html << "<h2>Location hypotheses of " << E(f.robot_id) << " after a kidnap</h2>\n"
         << "<p class=\"note\">At " << H(f.time_s)
         << " s, its largest set after a kidnap: " << f.hypotheses
         << " hypotheses (thesis Fig. 5.19), each an arrow along its heading in a 0.4 m ring "
            "with its 95 % position ellipse (magenta: the best, §5.5.2; yellow: the others); "
            "blue: the true pose.</p>\n"
         << "<img alt=\"hypotheses of " << E(f.robot_id) << "\" src=\"data:image/png;base64,"
         << Base64(f.png) << "\">\n";
  }
}

// "; 86,400 cycles drawn as 4,998 points: ..." when the series was thinned.
std::string DecimationNote(const SeriesDecimator& s, const std::string& what) {
  if (s.exact()) return "";
  return "; its " + HumanCount(s.samples()) + " " + what + " are drawn as " +
         HumanCount(static_cast<std::int64_t>(s.points().size())) +
         " points, the smallest and largest of each time bucket";
}

std::string NextChartId(const std::vector<ChartSpec>& charts) {
  return "chart-" + std::to_string(charts.size() + 1);
}

void LocalizationCharts(std::ostringstream& html, const ReportSeries& series, const TimeUnit& unit,
                        std::vector<ChartSpec>* charts) {
  for (const RobotErrorSeries& s : series.localization) {
    charts->push_back(LocalizationChart(s, unit, NextChartId(*charts)));
    html << "<h2>Localization of " << E(s.robot_id) << "</h2>\n"
         << ChartCanvas(charts->back(), "true position error and 2 sigma of " + s.robot_id)
         << "<p class=\"note\">The true position error (the estimate's distance from the true "
            "position) against two standard deviations of the estimate in the robot's frontal "
            "and lateral direction, per localization cycle (localization.csv; thesis Fig. 4.4)"
         << E(DecimationNote(s.position_error_m, "cycles")) << ".</p>\n";
  }
}

void EventCharts(std::ostringstream& html, const EventSeries& events, const TimeUnit& unit,
                 std::vector<ChartSpec>* charts) {
  if (!events.missions_started.empty()) {
    charts->push_back(MissionsChart(events, unit, NextChartId(*charts)));
    html << "<h2>Missions</h2>\n"
         << ChartCanvas(charts->back(), "missions started, completed and aborted over time")
         << "<p class=\"note\">Missions started, completed and aborted so far (events.jsonl; "
            "docs/navigation.md).</p>\n";
  }
  if (!events.lanes.empty()) {
    charts->push_back(TimelineChart(events, unit, NextChartId(*charts)));
    std::int64_t shown = 0;
    bool thinned = false;
    for (const EventLane& l : events.lanes) {
      shown += l.times.samples();
      thinned = thinned || !l.times.exact();
    }
    html << "<h2>Events over time</h2>\n"
         << ChartCanvas(charts->back(), "events over time, one lane per kind")
         << "<p class=\"note\">Every event of events.jsonl but the run's start and end and "
            "missions started or completed, one lane per kind; collisions by what was hit "
            "where the record says it. "
         << HumanCount(shown) << " events"
         << (thinned ? "; a lane with many keeps at most one per time bucket" : "") << ".</p>\n";
  }
}

void ChartSections(std::ostringstream& html, const RunMetrics& m, const ReportContent& c,
                   std::vector<ChartSpec>* charts) {
  const TimeUnit unit = TimeUnit::For(m.sim_duration_s);
  if (c.series) LocalizationCharts(html, *c.series, unit, charts);
  if (c.visitors_present && !c.visitors_present->empty()) {
    charts->push_back(VisitorsChart(*c.visitors_present, unit, NextChartId(*charts)));
    html << "<h2>Visitors present</h2>\n"
         << ChartCanvas(charts->back(), "visitors present over time")
         << "<p class=\"note\">Visitors of the crowd on the floor"
         << E(DecimationNote(*c.visitors_present, "samples")) << ".</p>\n";
  }
  if (c.series) EventCharts(html, c.series->events, unit, charts);
}

// The top-down picture; with events that have a position, drawn under them
// as a chart with the world's axes.
void TopDownSection(std::ostringstream& html, const Scenario& scenario, const ReportContent& c,
                    std::vector<ChartSpec>* charts) {
  bool markers = false;
  if (c.series && c.topdown_extent) {
    for (const MapMarkers& m : c.series->events.markers) markers = markers || !m.markers.empty();
  }
  html << "<h2>Top-down view at the end of the run</h2>\n"
       << "<p class=\"note\">Footprints in material colours; black outline: the world cut at "
       << H(scenario.outputs.section_height_m)
       << " m, what a laser at that height can meet (light blue: glass, which it cannot); "
          "red: body trajectories; blue: robots' true paths, orange: their encoder odometry; "
          "green: named places; for robots with a mission, magenta: the plan still ahead, cyan: "
          "the elastic band and its bubbles, thick green: the dynamic window's chosen arc"
       << (markers ? "; markers: events where they happened (collisions at their contact point, "
                     "kidnaps where the robot was put), see the legend"
                   : "")
       << ".</p>\n<img id=\"" << kTopDownImageId << "\" alt=\"top-down view\""
       << (markers ? " hidden" : "") << " src=\"data:image/png;base64," << Base64(c.topdown_png)
       << "\">\n";
  if (!markers) return;
  charts->push_back(
      EventMapChart(c.series->events, *c.topdown_extent, kTopDownImageId, NextChartId(*charts)));
  html << ChartCanvas(charts->back(), "top-down view with event markers");
}

void FilesSection(std::ostringstream& html, const std::vector<std::string>& files) {
  html << "<h2>Files</h2>\n<p class=\"note\">";
  if (!files.empty()) html << "In this run's folder: ";
  for (std::size_t k = 0; k < files.size(); ++k) {
    html << (k > 0 ? ", " : "") << "<a href=\"" << E(files[k]) << "\">" << E(files[k]) << "</a>";
  }
  html << (files.empty() ? "" : ". ")
       << "performance.json, with the run's wall-clock figures, is written after this page.</p>\n";
}

}  // namespace

std::string HumanNumber(double value, int significant) {
  if (std::isnan(value)) return "n/a";
  if (std::isinf(value)) return value > 0 ? "∞" : "−∞";
  if (value == 0.0) return "0";
  significant = std::clamp(significant, 1, 15);
  const double a = std::abs(value);
  if (a < kSmallestFixed) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*e", significant - 1, value);
    return buf;
  }
  const int exponent = static_cast<int>(std::floor(std::log10(a)));
  int decimals = std::max(0, significant - 1 - exponent);
  std::string text = Fixed(value, decimals);
  // Rounding may carry into a new digit (9.996 -> "10.00"): one place fewer.
  if (decimals > 0 &&
      std::abs(std::strtod(text.c_str(), nullptr)) >= std::pow(10.0, exponent + 1)) {
    text = Fixed(value, --decimals);
  }
  if (text.find('.') != std::string::npos) {
    text.erase(text.find_last_not_of('0') + 1);
    if (text.back() == '.') text.pop_back();
  }
  if (text == "-0") text = "0";
  return GroupThousands(text);
}

std::string HumanCount(std::int64_t count) { return GroupThousands(std::to_string(count)); }

std::string HumanDistance(double metres) {
  return std::abs(metres) >= 1000.0 ? HumanNumber(metres / 1000.0) + " km"
                                    : HumanNumber(metres) + " m";
}

std::string HumanDuration(double seconds) {
  if (std::abs(seconds) >= kHoursFromS) return HumanNumber(seconds / 3600.0) + " h";
  if (std::abs(seconds) >= kMinutesFromS) return HumanNumber(seconds / 60.0) + " min";
  return HumanNumber(seconds) + " s";
}

std::string RenderReportHtml(const Scenario& scenario, const RunMetrics& metrics,
                             const ReportContent& content) {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
       << "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n"
       << "<title>Pavilion run: " << E(scenario.name) << "</title>\n"
       << "<style>" << kStyle << "</style></head><body>\n";
  html << "<h1>Pavilion run: " << E(scenario.name) << "</h1>\n";
  if (!scenario.description.empty()) html << "<p>" << E(scenario.description) << "</p>\n";
  if (!metrics.ended_early.empty()) {
    html << "<p class=\"verdict fail\">The run ended early: " << E(metrics.ended_early)
         << ". Everything below covers the run up to then.</p>\n";
  }
  if (content.expectations && !content.expectations->results.empty()) {
    ExpectationTable(html, *content.expectations);
  }
  RunTableSection(html, scenario, metrics);
  std::vector<ChartSpec> charts;
  ChartSections(html, metrics, content, &charts);
  TopDownSection(html, scenario, content, &charts);
  CrowdStripSection(html, metrics, content.crowd_frames);
  DeadlockSection(html, content.first_deadlock);
  CameraSnapshotSection(html, content.camera_snapshots);
  HypothesisSection(html, content.hypothesis_figures);
  DetailsTable(html, scenario, metrics);
  if (!metrics.robots.empty()) {
    RobotTable(html, metrics);
    const bool any_localization =
        std::any_of(metrics.robots.begin(), metrics.robots.end(),
                    [](const RobotMetrics& r) { return r.localization.has_value(); });
    if (any_localization) LocalizationTable(html, metrics);
    if (metrics.any_relocalization()) RelocalizationTable(html, metrics);
    if (metrics.any_navigation()) NavigationTable(html, metrics);
    if (metrics.fleet) FleetTable(html, metrics);
  }
  EventCountTable(html, metrics);
  FilesSection(html, content.files);
  html << ChartScripts(charts) << "</body></html>\n";
  return html.str();
}

std::string CrowdFrameCaption(double time_s) {
  const double whole = std::round(time_s);
  std::ostringstream text;
  text.setf(std::ios::fixed);
  text.precision(std::abs(time_s - whole) < kWholeSecondS ? 0 : 1);
  text << "t = " << (std::abs(time_s - whole) < kWholeSecondS ? whole : time_s) << " s";
  return text.str();
}

}  // namespace pavilion::scenarios
