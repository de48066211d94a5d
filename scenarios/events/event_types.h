#pragma once

// Every event type a run can write to events.jsonl: the detected ones the
// runner emits, the navigation's (nav::NavigationEvent) and the scripted
// types of the event registry. Expectations (scenarios/expect/) check the
// event names they use against it at load time.

#include <set>
#include <string>

namespace pavilion::scenarios {

// Detected events the runner emits (besides the navigation's).
inline constexpr const char* kRunStarted = "run_started";
inline constexpr const char* kRunFinished = "run_finished";
inline constexpr const char* kCollision = "collision";
inline constexpr const char* kBumper = "bumper";
inline constexpr const char* kLost = "lost";
inline constexpr const char* kHypotheses = "hypotheses";
inline constexpr const char* kLocalized = "localized";
inline constexpr const char* kRelocalized = "relocalized";
inline constexpr const char* kRouteDone = "route_done";
inline constexpr const char* kScanLogStopped = "scan_log_stopped";
// A robot's base left the floor's rectangle: the world has no floor there,
// and the run ends (RunSummary::ended_early).
inline constexpr const char* kRobotLeftFloor = "robot_left_floor";
inline constexpr const char* kNearMiss = "near_miss";  // two robots' hulls < 0.2 m apart
// Two or more robot centres within 1 m of the same station node.
inline constexpr const char* kStationConflict = "station_conflict";

std::set<std::string> KnownEventTypes();

}  // namespace pavilion::scenarios
