#include "scenarios/events/scripted_events.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <set>
#include <vector>

#include "nav/reactive/swept_polygon.h"
#include "scenarios/events/free_space.h"
#include "scenarios/events/kidnap_event.h"
#include "scenarios/metrics/run_metrics.h"

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

// Another robot's footprint circle, where it stands and where its present
// velocity carries it over the look-ahead.
struct MovingDisc {
  Eigen::Vector2d at_m;
  Eigen::Vector2d velocity_mps;
  double radius_m;
};

std::vector<MovingDisc> OtherRobots(const EventContext& c, int index) {
  std::vector<MovingDisc> others;
  for (int k = 0; k < c.world->robot_count(); ++k) {
    if (k == index) continue;
    const sim::RobotState& r = c.snapshot->robots[k];
    others.push_back({r.pose.translation(), r.velocity_mps,
                      nav::Circumradius(c.world->robot_model(k).footprint_m)});
  }
  return others;
}

// Whether a disc of `radius_m` at `p_m` keeps clear of every other robot's
// circle over the look-ahead.
bool ClearOfOtherRobots(const std::vector<MovingDisc>& others, const Eigen::Vector2d& p_m,
                        double radius_m) {
  for (const MovingDisc& o : others) {
    const double reach_m = radius_m + o.radius_m + PushEvent::kOtherRobotMarginM;
    for (double t = 0.0; t <= PushEvent::kOtherRobotLookaheadS + 1e-9;
         t += PushEvent::kOtherRobotSampleS) {
      if ((o.at_m + t * o.velocity_mps - p_m).squaredNorm() < reach_m * reach_m) return false;
    }
  }
  return true;
}

}  // namespace

void PushEvent::Impulse(const EventContext& c, const Eigen::Vector2d& impulse_ns) const {
  if (c.robot_index->contains(target_)) {
    c.world->ApplyRobotImpulse(c.robot_index->at(target_), impulse_ns);
  } else {
    c.world->ApplyImpulse(c.body_index->at(target_), impulse_ns);
  }
}

Eigen::Vector2d PushEvent::TowardOpenFloor(const EventContext& c, int index) const {
  const sim::RobotDescription& model = c.world->robot_model(index);
  const double radius_m = nav::Circumradius(model.footprint_m);
  std::vector<core::PlanarSection> sections;
  for (double h : ChassisCheckHeights(model.chassis_base_z_m,
                                      model.chassis_base_z_m + model.chassis_height_m)) {
    sections.push_back(c.world->SectionAt(h));
  }
  const sim::Floor& floor = c.world->description().floor;
  const core::Pose2& pose = c.snapshot->robots[index].pose;
  const Eigen::Vector2d from = pose.translation();
  const int group = c.world->robot_group(index);
  const double given_rad = std::atan2(options_.force_n.y(), options_.force_n.x());
  // A robot on free-rolling wheels moves along its heading whichever way it is
  // pushed (its wheels do not slide sideways): staff push it forwards or
  // backwards, whichever way the floor is open further.
  const std::vector<MovingDisc> others = OtherRobots(c, index);
  double best_travel = -1.0, best_turn = 0.0;
  Eigen::Vector2d best = options_.force_n.normalized();
  for (const double angle : {pose.theta_rad, pose.theta_rad + std::numbers::pi}) {
    const Eigen::Vector2d direction(std::cos(angle), std::sin(angle));
    const auto clear = [&](double travel_m) {
      const Eigen::Vector2d p = from + travel_m * direction;
      return CheckDisc(sections, floor, p, radius_m, group).free &&
             ClearOfOtherRobots(others, p, radius_m);
    };
    double travel = 0.0;
    while (travel + kOpenFloorStepM <= kOpenFloorReachM + 1e-9 && clear(travel + kOpenFloorStepM)) {
      travel += kOpenFloorStepM;
    }
    const double turn = std::abs(core::NormalizeAngle(angle - given_rad));
    if (travel > best_travel + 1e-9 ||
        (std::abs(travel - best_travel) <= 1e-9 && turn < best_turn)) {
      best_travel = travel;
      best_turn = turn;
      best = direction;
    }
  }
  // Where the floor is open for less than the reach, they push gently: the
  // force in proportion to the open floor (150 N for 1.5 s rolls a Robox
  // 2.2 m, its braking included: PushEventTest.TowardOpenFloorPushesAlongTheWheels).
  const double share = std::clamp(best_travel / kOpenFloorReachM, 0.0, 1.0);
  return share * options_.force_n.norm() * best;
}

EventFields PushEvent::Apply(const EventContext& c) const {
  const Options& o = options_;
  EventFields fields{{"body", target_}};
  force_n_ = o.force_n;
  if (o.toward_open_floor && c.robot_index->contains(target_)) {
    // Staff hold the robot still, then push it along its wheels: a robot
    // turning when pushed curved off the line checked (expo_day seed 2,
    // 2,264.6 s and 3,589.2 s, into a robot and a showcase).
    const int index = c.robot_index->at(target_);
    c.world->HaltRobot(index);
    c.snapshot->robots[index] = c.world->robot_state(index);
    force_n_ = TowardOpenFloor(c, index);
  }
  if (o.duration_s > 0.0) {
    fields["force_n"] = {RoundForJson(force_n_.x(), 3), RoundForJson(force_n_.y(), 3)};
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
    if (options_.duration_s > 0.0) Impulse(c, force_n_ * c.world->step_s());
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
    o.toward_open_floor = r.Choice("toward", {"given", "open_floor"}, "given") == "open_floor";
    if (o.toward_open_floor && (!pull || (!body.empty() && !targets.robots.contains(body)))) {
      r.doc()->Error(r.Child("toward"), r.PathOf("toward"),
                     "`toward: open_floor` turns a robot's `force`; '" + body +
                         "' needs to be a robot pushed with a force");
    }
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
