#include "scenarios/events/event_types.h"

#include "nav/mission/mission.h"
#include "scenarios/events/event_registry.h"

namespace pavilion::scenarios {

std::set<std::string> KnownEventTypes() {
  std::set<std::string> types{kRunStarted,    kRunFinished,    kCollision, kBumper,
                              kLost,          kHypotheses,     kLocalized, kRelocalized,
                              kRouteDone,     kScanLogStopped, kNearMiss,  kStationConflict,
                              kRobotLeftFloor};
  using Type = nav::NavigationEvent::Type;
  for (Type t : {Type::kMissionStarted, Type::kMissionCompleted, Type::kMissionAborted,
                 Type::kBlocked, Type::kReplanned, Type::kDeadlockDetected, Type::kDeadlockResolved,
                 Type::kDeadlockUnresolved}) {
    types.insert(nav::ToString(t));
  }
  for (const std::string& t : EventRegistry::Global().types()) types.insert(t);
  return types;
}

}  // namespace pavilion::scenarios
