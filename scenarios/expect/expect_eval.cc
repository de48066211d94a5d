#include "scenarios/expect/expect_eval.h"

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <variant>

#include "scenarios/expect/metrics_schema.h"

namespace pavilion::scenarios {
namespace {

using Json = nlohmann::ordered_json;

std::string RobotOf(const Json& fields) {
  const auto it = fields.find("robot");
  return it != fields.end() && it->is_string() ? it->get<std::string>() : std::string();
}

std::string At(double time_s) { return "at " + FormatFigure(time_s) + " s"; }

std::string Who(const std::string& robot) { return robot.empty() ? "" : robot + " "; }

ExpectationResult JudgeMetric(const Expectation& e, const MetricExpectation& m,
                              const Json& metrics) {
  ExpectationResult r{e.text, ExpectationStatus::kPass, "", "", "", e.line};
  r.bound = std::string(ToString(m.comparison)) + " " + FormatFigure(m.bound);
  const std::vector<MetricValue> values = LookUpMetric(metrics, m.path);
  int found = 0;
  int passed = 0;
  std::string first_bad;
  std::string first_missing;
  for (const MetricValue& v : values) {
    if (!v.found) {
      if (first_missing.empty()) first_missing = v.path;
      continue;
    }
    ++found;
    const bool ok = Compare(v.value, m.comparison, m.bound);
    passed += ok ? 1 : 0;
    if (values.size() == 1) r.measured = FormatFigure(v.value);
    if (!ok && first_bad.empty()) first_bad = v.path + " = " + FormatFigure(v.value);
  }
  if (values.size() > 1) {
    r.measured = std::to_string(passed) + " of " + std::to_string(values.size()) + " pass";
  }
  if (found == 0 || (!m.any && !first_missing.empty())) {
    r.status = ExpectationStatus::kMissing;
    r.detail = first_missing + ": not in this run's metrics.json";
    return r;
  }
  const bool ok = m.any ? passed > 0 : passed == found;
  if (!ok) {
    r.status = ExpectationStatus::kFail;
    r.detail = m.any ? "none passes" : first_bad;
  }
  return r;
}

}  // namespace

const char* ToString(ExpectationStatus status) {
  switch (status) {
    case ExpectationStatus::kPass:
      return "pass";
    case ExpectationStatus::kFail:
      return "fail";
    case ExpectationStatus::kMissing:
      return "missing";
  }
  return "missing";
}

bool ExpectationResults::passed() const { return failures() == 0; }

int ExpectationResults::failures() const {
  return static_cast<int>(std::count_if(results.begin(), results.end(), [](const auto& r) {
    return r.status != ExpectationStatus::kPass;
  }));
}

std::string FormatFigure(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", value == 0.0 ? 0.0 : value);
  return buf;
}

EventExpectationMonitor::EventExpectationMonitor(const std::vector<Expectation>& expectations,
                                                 std::vector<std::string> robot_ids)
    : expectations_(expectations),
      robot_ids_(std::move(robot_ids)),
      motion_s_(robot_ids_.size(), 0.0),
      states_(expectations.size()) {}

double EventExpectationMonitor::Clock(const std::string& robot, bool motion, double time_s) const {
  if (!motion) return time_s;
  const auto it = std::find(robot_ids_.begin(), robot_ids_.end(), robot);
  return it == robot_ids_.end() ? time_s
                                : motion_s_[static_cast<std::size_t>(it - robot_ids_.begin())];
}

void EventExpectationMonitor::OnEvent(double time_s, const std::string& type, const Json& fields) {
  last_time_s_ = time_s;
  for (std::size_t i = 0; i < expectations_.size(); ++i) {
    State& s = states_[i];
    if (const auto* never = std::get_if<NeverExpectation>(&expectations_[i].kind)) {
      if (!never->event.Matches(type, fields)) continue;
      if (s.matches++ == 0) s.first = type + " " + At(time_s) + ": " + fields.dump();
      continue;
    }
    const auto* within = std::get_if<WithinExpectation>(&expectations_[i].kind);
    if (!within) continue;
    const std::string robot = RobotOf(fields);
    const double now = Clock(robot, within->motion_time, time_s);
    if (within->event.Matches(type, fields)) {
      auto open = s.open.find(robot);
      if (open != s.open.end()) {
        for (const Anchor& a : open->second) {
          const double waited = now - a.clock_s;
          if (waited <= within->limit_s) {
            ++s.met;
            s.worst_s = std::max(s.worst_s, waited);
          } else if (s.first.empty()) {
            s.first = Who(robot) + within->after.type + " " + At(a.time_s) + ": " + type +
                      " only after " + FormatFigure(waited) + " s";
          }
        }
        s.open.erase(open);
      }
    }
    if (within->after.Matches(type, fields)) {
      ++s.anchors;
      s.open[robot].push_back(Anchor{time_s, now});
    }
  }
}

ExpectationResult EventExpectationMonitor::Judge(std::size_t index, const Expectation& e) const {
  const State& s = states_[index];
  ExpectationResult r{e.text, ExpectationStatus::kPass, "", "", "", e.line};
  if (const auto* never = std::get_if<NeverExpectation>(&e.kind)) {
    r.bound = "never";
    r.measured = std::to_string(s.matches) + (s.matches == 1 ? " event" : " events");
    if (s.matches > 0) {
      r.status = ExpectationStatus::kFail;
      r.detail = "first: " + s.first;
    }
    (void)never;
    return r;
  }
  const auto& within = std::get<WithinExpectation>(e.kind);
  r.bound =
      "within " + FormatFigure(within.limit_s) + " s" + (within.motion_time ? " of motion" : "");
  std::string detail = s.first;
  for (const auto& [robot, anchors] : s.open) {
    for (const Anchor& a : anchors) {
      if (!detail.empty()) break;
      const double waited = Clock(robot, within.motion_time, last_time_s_) - a.clock_s;
      detail = Who(robot) + within.after.type + " " + At(a.time_s) + ": no " + within.event.type +
               (waited <= within.limit_s
                    ? " before the run ended (" + FormatFigure(waited) + " s into the window)"
                    : " in " + FormatFigure(waited) + " s");
    }
  }
  r.measured = std::to_string(s.met) + " of " + std::to_string(s.anchors) +
               (s.met > 0 ? " (longest " + FormatFigure(s.worst_s) + " s)" : "");
  if (s.anchors == 0) {
    r.status = ExpectationStatus::kMissing;
    r.measured.clear();
    r.detail = "no " + within.after.ToString() + " event in the run";
  } else if (s.met < s.anchors) {
    r.status = ExpectationStatus::kFail;
    r.detail = detail;
  }
  return r;
}

ExpectationResults EvaluateExpectations(const std::vector<Expectation>& expectations,
                                        const Json& metrics,
                                        const EventExpectationMonitor& monitor) {
  ExpectationResults out;
  for (std::size_t i = 0; i < expectations.size(); ++i) {
    const Expectation& e = expectations[i];
    if (const auto* m = std::get_if<MetricExpectation>(&e.kind)) {
      out.results.push_back(JudgeMetric(e, *m, metrics));
    } else {
      out.results.push_back(monitor.Judge(i, e));
    }
  }
  return out;
}

Json ExpectationsToJson(const ExpectationResults& results) {
  Json list = Json::array();
  for (const ExpectationResult& r : results.results) {
    Json item = {{"name", r.name},
                 {"status", ToString(r.status)},
                 {"measured", r.measured},
                 {"bound", r.bound},
                 {"line", r.line}};
    if (!r.detail.empty()) item["detail"] = r.detail;
    list.push_back(std::move(item));
  }
  return Json{{"passed", results.passed()}, {"failures", results.failures()}, {"results", list}};
}

ExpectationResults ExpectationsFromJson(const nlohmann::json& json) {
  ExpectationResults out;
  for (const auto& r : json.at("results")) {
    ExpectationStatus status = ExpectationStatus::kMissing;
    for (ExpectationStatus s :
         {ExpectationStatus::kPass, ExpectationStatus::kFail, ExpectationStatus::kMissing}) {
      if (r.at("status") == ToString(s)) status = s;
    }
    out.results.push_back({r.at("name"), status, r.at("measured"), r.at("bound"),
                           r.value("detail", ""), r.value("line", 0)});
  }
  return out;
}

std::string FormatExpectationTable(const ExpectationResults& results) {
  std::size_t width = 11;
  for (const ExpectationResult& r : results.results) width = std::max(width, r.name.size());
  width = std::min<std::size_t>(width, 70);
  std::ostringstream out;
  char line[512];
  std::snprintf(line, sizeof line, "%-8s %-*s  %-24s %s\n", "result", static_cast<int>(width),
                "expectation", "measured", "bound");
  out << line;
  for (const ExpectationResult& r : results.results) {
    std::snprintf(line, sizeof line, "%-8s %-*s  %-24s %s\n", ToString(r.status),
                  static_cast<int>(width), r.name.c_str(), r.measured.c_str(), r.bound.c_str());
    out << line;
    if (!r.detail.empty()) out << "         " << r.detail << "\n";
  }
  out << results.results.size() - static_cast<std::size_t>(results.failures()) << " of "
      << results.results.size() << " expectations passed\n";
  return out.str();
}

}  // namespace pavilion::scenarios
