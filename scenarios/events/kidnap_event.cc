#include "scenarios/events/kidnap_event.h"

#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "nav/reactive/swept_polygon.h"
#include "scenarios/config/options_reader.h"
#include "scenarios/events/free_space.h"
#include "scenarios/metrics/run_metrics.h"
#include "sim/world/static_section.h"

namespace pavilion::scenarios {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
constexpr double kRadPerDeg = std::numbers::pi / 180.0;
constexpr double kMaxMinDistanceM = 1e3;
constexpr double kMaxMarginM = 10.0;
constexpr double kMaxPerM = 100.0;
constexpr int kMaxDraws = 1000000;
// Cell size of the reachable free space a random pose is drawn in, m (chosen:
// finer than the robots' footprints, coarse enough to grid a hall quickly).
constexpr double kReachCellM = 0.2;
// Decimals of poses in records (m, rad): as trajectories.csv.
constexpr int kPoseDecimals = 6;

nlohmann::ordered_json PoseJson(const core::Pose2& p) {
  return {RoundForJson(p.x_m, kPoseDecimals), RoundForJson(p.y_m, kPoseDecimals),
          RoundForJson(p.theta_rad, kPoseDecimals)};
}

std::string StreamName(const std::string& robot) { return robot + "/kidnap"; }

}  // namespace

void KidnapOptions::Validate() const {
  if (!(min_distance_m >= 0.0 && min_distance_m <= kMaxMinDistanceM)) {
    throw std::invalid_argument("min_distance_m must be in [0, 1000] m");
  }
  if (!(min_turn_rad >= 0.0 && min_turn_rad <= std::numbers::pi)) {
    throw std::invalid_argument("min_turn_rad must be in [0, 180] deg");
  }
  if (!(margin_m >= 0.0 && margin_m <= kMaxMarginM)) {
    throw std::invalid_argument("margin_m must be in [0, 10] m");
  }
  if (!(per_m >= 0.0 && per_m <= kMaxPerM)) {
    throw std::invalid_argument("per_m must be in [0, 100] per m");
  }
  if (!(std::abs(turn_rad) <= 2.0 * std::numbers::pi)) {
    throw std::invalid_argument("turn_rad must be in [-360, 360] deg");
  }
  if (max_draws < 1 || max_draws > kMaxDraws) {
    throw std::invalid_argument("max_draws must be in [1, 1000000]");
  }
}

KidnapEvent::KidnapEvent(std::string robot, std::optional<core::Pose2> pose, KidnapOptions options)
    : robot_(std::move(robot)), pose_(pose), options_(options) {
  options_.Validate();
}

EventFields KidnapEvent::Apply(const EventContext& c) const {
  const int index = c.robot_index->at(robot_);
  if (pose_) return MoveTo(c, index, *pose_, "pose");
  if (options_.per_m > 0.0) return nullptr;  // the turns come with Continue
  if (const std::optional<core::Pose2> to = DrawFreePose(c, index)) {
    return MoveTo(c, index, *to, "random");
  }
  return EventFields{
      {"robot", robot_},
      {"mode", "random"},
      {"error", "no free pose at least " + std::to_string(options_.min_distance_m) + " m and " +
                    std::to_string(options_.min_turn_rad * kDegPerRad) + " deg away in " +
                    std::to_string(options_.max_draws) + " draws: the robot stays"}};
}

EventFields KidnapEvent::Continue(const EventContext& c) const {
  const int index = c.robot_index->at(robot_);
  const double step_m = (*c.robot_step_m)[index];
  if (step_m <= 0.0) return nullptr;
  const double u = c.streams->Get(StreamName(robot_)).Uniform();
  if (u >= options_.per_m * step_m) return nullptr;
  core::Pose2 to = c.snapshot->robots[index].pose;
  to.theta_rad = core::NormalizeAngle(to.theta_rad + options_.turn_rad);
  return MoveTo(c, index, to, "per_m");
}

EventFields KidnapEvent::MoveTo(const EventContext& c, int index, const core::Pose2& to,
                                const char* mode) const {
  const core::Pose2 before = c.snapshot->robots[index].pose;
  c.world->TeleportRobot(index, to);
  c.snapshot->robots[index] = c.world->robot_state(index);
  const core::Pose2 after = c.snapshot->robots[index].pose;
  if (c.kidnaps) c.kidnaps->push_back(KidnapNote{index, before, after});
  const double turn_rad = core::NormalizeAngle(after.theta_rad - before.theta_rad);
  return EventFields{
      {"robot", robot_},
      {"mode", mode},
      {"before", PoseJson(before)},
      {"after", PoseJson(after)},
      {"distance_m",
       RoundForJson((after.translation() - before.translation()).norm(), kPoseDecimals)},
      {"turn_deg", RoundForJson(turn_rad * kDegPerRad, 3)}};
}

std::optional<core::Pose2> KidnapEvent::DrawFreePose(const EventContext& c, int index) const {
  const sim::RobotDescription& model = c.world->robot_model(index);
  const double radius_m = nav::Circumradius(model.footprint_m) + options_.margin_m;
  std::vector<core::PlanarSection> sections, static_sections;
  for (double h : ChassisCheckHeights(model.chassis_base_z_m,
                                      model.chassis_base_z_m + model.chassis_height_m)) {
    sections.push_back(c.world->SectionAt(h));
    static_sections.push_back(c.world->StaticSectionAt(h));
  }
  const sim::Floor& floor = c.world->description().floor;
  const core::Pose2 from = c.snapshot->robots[index].pose;
  const int group = c.world->robot_group(index);
  // Into the building the robot is in: free space it could drive to.
  const ReachableCells reachable(static_sections, floor, nav::Circumradius(model.footprint_m),
                                 kReachCellM, from.translation(), group);
  core::RandomStream& stream = c.streams->Get(StreamName(robot_));
  for (int draw = 0; draw < options_.max_draws; ++draw) {
    const core::Pose2 to{stream.Uniform(floor.min_m.x(), floor.max_m.x()),
                         stream.Uniform(floor.min_m.y(), floor.max_m.y()),
                         stream.Uniform(-std::numbers::pi, std::numbers::pi)};
    if ((to.translation() - from.translation()).norm() < options_.min_distance_m) continue;
    if (std::abs(core::NormalizeAngle(to.theta_rad - from.theta_rad)) < options_.min_turn_rad) {
      continue;
    }
    if (!reachable.Contains(to.translation())) continue;
    const core::PlanarSection& middle = static_sections[static_sections.size() / 2];
    if (!Enclosed(middle, floor, to.translation()) || !WheelsRunInside(middle, floor, to)) continue;
    if (CheckDisc(sections, floor, to.translation(), radius_m, group).free) return to;
  }
  return std::nullopt;
}

std::string StaticObstacleAt(const sim::WorldDescription& world, const RobotFootprint& footprint,
                             const core::Pose2& pose) {
  // The element order of sim::World (and sim::AppendStaticSection): the floor,
  // walls, boxes, cylinders, meshes, doors.
  std::vector<core::SectionElement> elements{{.id = "floor"}};
  for (const auto& w : world.walls) elements.push_back({.id = w.id});
  for (const auto& b : world.boxes) elements.push_back({.id = b.id});
  for (const auto& c : world.cylinders) elements.push_back({.id = c.id});
  for (const auto& m : world.meshes) elements.push_back({.id = m.id});
  for (const auto& d : world.doors) elements.push_back({.id = d.id});
  std::vector<core::PlanarSection> sections;
  for (double h : ChassisCheckHeights(footprint.bottom_m, footprint.top_m)) {
    core::PlanarSection s;
    s.height_m = h;
    s.elements = elements;
    sim::AppendStaticSection(world, h, &s);
    sections.push_back(std::move(s));
  }
  const DiscObstacle hit = CheckDisc(sections, world.floor, pose.translation(), footprint.radius_m);
  return hit.free ? std::string() : hit.what;
}

std::shared_ptr<const ScenarioEvent> ReadKidnapTo(MapReader& r, const EventTargets& targets,
                                                  const std::string& robot,
                                                  const std::string& pose_key, bool pose_required,
                                                  const KidnapOptions& options) {
  std::optional<core::Pose2> pose;
  if (r.Has(pose_key) || pose_required) {
    if (auto p = r.Numbers(pose_key, 3, true)) pose = core::Pose2{(*p)[0], (*p)[1], (*p)[2]};
  }
  if (pose && targets.world && targets.footprints.contains(robot)) {
    const std::string what = StaticObstacleAt(*targets.world, targets.footprints.at(robot), *pose);
    if (!what.empty()) {
      char radius[32];
      std::snprintf(radius, sizeof radius, "%.3g", targets.footprints.at(robot).radius_m);
      const std::string where = what == kFloorEdge ? "would stand outside the world's floor"
                                                   : "would overlap '" + what + "'";
      r.doc()->Error(r.Child(pose_key), r.PathOf(pose_key),
                     "robot '" + robot + "' at this pose " + where +
                         " (its footprint's radius: " + radius + " m)");
    }
  }
  if (robot.empty() || !targets.robots.contains(robot)) return nullptr;
  try {
    return std::make_shared<const KidnapEvent>(robot, pose, options);
  } catch (const std::invalid_argument&) {
    return nullptr;  // reported by the options reader
  }
}

void RegisterKidnapEvent(EventRegistry* registry) {
  registry->Register("kidnap", [](MapReader& r, const EventTargets& targets) {
    std::string robot = r.RequiredString("robot").value_or("");
    if (!robot.empty() && !targets.robots.contains(robot)) {
      r.doc()->Error(r.Child("robot"), r.PathOf("robot"), "no robot '" + robot + "'");
    }
    KidnapOptions options;
    ReadOptions(r, &options,
                {{"min_distance_m", &KidnapOptions::min_distance_m},
                 {"min_turn_deg", "min_turn_rad", &KidnapOptions::min_turn_rad, kRadPerDeg},
                 {"margin_m", &KidnapOptions::margin_m},
                 {"per_m", &KidnapOptions::per_m},
                 {"turn_deg", "turn_rad", &KidnapOptions::turn_rad, kRadPerDeg},
                 {"max_draws", &KidnapOptions::max_draws}});
    if (r.Has("pose") && options.per_m > 0.0) {
      r.doc()->Error(r.Child("per_m"), r.PathOf("per_m"), "give either pose or per_m");
    }
    return ReadKidnapTo(r, targets, robot, "pose", false, options);
  });
}

}  // namespace pavilion::scenarios
