#include "scenarios/events/scripted_events.h"

#include <memory>
#include <set>

#include "scenarios/events/kidnap_event.h"

namespace pavilion::scenarios {
namespace {

// The target key's id, checked against the ids the scenario has.
std::string ReadTarget(MapReader& r, const std::string& key, const std::set<std::string>& known) {
  const std::string target = r.RequiredString(key).value_or("");
  if (!target.empty() && !known.contains(target)) {
    r.doc()->Error(r.Child(key), r.PathOf(key), "no " + key + " '" + target + "'");
  }
  return target;
}

}  // namespace

EventFields PushEvent::Apply(const EventContext& c) const {
  if (c.robot_index->contains(target_)) {
    c.world->ApplyRobotImpulse(c.robot_index->at(target_), impulse_ns_);
  } else {
    c.world->ApplyImpulse(c.body_index->at(target_), impulse_ns_);
  }
  return EventFields{{"body", target_}, {"impulse_ns", {impulse_ns_.x(), impulse_ns_.y()}}};
}

EventFields TeleportEvent::Apply(const EventContext& c) const {
  // A robot teleported is a robot kidnapped (kidnap_event.h).
  if (c.robot_index->contains(target_)) return KidnapEvent(target_, pose_, {}).Apply(c);
  const int index = c.body_index->at(target_);
  c.world->Teleport(index, pose_);
  c.snapshot->bodies[index] = c.world->body_state(index);
  return EventFields{{"body", target_}, {"pose", {pose_.x_m, pose_.y_m, pose_.theta_rad}}};
}

EventFields DoorEvent::Apply(const EventContext& c) const {
  c.world->SetDoorOpen(door_, open_);
  return EventFields{{"door", door_}, {"state", open_ ? "open" : "closed"}};
}

void RegisterScriptedEvents(EventRegistry* registry) {
  RegisterKidnapEvent(registry);
  registry->Register("push", [](MapReader& r, const EventTargets& targets) {
    const std::string body = ReadTarget(r, "body", targets.bodies);
    Eigen::Vector2d impulse(0, 0);
    if (auto v = r.Numbers("impulse", 2, true)) impulse = {(*v)[0], (*v)[1]};
    return std::shared_ptr<const ScenarioEvent>(std::make_shared<const PushEvent>(body, impulse));
  });
  registry->Register("teleport", [](MapReader& r, const EventTargets& targets) {
    const std::string body = ReadTarget(r, "body", targets.bodies);
    // For robots, an alias of `kidnap` to a pose (its record is a kidnap).
    if (targets.robots.contains(body)) {
      return ReadKidnapTo(r, targets, body, "pose", true, KidnapOptions{});
    }
    core::Pose2 pose;
    if (auto p = r.Numbers("pose", 3, true)) pose = {(*p)[0], (*p)[1], (*p)[2]};
    return std::shared_ptr<const ScenarioEvent>(std::make_shared<const TeleportEvent>(body, pose));
  });
  registry->Register("door", [](MapReader& r, const EventTargets& targets) {
    const std::string door = ReadTarget(r, "door", targets.doors);
    const bool open = r.Choice("state", {"open", "closed"}, "closed", true) == "open";
    return std::shared_ptr<const ScenarioEvent>(std::make_shared<const DoorEvent>(door, open));
  });
}

}  // namespace pavilion::scenarios
