#include "scenarios/output/report.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "scenarios/output/png.h"

namespace pavilion::scenarios {
namespace {

// Crowd frame captions give whole seconds within this of one, else tenths.
constexpr double kWholeSecondS = 0.05;

std::string Escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
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
        out += c;
    }
  }
  return out;
}

void Row(std::ostringstream& html, const std::string& name, const std::string& value) {
  html << "<tr><th>" << Escape(name) << "</th><td>" << Escape(value) << "</td></tr>\n";
}

// A figure as metrics.json writes it.
std::string Num(double v, int decimals = 6) {
  return nlohmann::json(RoundForJson(v, decimals)).dump();
}
std::string Raw(double v) { return nlohmann::json(v).dump(); }
std::string Int(std::int64_t v) { return std::to_string(v); }

void RunTable(std::ostringstream& html, const Scenario& scenario, const RunMetrics& m) {
  html << "<table>\n";
  Row(html, "scenario file", scenario.source_file);
  Row(html, "world", scenario.world.name);
  Row(html, "seed", std::to_string(scenario.seed));
  Row(html, "simulated time (s)", Raw(m.sim_duration_s));
  Row(html, "physics rate (Hz)", Raw(m.physics_rate_hz));
  Row(html, "pavilion version", m.pavilion_version);
  if (!m.bodies.empty()) {
    Row(html, "bodies", Int(static_cast<std::int64_t>(m.bodies.size())));
    Row(html, "distance travelled by all bodies (m)", Num(m.bodies_distance_m()));
    Row(html, "collision begins per body, summed (a body-body contact counts for both)",
        Int(m.bodies_collisions()));
  }
  html << "</table>\n";
}

void RobotTable(std::ostringstream& html, const RunMetrics& m) {
  html << "<h2>Robots</h2>\n<table>\n<tr><th>robot</th><th>model</th><th>distance (m)</th>"
          "<th>collisions</th><th>bumper presses</th><th>scans</th>"
          "<th>odometry error at the end: position (m)</th><th>heading (rad)</th></tr>\n";
  for (const RobotMetrics& r : m.robots) {
    html << "<tr><td>" << Escape(r.id) << "</td><td>" << Escape(r.model) << "</td><td>"
         << Num(r.distance_m) << "</td><td>" << r.collisions << "</td><td>" << r.bumper_presses
         << "</td><td>" << r.scans << "</td><td>" << Num(r.odometry_final_position_error_m)
         << "</td><td>" << Num(r.odometry_final_heading_error_rad) << "</td></tr>\n";
  }
  html << "</table>\n<p class=\"note\">Odometry: the encoder counts integrated with the "
          "robot's calibrated model from its start pose; it misses the slip of collisions "
          "and pushes.</p>\n";
}

void LocalizationTable(std::ostringstream& html, const RunMetrics& m) {
  html << "<h2>Localization</h2>\n<table>\n<tr><th>robot</th><th>cycles</th>"
          "<th>position RMSE (m)</th><th>heading RMSE (deg)</th><th>2&sigma; frontal "
          "(m)</th><th>2&sigma; lateral (m)</th><th>2&sigma; heading (deg)</th>"
          "<th>ANEES</th><th>matched lines per cycle</th><th>lost situations</th>"
          "<th>declared lost</th></tr>\n";
  for (const RobotMetrics& r : m.robots) {
    if (!r.localization) continue;
    const LocalizationFigures& l = *r.localization;
    html << "<tr><td>" << Escape(r.id) << "</td>";
    for (const std::string& cell :
         {Int(l.cycles), Num(l.position_rmse_m), Num(l.heading_rmse_deg),
          Num(l.two_sigma_frontal_m), Num(l.two_sigma_lateral_m), Num(l.two_sigma_heading_deg),
          Num(l.anees), Num(l.matched_lines_per_cycle), Int(l.lost_situations),
          Int(l.declared_lost_situations)}) {
      html << "<td>" << cell << "</td>";
    }
    html << "</tr>\n";
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
    html << "<tr><td>" << Escape(id) << "</td>";
    for (const std::string& cell :
         {Int(f.kidnaps), Int(f.recovered) + " (" + Num(f.recovered_ratio, 3) + ")",
          Num(f.lost_declared_within_10s_ratio, 3), Num(f.median_time_to_lost_s, 2),
          Num(f.median_time_to_relocalize_s, 2), Num(f.median_distance_to_relocalize_m, 2),
          Int(f.false_relocalizations), Num(f.fbt_recovered_ratio, 3),
          Num(f.fbt_mean_recovery_s, 2),
          Num(f.mean_hypotheses, 2) + " / " + Int(f.max_hypotheses)}) {
      html << "<td>" << cell << "</td>";
    }
    html << "</tr>\n";
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
    html << "<tr><td>" << Escape(r.id) << "</td>";
    for (const std::string& cell :
         {Int(n.missions_started), Int(n.missions_completed), Int(n.missions_aborted_total()),
          Num(n.mission_time_s / done), Num(n.mission_path_length_m / done),
          Num(n.clearance_samples > 0 ? n.min_clearance_m : 0.0), Num(n.time_blocked_s),
          Int(n.replans), Int(c.of(CollisionClass::kVisible)),
          Int(c.of(CollisionClass::kInvisible)), Int(c.of(CollisionClass::kVisitor)),
          Int(c.of(CollisionClass::kRobot))}) {
      html << "<td>" << cell << "</td>";
    }
    html << "</tr>\n";
  }
  html << "</table>\n<p class=\"note\">The chapter 6 navigation (docs/navigation.md): "
          "aborts by reason, band snaps and who moved into whom are in metrics.json. "
          "Computer 2000 (Table 4.3): 724 missions, no lost situation, about 60 "
          "collisions in 5 km.</p>\n";
}

// The crowd frames in one row, each with its time below; they shrink to share
// the page's width.
void CrowdStripSection(std::ostringstream& html, const RunMetrics& m,
                       const std::vector<CrowdFrame>& frames) {
  if (frames.empty()) return;
  const std::string around =
      m.robots.empty() ? std::string("the floor's centre") : Escape(m.robots.front().id);
  html << "<h2>The crowd around " << around << "</h2>\n"
       << "<p class=\"note\">The top-down view cropped to " << Num(frames.front().size_m, 2)
       << " m &times; " << Num(frames.front().size_m, 2) << " m around " << around
       << " at evenly spaced times of the run (snapshots/crowd_NN.png): visitors as their "
          "shoulder disc with a heading tick and their two legs cut at the section's height.</p>\n"
       << "<div style=\"display:flex;gap:6px\">\n";
  for (const CrowdFrame& f : frames) {
    const std::string caption = CrowdFrameCaption(f.time_s);
    html << "<figure style=\"flex:1 1 0;min-width:0;margin:0;text-align:center\">"
         << "<img style=\"width:100%\" alt=\"crowd at " << caption << "\" title=\""
         << Escape(f.path) << "\" src=\"data:image/png;base64," << Base64(f.png) << "\">"
         << "<figcaption>" << caption << "</figcaption></figure>\n";
  }
  html << "</div>\n";
}

void Pictures(std::ostringstream& html, const Scenario& scenario, const RunMetrics& metrics,
              const std::vector<std::uint8_t>& topdown_png,
              const std::vector<LocalizationPlot>& localization_plots,
              const std::vector<HypothesisFigure>& hypothesis_figures,
              const std::vector<CrowdFrame>& crowd_frames) {
  html << "<h2>Top-down view at the end of the run</h2>\n"
       << "<p class=\"note\">Footprints in material colours; black outline: the world cut at "
       << scenario.outputs.section_height_m
       << " m, what a laser at that height can meet (light blue: glass, which it cannot); "
          "red: body trajectories; blue: robots' true paths, orange: their encoder odometry; "
          "green: named places; for robots with a mission, magenta: the plan still ahead, cyan: "
          "the elastic band and its bubbles, thick green: the dynamic window's chosen arc.</p>\n"
       << "<img alt=\"top-down view\" src=\"data:image/png;base64," << Base64(topdown_png)
       << "\">\n";
  CrowdStripSection(html, metrics, crowd_frames);
  for (const LocalizationPlot& plot : localization_plots) {
    html << "<h2>Localization of " << Escape(plot.robot_id) << ": 2 sigma over time</h2>\n"
         << "<p class=\"note\">Two standard deviations of the estimate in the robot's frontal "
            "(blue) and lateral (red) direction, per localization cycle (localization.csv; "
            "thesis Fig. 4.4).</p>\n"
         << "<img alt=\"2 sigma of " << Escape(plot.robot_id) << "\" src=\"data:image/png;base64,"
         << Base64(plot.png) << "\">\n";
  }
  for (const HypothesisFigure& f : hypothesis_figures) {
    html << "<h2>Location hypotheses of " << Escape(f.robot_id) << " after a kidnap</h2>\n"
         << "<p class=\"note\">At " << Num(f.time_s, 2)
         << " s, its largest set after a kidnap: " << f.hypotheses
         << " hypotheses (thesis Fig. 5.19), each an arrow along its heading in a 0.4 m ring "
            "with its 95 % position ellipse (magenta: the best, §5.5.2; yellow: the others); "
            "blue: the true pose.</p>\n"
         << "<img alt=\"hypotheses of " << Escape(f.robot_id) << "\" src=\"data:image/png;base64,"
         << Base64(f.png) << "\">\n";
  }
}

}  // namespace

std::string CrowdFrameCaption(double time_s) {
  const double whole = std::round(time_s);
  std::ostringstream text;
  text.setf(std::ios::fixed);
  text.precision(std::abs(time_s - whole) < kWholeSecondS ? 0 : 1);
  text << "t = " << (std::abs(time_s - whole) < kWholeSecondS ? whole : time_s) << " s";
  return text.str();
}

std::string RenderReportHtml(const Scenario& scenario, const RunMetrics& metrics,
                             const std::vector<std::uint8_t>& topdown_png,
                             const std::vector<LocalizationPlot>& localization_plots,
                             const std::vector<HypothesisFigure>& hypothesis_figures,
                             const std::vector<CrowdFrame>& crowd_frames) {
  std::ostringstream html;
  html
      << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
      << "<title>Pavilion run: " << Escape(scenario.name) << "</title>\n"
      << "<style>body{font-family:sans-serif;max-width:1000px;margin:2em auto;color:#222}"
         "table{border-collapse:collapse;margin:1em 0}th,td{border:1px solid #ccc;padding:4px 10px;"
         "text-align:left}th{background:#f3f3f3}img{max-width:100%;border:1px solid #ccc}"
         ".note{color:#666;font-size:90%}</style></head><body>\n";
  html << "<h1>Pavilion run: " << Escape(scenario.name) << "</h1>\n";
  if (!scenario.description.empty()) html << "<p>" << Escape(scenario.description) << "</p>\n";
  RunTable(html, scenario, metrics);
  if (!metrics.robots.empty()) {
    RobotTable(html, metrics);
    const bool any_localization =
        std::any_of(metrics.robots.begin(), metrics.robots.end(),
                    [](const RobotMetrics& r) { return r.localization.has_value(); });
    if (any_localization) LocalizationTable(html, metrics);
    if (metrics.any_relocalization()) RelocalizationTable(html, metrics);
    if (metrics.any_navigation()) NavigationTable(html, metrics);
  }
  html << "<h2>Events</h2>\n<table>\n<tr><th>type</th><th>count</th></tr>\n";
  for (const auto& [type, n] : metrics.event_counts) {
    html << "<tr><td>" << Escape(type) << "</td><td>" << n << "</td></tr>\n";
  }
  html << "</table>\n";
  Pictures(html, scenario, metrics, topdown_png, localization_plots, hypothesis_figures,
           crowd_frames);
  html << "<p class=\"note\">Files: metrics.json, performance.json (wall-clock figures), "
          "events.jsonl, trajectories.csv, localization.csv, scans.bin (robots' laser scans with "
          "ground truth), "
          "snapshots/.</p>\n</body></html>\n";
  return html.str();
}

}  // namespace pavilion::scenarios
