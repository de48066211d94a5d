#pragma once

// `random:` entries of the event timeline (issue 17): "a kidnap of a random
// robot every 20 simulated minutes". An `events:` entry may carry a `random:`
// block instead of `at_s`:
//
//   - type: kidnap
//     random: {every_s: 1200}   # or rate_per_h: 3, or count: 5; optional
//                               # start_s, end_s, robots: [ids]
//     min_distance_m: 2         # the type's own keys, as for a fixed event
//
// At load time it expands into ordinary timed events of its type, each read
// and checked by the type's reader as a hand-written entry would be. Times in
// the window [start_s, end_s) (default: from 0 to the run's duration after
// --duration):
//   every_s:    start_s + k every_s, k = 1, 2, ... (periodic, no random phase);
//   rate_per_h: a Poisson process of that rate (exponential gaps);
//   count:      that many times uniform in the window, sorted.
// For a type that names a robot (kidnap, sensor_fault, odometry_bias: robot;
// push: body) and an entry that names none, each event's robot is drawn
// uniformly from `robots` (default: every robot of the scenario). Times, then
// robots in time order, come from the stream "random/<entry index>" of the
// scenario seed, so other entries' draws never shift them. door and teleport
// are not supported. The events' records in events.jsonl carry "random": true.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/random/random_stream.h"
#include "scenarios/config/yaml_reader.h"
#include "scenarios/events/event.h"
#include "scenarios/events/event_registry.h"

namespace pavilion::scenarios {

// When a random entry's events happen (the keys of its `random:` block).
struct RandomTimes {
  enum class Kind { kEvery, kRate, kCount };
  Kind kind = Kind::kCount;
  double every_s = 0.0;     // kEvery: the period, s, > 0
  double rate_per_h = 0.0;  // kRate: events per simulated hour, >= 0
  int count = 0;            // kCount: how many, >= 0
  double start_s = 0.0;     // the window, s: [start_s, end_s)
  double end_s = 0.0;
};

// The times of `times`, ascending, drawn from `stream` (none for kEvery).
std::vector<double> DrawRandomTimes(const RandomTimes& times, core::RandomStream* stream);

// What an entry expands against: the seed and durations of the run.
struct RandomEventRun {
  std::uint64_t seed = 0;        // the scenario's, after --seed
  double file_duration_s = 0.0;  // the file's duration_s: start_s, end_s no later
  double duration_s = 0.0;       // the run's, after --duration: the window's default end
};

// An expanded event: the type's own event, its records marked "random": true.
class RandomlyTimedEvent : public ScenarioEvent {
 public:
  explicit RandomlyTimedEvent(std::shared_ptr<const ScenarioEvent> event)
      : event_(std::move(event)) {}
  std::string type() const override { return event_->type(); }
  EventFields Apply(const EventContext& context) const override;
  bool ongoing() const override { return event_->ongoing(); }
  EventFields Continue(const EventContext& context) const override;
  const ScenarioEvent& event() const { return *event_; }

 private:
  std::shared_ptr<const ScenarioEvent> event_;
};

// Expands the `events:` entry `r` (item `index` of the list), which has a
// `random` key, into `out` (unsorted); reports its problems through r's
// document as file:line: key: message, and its unknown keys (r.Finish()).
void ExpandRandomEvent(MapReader& r, std::size_t index, const EventTargets& targets,
                       const RandomEventRun& run, std::vector<TimedEvent>* out);

}  // namespace pavilion::scenarios
