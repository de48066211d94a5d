#include "scenarios/events/crowd_events.h"

#include <memory>
#include <string>

#include "scenarios/events/kidnap_event.h"
#include "sim/crowd/crowd.h"
#include "sim/world/world.h"

namespace pavilion::scenarios {
namespace {

// The spot must hold a standing person: a disc of this radius (m), from the
// floor to head height (m), clear of the static geometry.
constexpr double kPersonRadiusM = 0.25;
constexpr double kPersonHeightM = 1.7;

// Where a place stands: its pose, or its area's vertex mean.
std::optional<Eigen::Vector2d> PlaceSpot(const sim::Place& place) {
  if (place.pose) return place.pose->translation();
  if (place.area && !place.area->empty()) {
    Eigen::Vector2d sum(0, 0);
    for (const Eigen::Vector2d& v : *place.area) sum += v;
    return Eigen::Vector2d(sum / static_cast<double>(place.area->size()));
  }
  return std::nullopt;
}

}  // namespace

EventFields SpawnGroupEvent::Apply(const EventContext& c) const {
  sim::crowd::Crowd* crowd = c.world->mutable_crowd();
  const int spawned = crowd ? crowd->SpawnGroup(at_m_, count_) : 0;
  return EventFields{{"count", count_}, {"spawned", spawned}, {"at", {at_m_.x(), at_m_.y()}}};
}

void RegisterCrowdEvents(EventRegistry* registry) {
  registry->Register(
      "spawn_group",
      [](MapReader& r, const EventTargets& targets) -> std::shared_ptr<const ScenarioEvent> {
        const int count = static_cast<int>(r.Integer("count", 1, 1, 10000));
        if (targets.crowd_pool > 0 && count > targets.crowd_pool) {
          r.doc()->Error(
              r.Child("count"), r.PathOf("count"),
              "more visitors than the crowd's pool (" + std::to_string(targets.crowd_pool) + ")");
        }
        std::optional<Eigen::Vector2d> at;
        std::string key = "at";
        if (r.Has("place")) {
          key = "place";
          const std::string name = r.RequiredString("place").value_or("");
          const auto it = targets.world ? targets.world->places.find(name)
                                        : std::map<std::string, sim::Place>::const_iterator{};
          if (!targets.world || it == targets.world->places.end()) {
            r.doc()->Error(r.Child("place"), r.PathOf("place"), "no place '" + name + "'");
          } else {
            at = PlaceSpot(it->second);
          }
        } else if (auto v = r.Numbers("at", 2, true)) {
          at = Eigen::Vector2d((*v)[0], (*v)[1]);
        }
        if (targets.crowd_pool <= 0) {
          r.doc()->Error(r.Child("type"), r.PathOf("type"),
                         "spawn_group needs a crowd (the scenario has no crowd: block)");
          return nullptr;
        }
        if (!at) return nullptr;
        if (targets.world) {
          const std::string what =
              StaticObstacleAt(*targets.world, RobotFootprint{kPersonRadiusM, 0.0, kPersonHeightM},
                               core::Pose2{at->x(), at->y(), 0.0});
          if (!what.empty()) {
            r.doc()->Error(r.Child(key), r.PathOf(key),
                           "the spot is not free for a person: it meets " + what);
          }
        }
        return std::make_shared<const SpawnGroupEvent>(*at, count);
      });
}

}  // namespace pavilion::scenarios
