#include "scenarios/output/report.h"

#include <sstream>

#include "scenarios/output/png.h"

namespace pavilion::scenarios {
namespace {

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

}  // namespace

std::string RenderReportHtml(const Scenario& scenario, const nlohmann::ordered_json& metrics,
                             const std::vector<std::uint8_t>& topdown_png,
                             const std::vector<LocalizationPlot>& localization_plots) {
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
  html << "<table>\n";
  Row(html, "scenario file", scenario.source_file);
  Row(html, "world", scenario.world.name);
  Row(html, "seed", std::to_string(scenario.seed));
  Row(html, "simulated time (s)", metrics["sim_duration_s"].dump());
  Row(html, "physics rate (Hz)", metrics["physics"]["rate_hz"].dump());
  Row(html, "pavilion version", metrics["pavilion_version"].get<std::string>());
  if (metrics.contains("bodies_summary")) {
    const auto& b = metrics["bodies_summary"];
    Row(html, "bodies", b["count"].dump());
    Row(html, "distance travelled by all bodies (m)", b["distance_m"].dump());
    Row(html, "collision begins per body, summed (a body-body contact counts for both)",
        b["collisions"].dump());
  }
  html << "</table>\n";
  if (metrics.contains("robots")) {
    html << "<h2>Robots</h2>\n<table>\n<tr><th>robot</th><th>model</th><th>distance (m)</th>"
            "<th>collisions</th><th>bumper presses</th><th>scans</th>"
            "<th>odometry error at the end: position (m)</th><th>heading (rad)</th></tr>\n";
    for (const auto& [id, r] : metrics["robots"].items()) {
      const auto& e = r["odometry_final_error"];
      html << "<tr><td>" << Escape(id) << "</td><td>" << Escape(r["model"].get<std::string>())
           << "</td><td>" << r["distance_m"].dump() << "</td><td>" << r["collisions"].dump()
           << "</td><td>" << r["bumper_presses"].dump() << "</td><td>" << r["scans"].dump()
           << "</td><td>" << e["position_m"].dump() << "</td><td>" << e["heading_rad"].dump()
           << "</td></tr>\n";
    }
    html << "</table>\n<p class=\"note\">Odometry: the encoder counts integrated with the "
            "robot's calibrated model from its start pose; it misses the slip of collisions "
            "and pushes.</p>\n";
    bool any_localization = false;
    for (const auto& [id, r] : metrics["robots"].items()) {
      any_localization = any_localization || r.contains("localization");
    }
    if (any_localization) {
      html << "<h2>Localization</h2>\n<table>\n<tr><th>robot</th><th>cycles</th>"
              "<th>position RMSE (m)</th><th>heading RMSE (deg)</th><th>2&sigma; frontal "
              "(m)</th><th>2&sigma; lateral (m)</th><th>2&sigma; heading (deg)</th>"
              "<th>ANEES</th><th>matched lines per cycle</th><th>lost situations</th></tr>\n";
      for (const auto& [id, r] : metrics["robots"].items()) {
        if (!r.contains("localization")) continue;
        const auto& l = r["localization"];
        html << "<tr><td>" << Escape(id) << "</td>";
        for (const char* key :
             {"cycles", "position_rmse_m", "heading_rmse_deg", "two_sigma_frontal_m",
              "two_sigma_lateral_m", "two_sigma_heading_deg", "anees", "matched_lines_per_cycle",
              "lost_situations"}) {
          html << "<td>" << l[key].dump() << "</td>";
        }
        html << "</tr>\n";
      }
      html << "</table>\n<p class=\"note\">Against ground truth, per localization cycle "
              "(localization.csv; metrics.md). A consistent filter has ANEES near 3; the "
              "thesis' Table 4.2 (laser only) gives 2&sigma; of 13.1 mm frontal, 13.5 mm "
              "lateral, 0.92&deg; and 2.73 matched lines per cycle.</p>\n";
    }
  }
  html << "<h2>Events</h2>\n<table>\n<tr><th>type</th><th>count</th></tr>\n";
  for (const auto& [type, n] : metrics["events"].items()) {
    html << "<tr><td>" << Escape(type) << "</td><td>" << n.dump() << "</td></tr>\n";
  }
  html << "</table>\n<h2>Top-down view at the end of the run</h2>\n"
       << "<p class=\"note\">Footprints in material colours; black outline: the world cut at "
       << scenario.outputs.section_height_m
       << " m, what a laser at that height can meet (light blue: glass, which it cannot); "
          "red: body trajectories; blue: robots' true paths, orange: their encoder odometry; "
          "green: named places.</p>\n"
       << "<img alt=\"top-down view\" src=\"data:image/png;base64," << Base64(topdown_png)
       << "\">\n";
  for (const LocalizationPlot& plot : localization_plots) {
    html << "<h2>Localization of " << Escape(plot.robot_id) << ": 2 sigma over time</h2>\n"
         << "<p class=\"note\">Two standard deviations of the estimate in the robot's frontal "
            "(blue) and lateral (red) direction, per localization cycle (localization.csv; "
            "thesis Fig. 4.4).</p>\n"
         << "<img alt=\"2 sigma of " << Escape(plot.robot_id) << "\" src=\"data:image/png;base64,"
         << Base64(plot.png) << "\">\n";
  }
  html << "<p class=\"note\">Files: metrics.json, performance.json (wall-clock figures), "
          "events.jsonl, trajectories.csv, localization.csv, scans.bin (robots' laser scans with "
          "ground truth), "
          "snapshots/.</p>\n</body></html>\n";
  return html.str();
}

}  // namespace pavilion::scenarios
