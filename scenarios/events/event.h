#pragma once

// The scenario timeline's seam: a scripted event acts on the run at its time
// and describes itself in events.jsonl. Push, teleport and door are built in
// (scripted_events.h); a new type registers a reader (event_registry.h) and
// needs no change to the runner.

#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "sim/world/world.h"

namespace pavilion::scenarios {

// The fields of an events.jsonl record after its time_s and type, in order.
using EventFields = nlohmann::ordered_json;

// What an event may act on: the world, the ids of its robots and bodies, and
// the state snapshot the tick's work reads (kept in step with teleports).
struct EventContext {
  sim::World* world = nullptr;
  const std::map<std::string, int>* robot_index = nullptr;  // world robot index by id
  const std::map<std::string, int>* body_index = nullptr;   // world body index by id
  sim::TickSnapshot* snapshot = nullptr;
};

class ScenarioEvent {
 public:
  virtual ~ScenarioEvent() = default;
  // The record's `type` (the key `type` of the scenario file).
  virtual std::string type() const = 0;
  // Acts on the run before the physics step it is due at; returns its record's fields.
  virtual EventFields Apply(const EventContext& context) const = 0;
};

// An event of the timeline with the time it is due at.
struct TimedEvent {
  double at_s = 0.0;
  std::shared_ptr<const ScenarioEvent> event;
};

}  // namespace pavilion::scenarios
