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

void PushEvent::Impulse(const EventContext& c, const Eigen::Vector2d& impulse_ns) const {
  if (c.robot_index->contains(target_)) {
    c.world->ApplyRobotImpulse(c.robot_index->at(target_), impulse_ns);
  } else {
    c.world->ApplyImpulse(c.body_index->at(target_), impulse_ns);
  }
}

EventFields PushEvent::Apply(const EventContext& c) const {
  const Options& o = options_;
  EventFields fields{{"body", target_}};
  if (o.duration_s > 0.0) {
    fields["force_n"] = {o.force_n.x(), o.force_n.y()};
    fields["duration_s"] = o.duration_s;
  } else {
    Impulse(c, o.impulse_ns);
    fields["impulse_ns"] = {o.impulse_ns.x(), o.impulse_ns.y()};
  }
  if (o.motors_disengaged) {
    c.world->SetMotorsEngaged(c.robot_index->at(target_), false);
    fields["motors"] = "disengaged";
  }
  if (ongoing()) {
    until_s_ = c.world->time_s() + (o.duration_s > 0.0 ? o.duration_s : kDisengagedAfterImpulseS);
  }
  return fields;
}

EventFields PushEvent::Continue(const EventContext& c) const {
  if (until_s_ < 0.0) return nullptr;
  const double now = c.world->time_s();
  if (now < until_s_ - 1e-9) {
    // The force over the coming step.
    if (options_.duration_s > 0.0) Impulse(c, options_.force_n * c.world->step_s());
    return nullptr;
  }
  until_s_ = -1.0;
  if (options_.motors_disengaged) {
    c.world->SetMotorsEngaged(c.robot_index->at(target_), true);
    return EventFields{{"body", target_}, {"motors", "engaged"}};
  }
  return nullptr;
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
    PushEvent::Options o;
    const bool pull = r.Has("force");
    if (pull) {
      if (auto v = r.Numbers("force", 2, true)) o.force_n = {(*v)[0], (*v)[1]};
      o.duration_s = r.Number("duration_s", 1.0, 1e-3, 3600.0);
      if (r.Has("impulse")) {
        r.doc()->Error(r.Child("impulse"), r.PathOf("impulse"), "give impulse or force, not both");
      }
    } else if (auto v = r.Numbers("impulse", 2, true)) {
      o.impulse_ns = {(*v)[0], (*v)[1]};
    }
    o.motors_disengaged = r.Choice("motors", {"engaged", "disengaged"}, "engaged") == "disengaged";
    if (o.motors_disengaged && !body.empty() && !targets.robots.contains(body)) {
      r.doc()->Error(r.Child("motors"), r.PathOf("motors"), "'" + body + "' is not a robot");
    }
    return std::shared_ptr<const ScenarioEvent>(std::make_shared<const PushEvent>(body, o));
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
