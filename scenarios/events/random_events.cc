#include "scenarios/events/random_events.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

namespace pavilion::scenarios {
namespace {

constexpr double kSecondsPerHour = 3600.0;
// Events one random entry may expand into, at most (chosen: bounds the
// timeline's memory, as the loader's bound on every_s repeats does).
constexpr std::int64_t kMaxRandomEvents = 100000;
constexpr double kMaxTimeS = 1e7;  // the scenario's bound on duration_s
constexpr double kMaxRatePerH = 1e6;

// The types random times are supported for, and the key naming their robot
// ("": the type takes none).
struct RandomType {
  const char* type;
  const char* robot_key;
};
constexpr RandomType kRandomTypes[] = {{"kidnap", "robot"},
                                       {"push", "body"},
                                       {"sensor_fault", "robot"},
                                       {"odometry_bias", "robot"},
                                       {"spawn_group", ""}};

// A number as people write it: 60, 2.5.
std::string Format(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", value);
  return buf;
}

// A number > 0 under `key` of `b`; nullopt after reporting a problem.
std::optional<double> Positive(MapReader& b, const std::string& key, double hi) {
  const std::optional<double> v = b.RequiredNumber(key, -kMaxTimeS, hi);
  if (v && !(*v > 0.0)) {
    b.doc()->Error(b.Child(key), b.PathOf(key), "must be > 0, got " + Format(*v));
    return std::nullopt;
  }
  return v;
}

// The window's start and end (clipped to the run's duration); false after a report.
bool ReadWindow(MapReader& b, const RandomEventRun& run, RandomTimes* t) {
  const std::string after =
      "after the scenario's duration_s (" + Format(run.file_duration_s) + " s)";
  t->start_s = b.Number("start_s", 0.0, 0.0, kMaxTimeS);
  if (t->start_s > run.file_duration_s) {
    b.doc()->Error(b.Child("start_s"), b.PathOf("start_s"), "the window starts " + after);
    return false;
  }
  t->end_s = b.Number("end_s", run.duration_s, 0.0, kMaxTimeS);
  if (b.Has("end_s") && t->end_s > run.file_duration_s) {
    b.doc()->Error(b.Child("end_s"), b.PathOf("end_s"), "the window ends " + after);
    return false;
  }
  if (b.Has("end_s") && t->end_s <= t->start_s) {
    b.doc()->Error(b.Child("end_s"), b.PathOf("end_s"), "must be after start_s");
    return false;
  }
  t->end_s = std::min(t->end_s, run.duration_s);
  return true;
}

// The `random:` block's times; nullopt after reporting a problem.
std::optional<RandomTimes> ReadTimes(MapReader& b, const RandomEventRun& run) {
  std::vector<std::string> given;
  for (const char* key : {"every_s", "rate_per_h", "count"}) {
    if (b.Has(key)) given.push_back(key);
  }
  if (given.size() != 1) {
    const std::string what = "give one of every_s, rate_per_h or count";
    if (given.empty()) b.doc()->Error(b.node(), b.path(), what);
    if (given.size() > 1)
      b.doc()->Error(b.Child(given[1]), b.PathOf(given[1]), what + ", not both");
    return std::nullopt;
  }
  RandomTimes t;
  if (!ReadWindow(b, run, &t)) return std::nullopt;
  const double window_s = std::max(0.0, t.end_s - t.start_s);
  double expected = 0.0;  // events in the window (mean)
  if (given[0] == "every_s") {
    t.kind = RandomTimes::Kind::kEvery;
    const std::optional<double> every_s = Positive(b, "every_s", kMaxTimeS);
    if (!every_s) return std::nullopt;
    t.every_s = *every_s;
    expected = window_s / t.every_s;
  } else if (given[0] == "rate_per_h") {
    t.kind = RandomTimes::Kind::kRate;
    const std::optional<double> rate = b.RequiredNumber("rate_per_h", 0.0, kMaxRatePerH);
    if (!rate) return std::nullopt;
    t.rate_per_h = *rate;
    expected = window_s * t.rate_per_h / kSecondsPerHour;
  } else {
    t.kind = RandomTimes::Kind::kCount;
    t.count = static_cast<int>(b.Integer("count", 0, 0, kMaxRandomEvents));
  }
  if (expected > static_cast<double>(kMaxRandomEvents)) {
    b.doc()->Error(b.Child(given[0]), b.PathOf(given[0]),
                   "gives more than " + std::to_string(kMaxRandomEvents) + " events in the run");
    return std::nullopt;
  }
  return t;
}

// The robots `random.robots` lists (checked), or every robot of the scenario.
std::vector<std::string> ReadRobotPool(MapReader& b, const EventTargets& targets) {
  if (!b.Has("robots")) return {targets.robots.begin(), targets.robots.end()};
  const YAML::Node list = b.Child("robots");
  if (!list.IsSequence() || list.size() == 0) {
    b.doc()->Error(list, b.PathOf("robots"), "expected a non-empty list of robot ids");
    return {};
  }
  std::vector<std::string> pool;
  for (std::size_t j = 0; j < list.size(); ++j) {
    const std::string path = IndexPath(b.PathOf("robots"), j);
    const std::string id = list[j].IsScalar() ? list[j].Scalar() : "";
    if (!targets.robots.contains(id)) {
      b.doc()->Error(list[j], path, id.empty() ? "expected a robot id" : "no robot '" + id + "'");
      return {};
    }
    pool.push_back(id);
  }
  return pool;
}

const RandomType* FindRandomType(const std::string& type) {
  for (const RandomType& t : kRandomTypes) {
    if (type == t.type) return &t;
  }
  return nullptr;
}

// The `random:` block of entry `r` and the robots of its events (empty when
// the entry names its robot or the type takes none); false after a report.
bool ReadRandomBlock(MapReader& r, const RandomType& type, const RandomEventRun& run,
                     const EventTargets& targets, std::optional<RandomTimes>* times,
                     std::vector<std::string>* pool) {
  MapReader b(r.doc(), r.Child("random"), r.PathOf("random"));
  if (!b.valid()) return false;
  *times = ReadTimes(b, run);
  if (!times->has_value()) return false;
  const std::string robot_key = type.robot_key;
  if (b.Has("robots") && (robot_key.empty() || r.Has(robot_key))) {
    b.doc()->Error(b.Child("robots"), b.PathOf("robots"),
                   robot_key.empty() ? std::string(type.type) + " takes no robot"
                                     : "give " + robot_key + " or random.robots, not both");
  } else if (!robot_key.empty() && !r.Has(robot_key)) {
    *pool = ReadRobotPool(b, targets);
    if (pool->empty() && !b.Has("robots")) {
      b.doc()->Error(b.node(), b.path(), "the scenario has no robots to draw from");
    }
    if (pool->empty()) return false;
  }
  b.Finish();
  return true;
}

}  // namespace

std::vector<double> DrawRandomTimes(const RandomTimes& t, core::RandomStream* stream) {
  std::vector<double> times;
  switch (t.kind) {
    case RandomTimes::Kind::kEvery:
      for (std::int64_t k = 1; t.start_s + k * t.every_s < t.end_s; ++k) {
        times.push_back(t.start_s + k * t.every_s);
      }
      break;
    case RandomTimes::Kind::kRate: {
      if (!(t.rate_per_h > 0.0)) break;
      const double mean_gap_s = kSecondsPerHour / t.rate_per_h;
      // Exponential gaps by inversion (1 - u is in (0, 1]).
      for (double at_s = t.start_s;;) {
        at_s -= mean_gap_s * std::log(1.0 - stream->Uniform());
        if (at_s >= t.end_s || std::ssize(times) >= kMaxRandomEvents) break;
        times.push_back(at_s);
      }
      break;
    }
    case RandomTimes::Kind::kCount:
      if (t.end_s <= t.start_s) break;
      for (int k = 0; k < t.count; ++k) times.push_back(stream->Uniform(t.start_s, t.end_s));
      std::sort(times.begin(), times.end());
      break;
  }
  return times;
}

EventFields RandomlyTimedEvent::Apply(const EventContext& context) const {
  EventFields fields = event_->Apply(context);
  if (!fields.is_null()) fields["random"] = true;
  return fields;
}

EventFields RandomlyTimedEvent::Continue(const EventContext& context) const {
  EventFields fields = event_->Continue(context);
  if (!fields.is_null()) fields["random"] = true;
  return fields;
}

void ExpandRandomEvent(MapReader& r, std::size_t index, const EventTargets& targets,
                       const RandomEventRun& run, std::vector<TimedEvent>* out) {
  YamlDocument* doc = r.doc();
  const std::size_t errors_before = doc->diagnostics().size();
  if (r.Has("at_s")) doc->Error(r.Child("at_s"), r.PathOf("at_s"), "give at_s or random, not both");
  if (r.Has("every_s")) {
    doc->Error(r.Child("every_s"), r.PathOf("every_s"),
               "give every_s inside random: {every_s: ...}, not beside it");
  }
  const EventRegistry& registry = EventRegistry::Global();
  const std::vector<std::string> types = registry.types();
  const std::string type_name = r.Choice("type", types, types.front(), true);
  if (doc->diagnostics().size() > errors_before) return;
  const RandomType* type = FindRandomType(type_name);
  std::optional<RandomTimes> window;
  std::vector<std::string> pool;
  if (type == nullptr) {
    std::string supported;
    for (const RandomType& t : kRandomTypes) {
      supported += (supported.empty() ? "" : ", ") + std::string(t.type);
    }
    doc->Error(r.Child("random"), r.PathOf("random"),
               "random times are not supported for " + type_name +
                   " events (supported: " + supported + ")");
  } else {
    ReadRandomBlock(r, *type, run, targets, &window, &pool);
  }
  // After a problem, the type's keys are left unread (and unreported).
  if (!window || doc->diagnostics().size() > errors_before) return;
  core::RandomStream stream(
      run.seed, core::RandomStream::StreamId(("random/" + std::to_string(index)).c_str()));
  const std::vector<double> times = DrawRandomTimes(*window, &stream);
  // The robots from a stream of their own: the k-th event's robot is the
  // k-th draw whatever the window's length, so that a run shortened with
  // --duration (the demo) is the first part of the full run.
  core::RandomStream robot_stream(
      run.seed,
      core::RandomStream::StreamId(("random/" + std::to_string(index) + "/robots").c_str()));
  std::vector<std::string> robots;
  for (std::size_t k = 0; k < times.size() && !pool.empty(); ++k) {
    robots.push_back(
        pool[static_cast<std::size_t>(robot_stream.UniformInt(0, std::ssize(pool) - 1))]);
  }
  // Each event is read by its type's reader, with its drawn robot written into
  // the entry; with no time in the window, once all the same, to check the keys.
  YAML::Node entry = r.node();
  const std::size_t errors = doc->diagnostics().size();
  const EventReader& read = *registry.Find(type_name);
  for (std::size_t k = 0; k < std::max<std::size_t>(times.size(), 1); ++k) {
    if (!pool.empty()) entry[type->robot_key] = robots.empty() ? pool.front() : robots[k];
    MapReader again(doc, entry, r.path());
    const std::shared_ptr<const ScenarioEvent> event = read(k == 0 ? r : again, targets);
    if (!event || doc->diagnostics().size() > errors) break;
    if (k < times.size()) {
      out->push_back(TimedEvent{times[k], std::make_shared<const RandomlyTimedEvent>(event)});
    }
  }
  if (!pool.empty()) entry.remove(type->robot_key);
  r.Finish();
}

}  // namespace pavilion::scenarios
