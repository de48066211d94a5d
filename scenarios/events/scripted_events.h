#pragma once

// The built-in scripted events: push (an impulse on a body or robot),
// teleport (a body or robot moved by hand: the kidnapped robot) and door
// (a hinged door opened or closed).

#include <Eigen/Core>
#include <string>

#include "core/types/pose2.h"
#include "scenarios/events/event_registry.h"

namespace pavilion::scenarios {

// A push: an impulse at once, or a force held for a while (a pull). On a
// robot, optionally with its motors disengaged from the push until the force
// ends (or 2 s after an impulse): its wheels then roll freely and its
// encoders see the rolling (staff at Expo.02 pushed robots switched off, §6.5).
// A robot's force may be turned, when the push begins, towards the more open
// floor ahead of or behind it (`toward: open_floor`): staff move a robot out
// of the way along its wheels, they do not shove it into a showcase.
class PushEvent : public ScenarioEvent {
 public:
  struct Options {
    Eigen::Vector2d impulse_ns{0, 0};  // N s, at once
    Eigen::Vector2d force_n{0, 0};     // N, for duration_s
    double duration_s = 0.0;           // > 0 with a force
    bool motors_disengaged = false;    // robots only
    // Robots with a force only: the force acts along the robot's heading,
    // forwards or backwards, whichever way its footprint circle travels
    // further clear of every element (up to kOpenFloorReachM; ties: the way
    // nearer the given force's), its magnitude scaled by that travel over
    // kOpenFloorReachM (a gentler push where the floor is open less far).
    // Other robots count where they stand and where their velocity takes
    // them within kOtherRobotLookaheadS: staff do not push a robot into the
    // path of one driving by. Staff first hold the robot still
    // (sim::World::HaltRobot): pushed while turning, it curved off the line.
    bool toward_open_floor = false;
  };
  PushEvent(std::string target, const Eigen::Vector2d& impulse_ns)
      : target_(std::move(target)), options_{impulse_ns, {0, 0}, 0.0, false} {}
  PushEvent(std::string target, const Options& options)
      : target_(std::move(target)), options_(options) {}
  std::string type() const override { return "push"; }
  EventFields Apply(const EventContext& context) const override;
  bool ongoing() const override { return options_.duration_s > 0.0 || options_.motors_disengaged; }
  EventFields Continue(const EventContext& context) const override;
  const std::string& target() const { return target_; }
  const Eigen::Vector2d& impulse_ns() const { return options_.impulse_ns; }

  // How long motors stay disengaged after an impulse, s.
  static constexpr double kDisengagedAfterImpulseS = 2.0;
  // `toward: open_floor`: how far along each way the footprint circle is
  // checked, and the step of the checks (m).
  static constexpr double kOpenFloorReachM = 3.0;
  static constexpr double kOpenFloorStepM = 0.1;
  // `toward: open_floor`: other robots are also kept out of the checked
  // travel where their present velocity carries them within this time, s
  // (chosen: the push's 1.5 s and the braking after it), sampled every
  // kOtherRobotSampleS.
  static constexpr double kOtherRobotLookaheadS = 3.0;
  static constexpr double kOtherRobotSampleS = 0.25;
  // ... and kept this much further from them than their footprint circles, m
  // (chosen: one standing may start off; expo_day seed 2, 1,819 s: pushed
  // 0.75 m past a standing robot that then set off, robox_03 ran into it).
  static constexpr double kOtherRobotMarginM = 0.5;

 private:
  void Impulse(const EventContext& c, const Eigen::Vector2d& impulse_ns) const;
  // The force turned towards the more open floor ahead of or behind robot `index`.
  Eigen::Vector2d TowardOpenFloor(const EventContext& c, int index) const;

  std::string target_;
  Options options_;
  // When the push's force (or disengagement) ends, s; -1 when none is running.
  mutable double until_s_ = -1.0;
  mutable Eigen::Vector2d force_n_{0, 0};  // of the running push (turned or as given)
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
