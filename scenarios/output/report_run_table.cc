#include "scenarios/output/report_run_table.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "scenarios/output/report.h"
#include "scenarios/output/report_charts.h"

namespace pavilion::scenarios {
namespace {

// Runs with more robots show the fleet's column only.
constexpr std::size_t kMaxRobotColumns = 8;

std::string E(const std::string& s) { return EscapeHtml(s); }
std::string Int(std::int64_t v) { return HumanCount(v); }
std::string H(double v) { return HumanNumber(v); }
std::string Percent(double ratio) { return HumanNumber(100.0 * ratio) + " %"; }

// One quantity of the table: the fleet's value, each robot's, and the
// run_table paths a reference may give for it (joined by " / ").
struct RunRow {
  std::string name;
  std::string fleet;
  std::vector<std::string> robots;
  std::vector<std::string> keys;
};

class RowBuilder {
 public:
  explicit RowBuilder(const RunMetrics& m) : m_(m) {}

  template <typename F>
  std::vector<std::string> PerRobot(F value) const {
    std::vector<std::string> cells;
    for (const RobotMetrics& r : m_.robots) cells.push_back(value(r));
    return cells;
  }

 private:
  const RunMetrics& m_;
};

const std::string kNone = "–";

void BasicRows(const Scenario& scenario, const RunMetrics& m, const RowBuilder& b,
               const std::optional<RunTable>& t, std::vector<RunRow>* rows) {
  const double s = m.sim_duration_s;
  rows->push_back({"hours of operation (simulated)",
                   HumanDuration(s) + " (" + H(s / 3600.0) + " h)",
                   b.PerRobot([&](const RobotMetrics&) { return HumanDuration(s); }),
                   {"hours"}});
  const Eigen::Vector2d floor = scenario.world.floor.max_m - scenario.world.floor.min_m;
  rows->push_back(
      {"environment", m.world + ", floor " + H(floor.x()) + " × " + H(floor.y()) + " m", {}, {}});
  if (t && t->robots > 1) {
    rows->push_back({"robots / robot-hours",
                     Int(t->robots) + " / " + H(t->robot_hours),
                     {},
                     {"robots", "robot_hours"}});
  }
  double metres = 0.0;
  for (const RobotMetrics& r : m.robots) metres += r.distance_m;
  rows->push_back({"overall travel distance",
                   HumanDistance(metres),
                   b.PerRobot([](const RobotMetrics& r) { return HumanDistance(r.distance_m); }),
                   {"distance_km"}});
  if (s > 0.0 && !m.robots.empty()) {
    rows->push_back(
        {"average speed (over the hours)",
         H(metres / s / static_cast<double>(m.robots.size())) + " m/s",
         b.PerRobot([&](const RobotMetrics& r) { return H(r.distance_m / s) + " m/s"; }),
         {"mean_speed_mps"}});
  }
  if (t) {
    rows->push_back({"average speed while driving, maximum",
                     H(t->mean_driving_speed_mps) + ", " + H(t->max_speed_mps) + " m/s",
                     b.PerRobot([](const RobotMetrics& r) {
                       if (!r.day || r.day->driving_s <= 0.0) return kNone;
                       return H(r.distance_m / r.day->driving_s) + ", " + H(r.day->max_speed_mps) +
                              " m/s";
                     }),
                     {"mean_driving_speed_mps", "max_speed_mps"}});
  }
}

void MissionRows(const RunMetrics& m, const RowBuilder& b, const std::optional<RunTable>& t,
                 std::vector<RunRow>* rows) {
  if (!m.any_navigation()) return;
  int started = 0, completed = 0, aborted = 0;
  std::array<int, nav::kAbortReasons.size()> by_reason{};
  for (const RobotMetrics& r : m.robots) {
    if (!r.navigation) continue;
    started += r.navigation->missions_started;
    completed += r.navigation->missions_completed;
    aborted += r.navigation->missions_aborted_total();
    for (std::size_t k = 0; k < by_reason.size(); ++k)
      by_reason[k] += r.navigation->missions_aborted[k];
  }
  rows->push_back({"missions started / completed / aborted",
                   Int(started) + " / " + Int(completed) + " / " + Int(aborted),
                   b.PerRobot([](const RobotMetrics& r) {
                     if (!r.navigation) return kNone;
                     const nav::NavigationFigures& n = *r.navigation;
                     return Int(n.missions_started) + " / " + Int(n.missions_completed) + " / " +
                            Int(n.missions_aborted_total());
                   }),
                   {"missions.started", "missions.completed", "missions.aborted"}});
  if (completed + aborted > 0) {
    rows->push_back({"missions completed, of those that ended",
                     Percent(static_cast<double>(completed) / (completed + aborted)),
                     {},
                     {"missions.completed_ratio"}});
  }
  std::string reasons;
  std::vector<std::string> keys;
  for (nav::AbortReason reason : nav::kAbortReasons) {
    reasons += (reasons.empty() ? "" : " / ") + Int(by_reason[static_cast<std::size_t>(reason)]);
    keys.push_back(std::string("missions.aborted_by_reason.") + nav::ToString(reason));
  }
  rows->push_back({"… aborted as unreachable / timed out / lost / blocked", reasons, {}, keys});
  if (t) {
    rows->push_back({"missions without a match for 10 s / 5 s",
                     Int(t->missions_without_match_10s) + " / " + Int(t->missions_without_match_5s),
                     b.PerRobot([](const RobotMetrics& r) {
                       if (!r.day) return kNone;
                       return Int(r.day->missions_without_match_10s) + " / " +
                              Int(r.day->missions_without_match_5s);
                     }),
                     {"missions_without_match_10s", "missions_without_match_5s"}});
  }
}

void LocalizationRows(const RunMetrics& m, const RowBuilder& b, const std::optional<RunTable>& t,
                      std::vector<RunRow>* rows) {
  std::int64_t cycles = 0, lost = 0, declared = 0;
  for (const RobotMetrics& r : m.robots) {
    if (!r.localization) continue;
    cycles += r.localization->cycles;
    lost += r.localization->lost_situations;
    declared += r.localization->declared_lost_situations;
  }
  const auto localization = [&](auto field) {
    return b.PerRobot([field](const RobotMetrics& r) {
      return r.localization ? Int(field(*r.localization)) : kNone;
    });
  };
  rows->push_back({"localization cycles",
                   Int(cycles),
                   localization([](const LocalizationFigures& l) { return l.cycles; }),
                   {"localization_cycles"}});
  rows->push_back({"lost situations (true error or declared) / declared",
                   Int(lost) + " / " + Int(declared),
                   b.PerRobot([](const RobotMetrics& r) {
                     if (!r.localization) return kNone;
                     return Int(r.localization->lost_situations) + " / " +
                            Int(r.localization->declared_lost_situations);
                   }),
                   {"lost_situations", "declared_lost_situations"}});
  if (!t) return;
  std::string causes;
  std::vector<std::string> keys;
  for (LossCause cause : kLossCauses) {
    causes +=
        (causes.empty() ? "" : " / ") + Int(t->lost_by_cause[static_cast<std::size_t>(cause)]);
    keys.push_back(std::string("lost_by_cause.") + ToString(cause));
  }
  rows->push_back({"… begun by a kidnap / push / collision / nothing seen", causes,
                   b.PerRobot([](const RobotMetrics& r) {
                     if (!r.day) return kNone;
                     std::string out;
                     for (int n : r.day->lost_by_cause) out += (out.empty() ? "" : " / ") + Int(n);
                     return out;
                   }),
                   keys});
  if (t->disturbances() > 0) {
    const std::string median =
        t->recovery_motion_s.empty() ? kNone : H(t->median_recovery_motion_s()) + " s";
    rows->push_back({"kidnaps + staff pushes, recovered within 30 s of motion",
                     Int(t->kidnaps) + " + " + Int(t->pushes) + ", " + Int(t->recovered) + " (" +
                         Percent(t->recovered_ratio()) + "; median " + median + ")",
                     {},
                     {"disturbances.kidnaps", "disturbances.pushes", "disturbances.recovered"}});
  }
}

void CollisionRows(const RunMetrics& m, const RowBuilder& b, std::vector<RunRow>* rows) {
  CollisionCounts all;
  for (const RobotMetrics& r : m.robots) all += r.collisions_by_class;
  std::int64_t total = 0;
  for (std::int64_t n : all.by_class) total += n;
  rows->push_back({"collisions",
                   Int(total),
                   b.PerRobot([](const RobotMetrics& r) {
                     std::int64_t n = 0;
                     for (std::int64_t c : r.collisions_by_class.by_class) n += c;
                     return Int(n);
                   }),
                   {}});
  for (const auto& [cls, name] :
       {std::pair{CollisionClass::kVisible, "a wall or exhibit the laser sees"},
        std::pair{CollisionClass::kInvisible, "an object invisible to the laser"},
        std::pair{CollisionClass::kVisitor, "a visitor (robot into visitor / visitor into robot)"},
        std::pair{CollisionClass::kRobot, "a robot (moved into the other / was hit)"}}) {
    std::string fleet = Int(all.of(cls));
    if (cls == CollisionClass::kVisitor) {
      fleet += " (" + Int(all.robot_into_visitor) + " / " + Int(all.visitor_into_robot) + ")";
    } else if (cls == CollisionClass::kRobot) {
      fleet += " (" + Int(all.robot_into_robot) + " / " + Int(all.robot_hit_by_robot) + ")";
    }
    rows->push_back(
        {std::string("… with ") + name,
         fleet,
         b.PerRobot([cls](const RobotMetrics& r) { return Int(r.collisions_by_class.of(cls)); }),
         {std::string("collisions.") + ToString(cls)}});
  }
  // Passes closer than the contact tracker's 5 mm that never touched: not
  // collisions, but how close the robots cut it.
  const auto passes = [](const CollisionCounts& c) {
    return Int(c.passes_by_class[static_cast<std::size_t>(CollisionClass::kVisible)]) + " / " +
           Int(c.passes_by_class[static_cast<std::size_t>(CollisionClass::kRobot)]);
  };
  rows->push_back(
      {"passes within 5 mm without a touch (wall or exhibit the laser sees / robot)",
       passes(all),
       b.PerRobot([&passes](const RobotMetrics& r) { return passes(r.collisions_by_class); }),
       {}});
}

void HumanRows(const RowBuilder& b, const RunTable& t, std::vector<RunRow>* rows) {
  rows->push_back({"deadlocks detected / resolved / unresolved",
                   Int(t.deadlocks_detected) + " / " + Int(t.deadlocks_resolved) + " / " +
                       Int(t.deadlocks_unresolved),
                   {},
                   {"deadlocks.detected", "deadlocks.resolved", "deadlocks.unresolved"}});
  rows->push_back({"interventions: standing > 60 s / lost > 30 s (per robot-hour)",
                   Int(t.still_over_60s) + " / " + Int(t.lost_over_30s) + " (" +
                       H(t.interventions_per_robot_hour()) + ")",
                   b.PerRobot([](const RobotMetrics& r) {
                     if (!r.day) return kNone;
                     return Int(r.day->still_over_60s) + " / " + Int(r.day->lost_over_30s);
                   }),
                   {"interventions.still_over_60s", "interventions.lost_over_30s",
                    "interventions.per_robot_hour"}});
  if (t.intimate_s + t.personal_s + t.social_s > 0.0) {
    rows->push_back({"time with a visitor within 0.45 / 1.2 / 3.6 m",
                     HumanDuration(t.intimate_s) + " / " + HumanDuration(t.personal_s) + " / " +
                         HumanDuration(t.social_s),
                     {},
                     {"social_zone_s.intimate", "social_zone_s.personal", "social_zone_s.social"}});
  }
}

// A reference figure in the unit its row shows ours in.
std::string ReferenceValue(const std::string& key, double value) {
  if (key == "hours") return HumanDuration(value * 3600.0);
  if (key == "distance_km") return HumanDistance(value * 1000.0);
  if (key.ends_with("_mps")) return H(value) + " m/s";
  if (key.ends_with("_ratio")) return Percent(value);
  return H(value);
}

std::string ReferenceCell(const RunReference& reference, const std::vector<std::string>& keys) {
  std::string out;
  bool any = false;
  for (const std::string& key : keys) {
    const double* value = reference.Find(key);
    any = any || value != nullptr;
    out += (out.empty() ? "" : " / ") + (value ? ReferenceValue(key, *value) : kNone);
  }
  return any ? out : "";
}

}  // namespace

void RunTableSection(std::ostringstream& html, const Scenario& scenario, const RunMetrics& m) {
  const std::optional<RunTable> table = MakeRunTable(m);
  const RowBuilder b(m);
  std::vector<RunRow> rows;
  BasicRows(scenario, m, b, table, &rows);
  MissionRows(m, b, table, &rows);
  LocalizationRows(m, b, table, &rows);
  CollisionRows(m, b, &rows);
  if (table) HumanRows(b, *table, &rows);
  if (m.crowd) {
    rows.push_back({"visitors: arrivals, mean and most present",
                    Int(m.crowd->arrivals) + ", " + H(m.crowd->mean_present) + ", " +
                        Int(m.crowd->max_present),
                    {},
                    {}});
  }
  const bool robot_columns = m.robots.size() > 1 && m.robots.size() <= kMaxRobotColumns;
  const bool reference = !scenario.reference.empty();
  html << "<h2>The run in figures</h2>\n<table>\n<tr><th></th><th>"
       << (m.robots.size() > 1 ? "fleet"
           : m.robots.empty()  ? "run"
                               : E(m.robots.front().id))
       << "</th>";
  if (reference) html << "<th>reference</th>";
  if (robot_columns) {
    for (const RobotMetrics& r : m.robots) html << "<th>" << E(r.id) << "</th>";
  }
  html << "</tr>\n";
  for (const RunRow& row : rows) {
    html << "<tr><th>" << E(row.name) << "</th><td class=\"num\">" << E(row.fleet) << "</td>";
    if (reference)
      html << "<td class=\"num\">" << E(ReferenceCell(scenario.reference, row.keys)) << "</td>";
    if (robot_columns) {
      for (std::size_t k = 0; k < m.robots.size(); ++k) {
        html << "<td class=\"num\">" << (k < row.robots.size() ? E(row.robots[k]) : "") << "</td>";
      }
    }
    html << "</tr>\n";
  }
  html << "</table>\n<p class=\"note\">";
  if (reference) html << "Reference: " << E(scenario.reference.source) << ". ";
  html << "In the style of thesis Table 4.3 (Computer 2000: 28 h, 5,013 m, 724 missions, 145,433 "
          "localization cycles, no lost situation, about 60 collisions, mostly with objects the "
          "laser cannot see) and of Expo.02's statistics (§6.5). Lost situation: the true error "
          "beyond 0.5 m or 10&deg;, or declared lost (metrics.md); its cause is a kidnap, push "
          "or collision of the robot within the 30 s before it. Recovered: localized within "
          "0.2 m and 5&deg; within 30 s of motion after the kidnap or push. An intervention is "
          "what Expo.02's staff did by hand: a robot standing with a mission for more than "
          "60 s, or lost for more than 30 s.</p>\n";
}

}  // namespace pavilion::scenarios
