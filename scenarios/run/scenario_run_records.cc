#include <cmath>
#include <set>
#include <tuple>

#include "scenarios/output/png.h"
#include "scenarios/run/scenario_run.h"

// What a tick records (scenario_run.h): contact begins and their classes,
// localization cycles and what they change, the navigation's events,
// trajectory rows, and the metrics at the end.

namespace pavilion::scenarios::detail {

void ScenarioRun::EmitNavigationEvents(RobotRun& r) {
  nav::Controller* controller = r.navigator->mutable_controller();
  if (!controller) return;
  nav_events_.clear();
  controller->TakeEvents(&nav_events_);
  for (const nav::NavigationEvent& e : nav_events_) {
    EventFields fields{{"robot", r.entry->id}, {"mission", e.mission}, {"goal", e.goal}};
    if (e.type == nav::NavigationEvent::Type::kMissionAborted) {
      fields["reason"] = nav::ToString(e.reason);
    }
    if (e.type == nav::NavigationEvent::Type::kMissionCompleted ||
        e.type == nav::NavigationEvent::Type::kMissionAborted) {
      fields["duration_s"] = RoundForJson(e.duration_s, 3);
      fields["path_length_m"] = RoundForJson(e.path_length_m, 3);
    }
    if (e.type == nav::NavigationEvent::Type::kReplanned ||
        e.type == nav::NavigationEvent::Type::kUncertaintyHoldEnded) {
      fields["cause"] = e.cause;
    }
    if (e.rest) fields["rest"] = true;
    if (e.type == nav::NavigationEvent::Type::kDeadlockResolved ||
        e.type == nav::NavigationEvent::Type::kUncertaintyHoldEnded) {
      fields["duration_s"] = RoundForJson(e.duration_s, 3);
    }
    events_->Emit(e.at_s, nav::ToString(e.type), fields);
    if (e.type == nav::NavigationEvent::Type::kDeadlockDetected && !first_deadlock_) {
      PictureDeadlock(r, e.at_s);
    }
  }
}

void ScenarioRun::PictureDeadlock(const RobotRun& r, double t) {
  constexpr double kCropM = 5.0;  // the robot, its neighbours and what pins them
  constexpr int kSizePx = 360;
  const int index = static_cast<int>(&r - robots_.data());
  const Eigen::Vector2d at = world_->robot_state(index).pose.translation();
  const std::string people = scenario_.crowd ? scenario_.crowd->material : std::string();
  const core::RgbImage image =
      RenderCrop(*world_, at, kCropM, kSizePx, scenario_.outputs.section_height_m, people,
                 CrowdFrameCaption(t) + ", " + r.entry->id);
  first_deadlock_ = DeadlockFrame{
      r.entry->id, CrowdFrame{"snapshots/deadlock_first.png", t, kCropM, EncodePng(image)}};
}

void ScenarioRun::RecordContacts(double t_after) {
  const auto& elements = world_->elements();
  for (const sim::ContactChange& c : world_->TakeContactChanges()) {
    ClassifyContact(c, t_after);
    if (c.phase != sim::ContactPhase::kTouch) continue;
    for (int element : {c.a, c.b}) {
      if (body_of_element_[element] >= 0) ++body_tally_[body_of_element_[element]].collisions;
      if (robot_of_element_[element] >= 0) ++robots_[robot_of_element_[element]].tally.collisions;
    }
    EventFields fields{{"a", elements[c.a].id},
                       {"b", elements[c.b].id},
                       {"impulse_ns", RoundForJson(c.impulse_ns)},
                       {"distance_m", RoundForJson(c.distance_m, 5)},
                       {"point_m",
                        {RoundForJson(c.point_m.x(), 4), RoundForJson(c.point_m.y(), 4),
                         RoundForJson(c.point_m.z(), 4)}}};
    // A robot's collision: the robot (the first, for two) and what it touched.
    const int ra = robot_of_element_[c.a];
    const int rb = robot_of_element_[c.b];
    if ((ra >= 0 || rb >= 0) && ra != rb) {
      fields["robot"] = robots_[ra >= 0 ? ra : rb].entry->id;
      fields["with"] = ToString(collision_classes_->Classify(ra >= 0 ? c.b : c.a));
      if (snapshots_) {
        snapshots_->OnEvent(*world_, t_after, robots_[ra >= 0 ? ra : rb].entry->id, "collision");
      }
    }
    events_->Emit(t_after, kCollision, fields);
  }
}

void ScenarioRun::ClassifyContact(const sim::ContactChange& c, double t_after) {
  const int ra = robot_of_element_[c.a];
  const int rb = robot_of_element_[c.b];
  // Walkers within contact distance of a robot stand for the pause, from the
  // contact's start and again from its end.
  if (c.phase != sim::ContactPhase::kTouch) {
    for (auto [robot, other] : {std::pair{ra, c.b}, std::pair{rb, c.a}}) {
      const int body = body_of_element_[other];
      if (robot >= 0 && body >= 0 && visitor_body_[body]) {
        walker_paused_until_s_[body] = t_after + kWalkerContactPauseS;
      }
    }
  }
  if (c.phase == sim::ContactPhase::kBegin || (ra >= 0 && ra == rb)) return;
  if (c.phase == sim::ContactPhase::kEnd) {
    if (c.touched) return;  // counted at its touch
    for (auto [robot, other] : {std::pair{ra, c.b}, std::pair{rb, c.a}}) {
      if (robot < 0) continue;
      CollisionCounts& counts = robots_[robot].tally.collisions_by_class;
      ++counts.passes_by_class[static_cast<std::size_t>(collision_classes_->Classify(other))];
    }
    return;
  }
  // Who moved into whom: the larger speed towards the contact point.
  const Eigen::Vector2d at = c.point_m.head<2>();
  const auto approach = [&](int element) {
    Eigen::Vector2d position, velocity;
    if (robot_of_element_[element] >= 0) {
      const sim::RobotState& s = snapshot_.robots[robot_of_element_[element]];
      position = s.pose.translation();
      velocity = s.velocity_mps;
    } else if (body_of_element_[element] >= 0) {
      const sim::BodyState& s = snapshot_.bodies[body_of_element_[element]];
      position = s.pose.translation();
      velocity = s.velocity_mps;
    } else if (person_of_element_[element] >= 0) {
      const sim::crowd::PersonState& s = snapshot_.people[person_of_element_[element]];
      position = s.position_m;
      velocity = s.velocity_mps;
    } else {
      return 0.0;
    }
    const Eigen::Vector2d d = at - position;
    return d.norm() > 0.0 ? velocity.dot(d.normalized()) : 0.0;
  };
  for (auto [robot, self, other] : {std::tuple{ra, c.a, c.b}, std::tuple{rb, c.b, c.a}}) {
    if (robot < 0) continue;
    if (robots_[robot].day) robots_[robot].day->OnCollision(t_after);
    CollisionCounts& counts = robots_[robot].tally.collisions_by_class;
    const CollisionClass kind = collision_classes_->Classify(other);
    ++counts.by_class[static_cast<std::size_t>(kind)];
    // A tie (both at rest: a resting contact flickering) is not the robot's doing.
    const bool robot_moved = approach(self) > approach(other) + kApproachTieMps;
    if (kind == CollisionClass::kVisitor) {
      ++(robot_moved ? counts.robot_into_visitor : counts.visitor_into_robot);
    } else if (kind == CollisionClass::kRobot) {
      ++(robot_moved ? counts.robot_into_robot : counts.robot_hit_by_robot);
    }
  }
}

void ScenarioRun::RecordCycle(RobotRun& r, const nav::EstimatorCycle& cycle,
                              const core::Pose2& truth, double t_after) {
  const nav::PoseEstimator& estimator = *r.navigator->estimator();
  const LocalizationCycle& c = r.tracker->Record(cycle, estimator, truth, t_after);
  localization_log_->Add(r.entry->id, r.tracker->cycle_count() - 1, c);
  const RelocalizationChange change = r.relocalization->OnCycle(
      t_after, c.mode, c.hypotheses, c.position_error_m, c.heading_error_rad);
  const nav::NavigationFigures* navigation =
      r.navigator->controller() ? r.navigator->controller()->navigation() : nullptr;
  r.day->OnCycle(t_after, c, r.tracker->in_lost_situation(),
                 navigation ? navigation->missions_started : 0);
  const auto error_fields = [&](EventFields fields) {
    fields["position_error_m"] = RoundForJson(c.position_error_m, 4);
    fields["heading_error_deg"] = RoundForJson(c.heading_error_rad * kDegPerRad, 3);
    return fields;
  };
  // The largest hypothesis set after a kidnap, for the report's picture.
  const std::size_t pictured = r.tracks.hypotheses ? r.tracks.hypotheses->hypotheses.size() : 0;
  if (r.kidnapped && c.mode == nav::LocalizationMode::kNotLocalized &&
      static_cast<std::size_t>(c.hypotheses) > pictured) {
    r.tracks.hypotheses = HypothesisSnapshot{t_after, truth, estimator.hypotheses()};
  }
  if (change.hypotheses_changed) {
    events_->Emit(t_after, kHypotheses,
                  EventFields{{"robot", r.entry->id},
                              {"n", c.hypotheses},
                              {"mode", nav::LocalizationModeName(c.mode)}});
  }
  // A lost situation (metrics.md: the truth's or the estimator's) begins, or
  // the estimator declares itself lost during one.
  if (r.tracker->lost_started() || change.lost) {
    const bool declared = c.mode == nav::LocalizationMode::kLost;
    events_->Emit(
        t_after, kLost,
        error_fields({{"robot", r.entry->id},
                      {"reason", declared ? estimator.lost_reason() : r.tracker->lost_reason()},
                      {"declared", declared}}));
  }
  if (change.localized) {
    events_->Emit(t_after, kLocalized,
                  EventFields{{"robot", r.entry->id}, {"hypotheses", c.hypotheses}});
  }
  if (change.relocalized) {
    events_->Emit(t_after, kRelocalized,
                  error_fields({{"robot", r.entry->id}, {"correct", change.correct}}));
  }
}

void ScenarioRun::RecordTrajectories(double t, bool bodies, bool robots) {
  for (int b = 0; bodies && b < world_->body_count(); ++b) {
    const core::Pose2& p = snapshot_.bodies[b].pose;
    trajectories_->AddBody(t, world_->body_spec(b).id, p);
    body_tracks_[b].Add(p.translation());
  }
  for (std::size_t k = 0; robots && k < robots_.size(); ++k) {
    RobotRun& r = robots_[k];
    const core::Pose2& p = snapshot_.robots[k].pose;
    const core::Pose2& o = r.navigator->odometry_pose();
    const nav::PoseEstimator* estimator = r.navigator->estimator();
    trajectories_->AddRobot(t, r.entry->id, p, o, estimator ? &estimator->estimate() : nullptr);
    if (estimator) r.estimate_path.Add(estimator->estimate().pose.translation());
    r.truth_path.Add(p.translation());
    r.odometry_path.Add(o.translation());
  }
}

RunMetrics ScenarioRun::CollectMetrics(double sim_s) const {
  RunMetrics m;
  m.scenario = scenario_.name;
  m.seed = scenario_.seed;
  m.pavilion_version = kVersion;
  m.world = scenario_.world.name;
  m.sim_duration_s = sim_s;
  m.physics_rate_hz = scenario_.physics.physics_rate_hz;
  m.ticks = ticks_run_;
  m.bodies = body_tally_;
  m.laser_backend = ToString(scenario_.laser_backend);
  if (scenario_.realism.realistic) {
    m.realism = RunMetrics::RealismFigures{
        static_cast<int>(real_world_.boxes.size() + real_world_.cylinders.size()),
        real_world_.opened_doors, static_cast<int>(real_world_.carpets.size())};
  }
  m.event_counts = events_->counts();
  for (std::size_t k = 0; k < robots_.size(); ++k) {
    const RobotRun& r = robots_[k];
    RobotMetrics robot = r.tally;
    robot.id = r.entry->id;
    robot.model = r.entry->config.description.model;
    const core::Pose2& truth = snapshot_.robots[k].pose;
    const core::Pose2& odo = r.navigator->odometry_pose();
    robot.odometry_final_position_error_m = (odo.translation() - truth.translation()).norm();
    robot.odometry_final_heading_error_rad =
        std::abs(core::NormalizeAngle(odo.theta_rad - truth.theta_rad));
    if (r.tracker) robot.localization = r.tracker->Figures();
    if (const nav::PoseEstimator* estimator = r.navigator->estimator()) {
      robot.estimator_counters = estimator->counters();
    }
    if (r.relocalization && r.relocalization->active()) {
      robot.relocalization = r.relocalization->Figures();
    }
    if (r.social && r.social->active()) robot.social = r.social->Figures();
    if (r.day) robot.day = r.day->Figures(sim_s);
    if (r.shadow_tracker) {
      robot.shadow = RobotMetrics::Shadow{"mcl", r.shadow_tracker->Figures(), std::nullopt};
      if (r.shadow_relocalization->active()) {
        robot.shadow->relocalization = r.shadow_relocalization->Figures();
      }
    }
    const nav::Controller* controller = r.navigator->controller();
    if (controller && controller->navigation()) robot.navigation = *controller->navigation();
    if (proximity_) {
      RobotFleetFigures fleet;
      fleet.proximity = proximity_->robot(static_cast<int>(k));
      if (fleet_) {
        fleet.bytes_up = fleet_->bytes_up(static_cast<int>(k));
        fleet.bytes_down = fleet_->bytes_down(static_cast<int>(k));
        fleet.messages = fleet_->messages(static_cast<int>(k));
      }
      robot.fleet = fleet;
    }
    if (r.entry->route) {
      const nav::MissionStatus mission = *r.navigator->controller()->mission();
      robot.route = RouteMetrics{r.entry->route->stops, mission.path_length_m, mission.done,
                                 mission.done ? mission.done_at_s : sim_s};
    }
    m.robots.push_back(std::move(robot));
  }
  if (crowd_tracker_) m.crowd = crowd_tracker_->Figures();
  if (proximity_) m.fleet = FleetRunFigures{fleet_ != nullptr, proximity_->fleet(), ticks_run_};
  return m;
}

}  // namespace pavilion::scenarios::detail
