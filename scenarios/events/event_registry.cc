#include "scenarios/events/event_registry.h"

#include <stdexcept>

#include "scenarios/events/crowd_events.h"
#include "scenarios/events/odometry_bias_event.h"
#include "scenarios/events/scripted_events.h"
#include "scenarios/events/sensor_fault_event.h"

namespace pavilion::scenarios {

core::RandomStream& EventStreams::Get(const std::string& name) {
  auto it = streams_.find(name);
  if (it == streams_.end()) {
    it = streams_
             .emplace(name, core::RandomStream(seed_, core::RandomStream::StreamId(name.c_str())))
             .first;
  }
  return it->second;
}

EventRegistry& EventRegistry::Global() {
  static EventRegistry* registry = [] {
    auto* r = new EventRegistry;
    RegisterScriptedEvents(r);
    RegisterCrowdEvents(r);
    RegisterSensorFaultEvent(r);
    RegisterOdometryBiasEvent(r);
    return r;
  }();
  return *registry;
}

void EventRegistry::Register(const std::string& type, EventReader reader) {
  if (Find(type) != nullptr) {
    throw std::invalid_argument("event type '" + type + "' is registered already");
  }
  readers_.emplace_back(type, std::move(reader));
}

const EventReader* EventRegistry::Find(const std::string& type) const {
  for (const auto& [name, reader] : readers_) {
    if (name == type) return &reader;
  }
  return nullptr;
}

std::vector<std::string> EventRegistry::types() const {
  std::vector<std::string> names;
  for (const auto& entry : readers_) names.push_back(entry.first);
  return names;
}

}  // namespace pavilion::scenarios
