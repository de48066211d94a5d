#include "nav/mission/mission.h"

#include <numeric>

namespace pavilion::nav {

const char* ToString(AbortReason reason) {
  switch (reason) {
    case AbortReason::kUnreachable:
      return "unreachable";
    case AbortReason::kTimeout:
      return "timeout";
    case AbortReason::kLost:
      return "lost";
    case AbortReason::kBlocked:
      return "blocked";
  }
  return "unknown";
}

const char* ToString(NavigationEvent::Type type) {
  switch (type) {
    case NavigationEvent::Type::kMissionStarted:
      return "mission_started";
    case NavigationEvent::Type::kMissionCompleted:
      return "mission_completed";
    case NavigationEvent::Type::kMissionAborted:
      return "mission_aborted";
    case NavigationEvent::Type::kBlocked:
      return "blocked";
    case NavigationEvent::Type::kReplanned:
      return "replanned";
    case NavigationEvent::Type::kDeadlockDetected:
      return "deadlock_detected";
    case NavigationEvent::Type::kDeadlockResolved:
      return "deadlock_resolved";
    case NavigationEvent::Type::kDeadlockUnresolved:
      return "deadlock_unresolved";
    case NavigationEvent::Type::kUncertaintyHold:
      return "uncertainty_hold";
    case NavigationEvent::Type::kUncertaintyHoldEnded:
      return "uncertainty_hold_ended";
  }
  return "unknown";
}

int NavigationFigures::missions_aborted_total() const {
  return std::accumulate(missions_aborted.begin(), missions_aborted.end(), 0);
}

}  // namespace pavilion::nav
