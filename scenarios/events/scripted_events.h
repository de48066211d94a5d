#pragma once

// The built-in scripted events: push (an impulse on a body or robot),
// teleport (a body or robot moved by hand: the kidnapped robot) and door
// (a hinged door opened or closed).

#include <Eigen/Core>
#include <string>

#include "core/types/pose2.h"
#include "scenarios/events/event_registry.h"

namespace pavilion::scenarios {

class PushEvent : public ScenarioEvent {
 public:
  PushEvent(std::string target, const Eigen::Vector2d& impulse_ns)
      : target_(std::move(target)), impulse_ns_(impulse_ns) {}
  std::string type() const override { return "push"; }
  EventFields Apply(const EventContext& context) const override;
  const std::string& target() const { return target_; }
  const Eigen::Vector2d& impulse_ns() const { return impulse_ns_; }

 private:
  std::string target_;
  Eigen::Vector2d impulse_ns_;
};

class TeleportEvent : public ScenarioEvent {
 public:
  TeleportEvent(std::string target, const core::Pose2& pose)
      : target_(std::move(target)), pose_(pose) {}
  std::string type() const override { return "teleport"; }
  EventFields Apply(const EventContext& context) const override;
  const std::string& target() const { return target_; }
  const core::Pose2& pose() const { return pose_; }

 private:
  std::string target_;
  core::Pose2 pose_;
};

class DoorEvent : public ScenarioEvent {
 public:
  DoorEvent(std::string door, bool open) : door_(std::move(door)), open_(open) {}
  std::string type() const override { return "door"; }
  EventFields Apply(const EventContext& context) const override;
  const std::string& door() const { return door_; }
  bool open() const { return open_; }

 private:
  std::string door_;
  bool open_;
};

// Registers push, teleport and door with their readers.
void RegisterScriptedEvents(EventRegistry* registry);

}  // namespace pavilion::scenarios
