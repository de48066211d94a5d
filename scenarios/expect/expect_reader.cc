#include "scenarios/expect/expect_reader.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <optional>
#include <sstream>
#include <utility>

#include "scenarios/metrics/collision_classes.h"

namespace pavilion::scenarios {
namespace {

constexpr double kMaxWindowS = 1e7;

struct Parsed {
  std::vector<std::string> path;
  Comparison comparison = Comparison::kLess;
  double bound = 0.0;
};

std::string Trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  const auto e = s.find_last_not_of(" \t");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

// "PATH OP VALUE": the operator is the first of <=, >=, ==, !=, <, > found.
std::optional<Parsed> ParseComparison(const std::string& text, std::string* error) {
  static const std::array<std::pair<const char*, Comparison>, 6> kOps{{
      {"<=", Comparison::kLessEqual},
      {">=", Comparison::kGreaterEqual},
      {"==", Comparison::kEqual},
      {"!=", Comparison::kNotEqual},
      {"<", Comparison::kLess},
      {">", Comparison::kGreater},
  }};
  std::size_t at = std::string::npos;
  std::size_t len = 0;
  Parsed p;
  for (const auto& [op, c] : kOps) {
    const std::size_t found = text.find(op);
    if (found != std::string::npos && (found < at || (found == at && std::strlen(op) > len))) {
      at = found;
      len = std::strlen(op);
      p.comparison = c;
    }
  }
  if (at == std::string::npos) {
    *error = "expected 'metric.path OP value' with OP one of < <= > >= == !=";
    return std::nullopt;
  }
  const std::string path = Trim(text.substr(0, at));
  const std::string value = Trim(text.substr(at + len));
  if (value == "true" || value == "false") {
    p.bound = value == "true" ? 1.0 : 0.0;
  } else {
    std::istringstream in(value);
    in >> p.bound;
    if (value.empty() || !in.eof() || in.fail() || !std::isfinite(p.bound)) {
      *error = "'" + value + "' is not a number or true/false";
      return std::nullopt;
    }
  }
  std::stringstream parts(path);
  for (std::string part; std::getline(parts, part, '.');) p.path.push_back(part);
  if (path.empty() || std::find(p.path.begin(), p.path.end(), "") != p.path.end()) {
    *error = "'" + path + "' is not a metric path (keys separated by dots)";
    return std::nullopt;
  }
  return p;
}

std::optional<MetricExpectation> ReadMetric(YamlDocument* doc, const YAML::Node& node,
                                            const std::string& key_path, const MetricIds& ids,
                                            bool any) {
  if (!node.IsScalar()) {
    doc->Error(node, key_path, "expected 'metric.path OP value'");
    return std::nullopt;
  }
  std::string error;
  const std::optional<Parsed> p = ParseComparison(node.Scalar(), &error);
  if (p) error = CheckMetricPath(p->path, ids);
  if (!error.empty()) {
    doc->Error(node, key_path, error);
    return std::nullopt;
  }
  return MetricExpectation{p->path, p->comparison, p->bound, any};
}

// A YAML scalar as the JSON value an event record would hold.
nlohmann::ordered_json ScalarToJson(const std::string& text) {
  if (text == "true" || text == "false") return text == "true";
  std::istringstream in(text);
  double number = 0.0;
  in >> number;
  if (!text.empty() && in.eof() && !in.fail()) return number;
  return text;
}

// An event type and the record fields it must have; `type_key` names the type.
std::optional<EventFilter> ReadFilter(MapReader& r, const std::string& type_key,
                                      const std::vector<std::string>& skip, const MetricIds& ids) {
  EventFilter f;
  const std::optional<std::string> type = r.RequiredString(type_key);
  if (!type) return std::nullopt;
  if (!ids.events.contains(*type)) {
    std::string known;
    for (const std::string& e : ids.events) known += (known.empty() ? "" : ", ") + e;
    r.doc()->Error(r.Child(type_key), r.PathOf(type_key),
                   "unknown event '" + *type + "' (known: " + known + ")");
    return std::nullopt;
  }
  f.type = *type;
  for (const auto& item : r.node()) {
    const std::string key = item.first.as<std::string>();
    if (key == type_key || std::find(skip.begin(), skip.end(), key) != skip.end()) continue;
    const YAML::Node value = r.Child(key);
    if (!value.IsScalar()) {
      r.doc()->Error(value, r.PathOf(key), "expected a value the event's field must equal");
      continue;
    }
    const std::string text = value.Scalar();
    if (key == "robot" && text != "*" && !ids.robots.contains(text)) {
      r.doc()->Error(value, r.PathOf(key), "no robot '" + text + "' in the scenario");
    }
    if (key == "robot" && text == "*") continue;  // any robot: no filter
    if (f.type == "collision" && key == "with") {
      bool known = false;
      for (std::size_t c = 0; c < kCollisionClasses; ++c) {
        known |= text == ToString(static_cast<CollisionClass>(c));
      }
      if (!known) {
        r.doc()->Error(value, r.PathOf(key),
                       "unknown collision class '" + text +
                           "' (wall_or_exhibit_visible, invisible_object, visitor, robot)");
      }
    }
    f.fields[key] = ScalarToJson(text);
  }
  return f;
}

std::optional<NeverExpectation> ReadNever(YamlDocument* doc, const YAML::Node& node,
                                          const std::string& key_path, const MetricIds& ids) {
  MapReader r(doc, node, key_path);
  if (!r.valid()) return std::nullopt;
  std::optional<EventFilter> f = ReadFilter(r, "event", {}, ids);
  r.Finish();
  if (!f) return std::nullopt;
  return NeverExpectation{std::move(*f)};
}

std::optional<WithinExpectation> ReadWithin(YamlDocument* doc, const YAML::Node& node,
                                            const std::string& key_path, const MetricIds& ids) {
  MapReader r(doc, node, key_path);
  if (!r.valid()) return std::nullopt;
  WithinExpectation w;
  if (r.Has("motion_s") == r.Has("time_s")) {
    doc->Error(node, key_path, "give exactly one of motion_s (the robot's motion time) and time_s");
  }
  w.motion_time = r.Has("motion_s");
  w.limit_s = r.Number(w.motion_time ? "motion_s" : "time_s", 0.0, 0.0, kMaxWindowS);
  // `after: kidnap` or `after: {event: kidnap, field: value ...}`.
  const YAML::Node after = r.Child("after", true);
  std::optional<EventFilter> anchor;
  if (after.IsMap()) {
    MapReader a(doc, after, r.PathOf("after"));
    anchor = ReadFilter(a, "event", {}, ids);
    a.Finish();
  } else if (after.IsDefined()) {
    YAML::Node wrapped;
    wrapped["event"] = after;
    MapReader a(doc, wrapped, r.PathOf("after"));
    anchor = ReadFilter(a, "event", {}, ids);
  }
  std::optional<EventFilter> event = ReadFilter(r, "event", {"after", "motion_s", "time_s"}, ids);
  r.Finish();
  if (!anchor || !event) return std::nullopt;
  w.after = std::move(*anchor);
  w.event = std::move(*event);
  return w;
}

}  // namespace

std::vector<Expectation> ReadExpectations(MapReader& top, const MetricIds& ids) {
  std::vector<Expectation> out;
  YamlDocument* doc = top.doc();
  const YAML::Node list = top.Child("expect");
  if (!list.IsDefined() || list.IsNull()) return out;
  if (!list.IsSequence()) {
    doc->Error(list, "expect", "expected a list of expectations");
    return out;
  }
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node item = list[i];
    const std::string path = IndexPath("expect", i);
    Expectation e;
    e.line = static_cast<int>(item.Mark().line) + 1;
    if (item.IsScalar()) {
      e.text = item.Scalar();
      if (auto m = ReadMetric(doc, item, path, ids, false)) out.push_back({e.text, e.line, *m});
      continue;
    }
    if (!item.IsMap() || item.size() != 1) {
      doc->Error(item, path,
                 "expected 'metric OP value' or one of all:, any:, never:, within: (one key)");
      continue;
    }
    const std::string key = item.begin()->first.as<std::string>();
    const YAML::Node body = item.begin()->second;
    const std::string body_path = path + "." + key;
    if (key == "all" || key == "any") {
      e.text = key + ": " + (body.IsScalar() ? body.Scalar() : "");
      if (auto m = ReadMetric(doc, body, body_path, ids, key == "any")) {
        out.push_back({e.text, e.line, *m});
      }
    } else if (key == "never") {
      if (auto n = ReadNever(doc, body, body_path, ids)) {
        out.push_back({"never " + n->event.ToString(), e.line, *n});
      }
    } else if (key == "within") {
      if (auto w = ReadWithin(doc, body, body_path, ids)) {
        const std::string window = (w->motion_time ? "motion_s " : "time_s ");
        std::ostringstream limit;
        limit << w->limit_s;
        out.push_back({w->event.ToString() + " within " + window + limit.str() + " after " +
                           w->after.ToString(),
                       e.line, *w});
      }
    } else {
      doc->Error(item, body_path, "unknown expectation kind (all, any, never, within)");
    }
  }
  return out;
}

}  // namespace pavilion::scenarios
