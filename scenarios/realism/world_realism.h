#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "core/map/robot_map.h"
#include "scenarios/config/realism.h"
#include "sim/sensors/robot_sensors.h"
#include "sim/world/world.h"
#include "sim/world/world_description.h"

namespace pavilion::scenarios {

// What a `realism: realistic` run changes in the world its map was surveyed
// from (issue 20): unmapped clutter against the walls, and doors that stand
// otherwise than the map says.
struct RealWorldChanges {
  std::vector<sim::Box> boxes;           // radiators, cabinets, framed posters, table tops
  std::vector<sim::Cylinder> cylinders;  // plants in pots, table legs
  std::vector<std::string> opened_doors;
  std::vector<sim::FloorPatch> carpets;  // for every robot's encoders
  sim::FloorRelief relief;               // slopes and bumps of the floor
};

// The name of the material clutter is made of (added to the description).
inline constexpr const char* kClutterMaterial = "realism_clutter";

// Where clutter must not stand: the robots' start positions and the roads of
// their maps (nodes and edges), kept `clearance_m` away from every object.
struct ClutterKeepOut {
  std::vector<Eigen::Vector2d> points_m;
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> roads_m;
  double clearance_m = 0.45;  // a robot's radius and a margin, m
};
// The keep-out of a map's roads and stations (its nodes and edges).
void AddRoads(const core::RobotMap& map, ClutterKeepOut* keep_out);

// Draws the changes from the scenario's seed (stream "realism/world"):
// - Clutter: along every wall face of `description` that faces the inside of
//   the building (a ray from it meets something within 30 m), objects stand
//   at exponentially distributed gaps of mean 1 / clutter_per_m: radiators
//   (10 cm deep), cabinets (35-50 cm), framed posters (1-3 cm, hanging down to
//   the scan plane), tables (60-80 cm deep: four 4 cm legs under a top above
//   the scan plane) and plants (round pots). An object is placed only where
//   the face runs on under all of it, the space in front stays free for a
//   metre beyond it (cast in `survey`, the world without clutter), it keeps
//   clear of doors, of the keep-out and of the clutter placed before it.
// - Doors: a door the description has closed stands open with probability
//   door_flip_probability. (Open doors stay open: closing one a route needs
//   is a scenario's `door` event, not a survey error.)
// - Carpet: the floor in 4 m squares, each carpeted with probability
//   carpet_fraction, its wheels turning farther per metre by a uniform draw
//   in [0.2, 1] x carpet_travel_error.
// - Relief: slopes and bumps of the floor no steeper than
//   floor_max_slope_rad (sim::DrawFloorRelief, stream "realism/floor"), for
//   the physics and both wheel models; the encoders and the map know nothing
//   of them.
// Nothing for an ideal profile. Deterministic for given inputs.
RealWorldChanges DrawRealWorld(const RealismProfile& profile, std::uint64_t seed,
                               const sim::World& survey, const sim::WorldDescription& description,
                               const ClutterKeepOut& keep_out);

// Adds the clutter (and its material) to `description` and opens its doors.
void ApplyRealWorld(const RealWorldChanges& changes, sim::WorldDescription* description);

}  // namespace pavilion::scenarios
