#pragma once

// Events of the crowd (sim/crowd/): `spawn_group`, a burst of visitors.

#include <Eigen/Core>

#include "scenarios/events/event.h"
#include "scenarios/events/event_registry.h"

namespace pavilion::scenarios {

// A party of `count` visitors walks in at a spot (a coach party, a school
// class): the crowd's free bodies placed on free floor around it, starting
// their visit. Fewer come when the pool or the spot has no room; the record
// says how many.
class SpawnGroupEvent : public ScenarioEvent {
 public:
  SpawnGroupEvent(const Eigen::Vector2d& at_m, int count) : at_m_(at_m), count_(count) {}
  std::string type() const override { return "spawn_group"; }
  EventFields Apply(const EventContext& context) const override;

 private:
  Eigen::Vector2d at_m_;
  int count_;
};

// Registers spawn_group: {at: [x, y] | place: name, count: N}. Errors (at
// load): no crowd in the scenario, a count above the crowd's pool, a spot off
// the floor or inside a wall or exhibit, an unknown place.
void RegisterCrowdEvents(EventRegistry* registry);

}  // namespace pavilion::scenarios
