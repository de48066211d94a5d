#include "scenarios/output/report_data.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string_view>

namespace pavilion::scenarios {
namespace {

// Timeline lanes in this order (what went wrong first), unknown kinds after
// them by name. Run start and end and mission starts and completions stay
// off the timeline: the missions chart shows those.
constexpr std::array<std::string_view, 26> kLaneOrder{
    "collision: visible wall or exhibit",
    "collision: invisible object",
    "collision: visitor",
    "collision: robot",
    "collision",
    "lost",
    "relocalized",
    "localized",
    "hypotheses",
    "kidnap",
    "teleport",
    "push",
    "sensor_fault",
    "odometry_bias",
    "door",
    "spawn_group",
    "mission_aborted",
    "blocked",
    "uncertainty_hold",
    "replanned",
    "deadlock_detected",
    "deadlock_resolved",
    "deadlock_unresolved",
    "near_miss",
    "bumper",
    "route_done",
};
// The lane of the kinds beyond ReportSeriesOptions::max_lanes, last.
constexpr std::string_view kOtherLane = "other";
constexpr std::array<std::string_view, 5> kOffTimeline{"run_started", "run_finished",
                                                       "mission_started", "mission_completed",
                                                       "uncertainty_hold_ended"};
// Fields holding where an event happened, [x, y, ...] in the world frame.
constexpr std::array<const char*, 4> kPositionFields{"point_m", "after", "pose", "at"};

std::size_t LaneRank(const std::string& label) {
  if (label == kOtherLane) return kLaneOrder.size() + 1;
  const auto it = std::find(kLaneOrder.begin(), kLaneOrder.end(), label);
  return static_cast<std::size_t>(it - kLaneOrder.begin());
}

std::vector<std::string_view> SplitCsv(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(line.substr(start, comma == std::string_view::npos ? comma : comma - start));
    if (comma == std::string_view::npos) return fields;
    start = comma + 1;
  }
}

std::optional<double> ParseDouble(std::string_view text) {
  double v = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(v)) {
    return std::nullopt;
  }
  return v;
}

// A sample into a series, its time held at the series' last (lines of a log
// may be a few milliseconds out of order).
void AddInOrder(SeriesDecimator* series, double t_s, double value) {
  series->Add(series->empty() ? t_s : std::max(t_s, series->last_t()), value);
}

std::optional<MapMarkers::Marker> PositionOf(const nlohmann::json& event, double t_s) {
  for (const char* field : kPositionFields) {
    const auto it = event.find(field);
    if (it == event.end() || !it->is_array() || it->size() < 2) continue;
    if (!(*it)[0].is_number() || !(*it)[1].is_number()) continue;
    return MapMarkers::Marker{t_s, (*it)[0].get<double>(), (*it)[1].get<double>()};
  }
  return std::nullopt;
}

// Reads events.jsonl into `series` (lanes and markers by label, unordered).
class EventReader {
 public:
  EventReader(const ReportSeriesOptions& options, EventSeries* series)
      : options_(options), series_(series) {}

  void Line(const std::string& line) {
    const nlohmann::json event = nlohmann::json::parse(line, nullptr, false);
    if (!event.is_object() || !event.contains("time_s") || !event["time_s"].is_number() ||
        !event.contains("type") || !event["type"].is_string()) {
      ++series_->skipped_lines;
      return;
    }
    ++series_->events;
    const double t_s = event["time_s"].get<double>();
    const std::string type = event["type"].get<std::string>();
    if (!std::isfinite(t_s)) return;
    last_t_s_ = std::max(last_t_s_, t_s);
    if (type == "run_finished") finished_s_ = t_s;
    Missions(type, t_s);
    if (std::find(kOffTimeline.begin(), kOffTimeline.end(), type) != kOffTimeline.end()) return;
    const auto cls = event.find("with");  // a robot's contact: what it touched
    std::string label =
        EventLaneLabel(type, cls != event.end() && cls->is_string() ? cls->get<std::string>() : "");
    if (!lanes_.contains(label) && lanes_.size() >= options_.max_lanes) {
      label = kOtherLane;
    }
    auto [lane, added] =
        lanes_.try_emplace(label, EventLane{label, SeriesDecimator(options_.max_points)});
    AddInOrder(&lane->second.times, t_s, 0.0);
    if (const std::optional<MapMarkers::Marker> at = PositionOf(event, t_s)) {
      auto [markers, fresh] = markers_.try_emplace(label, MapMarkers{label, {}, 0, 1});
      markers->second.Add(*at, options_.max_markers);
    }
  }

  // Ordered lanes and markers, and the missions' final counts at the end.
  void Finish() {
    series_->end_s = finished_s_.value_or(last_t_s_);
    if (any_mission_) {
      AddInOrder(&series_->missions_started, series_->end_s, static_cast<double>(started_));
      AddInOrder(&series_->missions_completed, series_->end_s, static_cast<double>(completed_));
      AddInOrder(&series_->missions_aborted, series_->end_s, static_cast<double>(aborted_));
    }
    std::vector<std::string> labels;
    for (const auto& [label, lane] : lanes_) labels.push_back(label);
    std::stable_sort(labels.begin(), labels.end(), [](const std::string& a, const std::string& b) {
      return LaneRank(a) < LaneRank(b);  // std::map gave them by name
    });
    for (const std::string& label : labels) {
      series_->lanes.push_back(std::move(lanes_.at(label)));
      if (markers_.contains(label)) series_->markers.push_back(std::move(markers_.at(label)));
    }
  }

 private:
  void Missions(const std::string& type, double t_s) {
    std::int64_t* count = type == "mission_started"     ? &started_
                          : type == "mission_completed" ? &completed_
                          : type == "mission_aborted"   ? &aborted_
                                                        : nullptr;
    if (!count) return;
    if (!any_mission_) {
      // The cumulative counts start from zero at the run's start.
      for (SeriesDecimator* s :
           {&series_->missions_started, &series_->missions_completed, &series_->missions_aborted}) {
        s->Add(0.0, 0.0);
      }
      any_mission_ = true;
    }
    ++*count;
    SeriesDecimator* series = count == &started_     ? &series_->missions_started
                              : count == &completed_ ? &series_->missions_completed
                                                     : &series_->missions_aborted;
    AddInOrder(series, t_s, static_cast<double>(*count));
  }

  const ReportSeriesOptions& options_;
  EventSeries* series_;
  std::map<std::string, EventLane> lanes_;
  std::map<std::string, MapMarkers> markers_;
  std::int64_t started_ = 0;
  std::int64_t completed_ = 0;
  std::int64_t aborted_ = 0;
  bool any_mission_ = false;
  double last_t_s_ = 0.0;
  std::optional<double> finished_s_;
};

// Column indices of localization.csv's header, by name.
struct LocalizationColumns {
  std::size_t time = 0, id = 0, error = 0, frontal = 0, lateral = 0;
  std::size_t needed = 0;  // fields a row must have

  static std::optional<LocalizationColumns> From(std::string_view header) {
    const std::vector<std::string_view> names = SplitCsv(header);
    const auto index = [&](std::string_view name) -> std::optional<std::size_t> {
      const auto it = std::find(names.begin(), names.end(), name);
      if (it == names.end()) return std::nullopt;
      return static_cast<std::size_t>(it - names.begin());
    };
    const auto t = index("time_s"), id = index("id"), e = index("position_error_m"),
               f = index("two_sigma_frontal_m"), l = index("two_sigma_lateral_m");
    if (!t || !id || !e || !f || !l) return std::nullopt;
    LocalizationColumns c{*t, *id, *e, *f, *l, 0};
    c.needed = 1 + std::max({c.time, c.id, c.error, c.frontal, c.lateral});
    return c;
  }
};

}  // namespace

void MapMarkers::Add(const Marker& m, std::size_t max_markers) {
  ++seen;
  if ((seen - 1) % stride != 0) return;
  markers.push_back(m);
  if (markers.size() <= std::max<std::size_t>(max_markers, 1)) return;
  // Keep every other one: the kept are then every (2 stride)-th of all seen.
  std::size_t kept = 0;
  for (std::size_t k = 0; k < markers.size(); k += 2) markers[kept++] = markers[k];
  markers.resize(kept);
  stride *= 2;
}

std::string EventLaneLabel(const std::string& type, const std::string& collision_class) {
  if (type != "collision" || collision_class.empty()) return type;
  if (collision_class == "wall_or_exhibit_visible" || collision_class == "visible") {
    return "collision: visible wall or exhibit";
  }
  if (collision_class == "invisible_object" || collision_class == "invisible") {
    return "collision: invisible object";
  }
  std::string words = collision_class;
  std::replace(words.begin(), words.end(), '_', ' ');
  return "collision: " + words;
}

std::vector<RobotErrorSeries> ReadLocalizationSeries(const std::filesystem::path& path,
                                                     const std::vector<std::string>& robot_order,
                                                     const ReportSeriesOptions& options) {
  std::ifstream in(path);
  std::string line;
  if (!in || !std::getline(in, line)) return {};
  const std::optional<LocalizationColumns> c = LocalizationColumns::From(line);
  if (!c) return {};
  std::map<std::string, RobotErrorSeries> by_id;
  while (std::getline(in, line)) {
    const std::vector<std::string_view> f = SplitCsv(line);
    if (f.size() < c->needed || f[c->id].empty()) continue;
    const std::optional<double> t = ParseDouble(f[c->time]), e = ParseDouble(f[c->error]),
                                fr = ParseDouble(f[c->frontal]), la = ParseDouble(f[c->lateral]);
    if (!t || !e || !fr || !la) continue;
    const std::string id(f[c->id]);
    auto it = by_id.find(id);
    if (it == by_id.end()) {
      const SeriesDecimator empty(options.max_points);
      it = by_id.emplace(id, RobotErrorSeries{id, empty, empty, empty}).first;
    }
    AddInOrder(&it->second.position_error_m, *t, *e);
    AddInOrder(&it->second.two_sigma_frontal_m, *t, *fr);
    AddInOrder(&it->second.two_sigma_lateral_m, *t, *la);
  }
  std::vector<RobotErrorSeries> out;
  for (const std::string& id : robot_order) {
    if (const auto it = by_id.find(id); it != by_id.end()) {
      out.push_back(std::move(it->second));
      by_id.erase(it);
    }
  }
  for (auto& [id, series] : by_id) out.push_back(std::move(series));
  return out;
}

EventSeries ReadEventSeries(const std::filesystem::path& path, const ReportSeriesOptions& options) {
  EventSeries series{SeriesDecimator(options.max_points),
                     SeriesDecimator(options.max_points),
                     SeriesDecimator(options.max_points),
                     {},
                     {},
                     0,
                     0,
                     0.0};
  std::ifstream in(path);
  if (!in) return series;
  EventReader reader(options, &series);
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty()) reader.Line(line);
  }
  reader.Finish();
  return series;
}

ReportSeries ReadReportSeries(const std::filesystem::path& out,
                              const std::vector<std::string>& robot_order,
                              const ReportSeriesOptions& options) {
  return {ReadLocalizationSeries(out / "localization.csv", robot_order, options),
          ReadEventSeries(out / "events.jsonl", options)};
}

}  // namespace pavilion::scenarios
