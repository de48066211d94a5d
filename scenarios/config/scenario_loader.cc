#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <map>
#include <numbers>
#include <set>

#include "nav/reactive/swept_polygon.h"
#include "scenarios/config/crowd_reader.h"
#include "scenarios/config/data_paths.h"
#include "scenarios/config/mission_reader.h"
#include "scenarios/config/options_reader.h"
#include "scenarios/config/realism_reader.h"
#include "scenarios/config/robot_loader.h"
#include "scenarios/config/scenario.h"
#include "scenarios/config/snapshot_options.h"
#include "scenarios/config/world_loader.h"
#include "scenarios/config/yaml_reader.h"
#include "scenarios/events/event_registry.h"
#include "scenarios/events/event_types.h"
#include "scenarios/events/random_events.h"
#include "scenarios/expect/expect_reader.h"
#include "scenarios/maps/map_derivation.h"
#include "scenarios/realism/robot_realism.h"

namespace pavilion::scenarios {
namespace {

constexpr double kMaxDurationS = 1e7;
// Repetitions of one `every_s` event in a run, at most (chosen: bounds the timeline's memory).
constexpr int kMaxEventRepeats = 1000000;
constexpr double kMaxMassKg = 1e5;
// A walker's relaxation time tau, s: Helbing & Molnar (1995) take 0.5 s.
constexpr double kWalkerRelaxationS = 0.5;
constexpr double kMaxRelaxationS = 100.0;
constexpr double kMaxBodySizeM = 100.0;
constexpr std::int64_t kMaxGroupCount = 100000;
constexpr double kMaxPeopleRateHz = 1e4;                 // OutputOptions::people_rate_hz's range
constexpr double kRadPerDeg = std::numbers::pi / 180.0;  // laser_max_tilt_deg is in degrees

// Reads a `wheel_model` key: one of the sim::WheelModel names.
sim::WheelModel ReadWheelModel(MapReader& r, sim::WheelModel default_model) {
  const std::vector<std::string> names = {sim::WheelModelName(sim::WheelModel::kArticulated),
                                          sim::WheelModelName(sim::WheelModel::kRaycast)};
  const std::string name = r.Choice("wheel_model", names, sim::WheelModelName(default_model));
  return name == names[1] ? sim::WheelModel::kRaycast : sim::WheelModel::kArticulated;
}

std::optional<sim::BodyShape> ReadShape(YamlDocument* doc, MapReader& parent) {
  MapReader r(doc, parent.Child("shape", true), parent.PathOf("shape"));
  if (!r.valid()) return std::nullopt;
  sim::BodyShape shape;
  const std::string type = r.Choice("type", {"box", "cylinder", "sphere"}, "cylinder", true);
  bool ok = true;
  if (type == "box") {
    shape.type = sim::BodyShapeType::kBox;
    auto size = r.Numbers("size", 3, true);
    if (size && size->at(0) > 0 && size->at(1) > 0 && size->at(2) > 0 &&
        std::max({size->at(0), size->at(1), size->at(2)}) <= kMaxBodySizeM) {
      shape.box_size_m = {(*size)[0], (*size)[1], (*size)[2]};
    } else if (size) {
      doc->Error(r.Child("size"), r.PathOf("size"), "every size must be in (0, 100] m");
      ok = false;
    } else {
      ok = false;
    }
  } else if (type == "cylinder") {
    shape.type = sim::BodyShapeType::kCylinder;
    auto radius = r.RequiredNumber("radius", 1e-3, kMaxBodySizeM);
    auto height = r.RequiredNumber("height", 1e-3, kMaxBodySizeM);
    ok = radius && height;
    if (ok) {
      shape.radius_m = *radius;
      shape.height_m = *height;
    }
  } else {
    shape.type = sim::BodyShapeType::kSphere;
    auto radius = r.RequiredNumber("radius", 1e-3, kMaxBodySizeM);
    ok = radius.has_value();
    if (ok) shape.radius_m = *radius;
  }
  r.Finish();
  if (!ok) return std::nullopt;
  return shape;
}

MotionSpec ReadMotion(YamlDocument* doc, MapReader& parent) {
  MotionSpec motion;
  YAML::Node node = parent.Child("motion");
  if (!node.IsDefined()) return motion;
  MapReader r(doc, node, parent.PathOf("motion"));
  const std::string type = r.Choice("type", {"none", "scripted", "random_walk"}, "none", true);
  if (type == "scripted") {
    motion.type = MotionSpec::Type::kScripted;
    motion.scripted.body_frame = r.Bool("body_frame", true);
    motion.scripted.loop = r.Bool("loop", false);
    YAML::Node segs = r.Child("segments", true);
    if (segs.IsDefined() && (!segs.IsSequence() || segs.size() == 0)) {
      doc->Error(segs, r.PathOf("segments"), "expected a non-empty list of segments");
    } else if (segs.IsDefined()) {
      for (std::size_t i = 0; i < segs.size(); ++i) {
        MapReader s(doc, segs[i], IndexPath(r.PathOf("segments"), i));
        sim::VelocitySegment seg;
        RequireKeys(s, {"duration_s"});
        using Segment = sim::VelocitySegment;
        ReadOptions(s, &seg,
                    {{"duration_s", &Segment::duration_s},
                     {"velocity", "velocity_mps", &Segment::velocity_mps},
                     {"yaw_rate", "yaw_rate_radps", &Segment::yaw_rate_radps}});
        s.Finish();
        motion.scripted.segments.push_back(seg);
      }
    }
  } else if (type == "random_walk") {
    motion.type = MotionSpec::Type::kRandomWalk;
    using Walk = sim::RandomWalkOptions;
    ReadOptions(r, &motion.random_walk,
                {{"speed_mps", &Walk::speed_mps}, {"mean_leg_s", &Walk::mean_leg_s}});
  }
  r.Finish();
  return motion;
}

// Fields shared by single bodies and groups.
void ReadBodyCommon(YamlDocument* doc, MapReader& r, const sim::WorldDescription& world,
                    BodyEntry* entry) {
  if (auto shape = ReadShape(doc, r)) entry->spec.shape = *shape;
  entry->spec.mass_kg = r.RequiredNumber("mass_kg", 1e-3, kMaxMassKg).value_or(1.0);
  if (auto m = r.RequiredString("material")) {
    if (!world.materials.contains(*m)) {
      doc->Error(r.Child("material"), r.PathOf("material"),
                 "unknown material '" + *m + "' (not in the world or the scenario's materials)");
    }
    entry->spec.material = *m;
  }
  entry->spec.upright = r.Bool("upright", true);
  entry->motion = ReadMotion(doc, r);
  entry->spec.driven = entry->motion.type != MotionSpec::Type::kNone;
  // A walker pushes with a person's finite force (sim::BodySpec); a scripted
  // body (a cart) holds its profile against anything.
  entry->spec.drive_relaxation_s =
      r.Number("drive_relaxation_s",
               entry->motion.type == MotionSpec::Type::kRandomWalk ? kWalkerRelaxationS : 0.0, 0.0,
               kMaxRelaxationS);
  if (r.Has("area")) {
    YAML::Node area = r.Child("area");
    if (area.IsSequence()) {  // an inline polygon
      core::Polygon2 polygon;
      for (std::size_t i = 0; i < area.size(); ++i) {
        if (auto p = ReadNumbers(doc, area[i], IndexPath(r.PathOf("area"), i), 2)) {
          polygon.emplace_back((*p)[0], (*p)[1]);
        }
      }
      if (polygon.size() != area.size()) return;
      if (polygon.size() < 3 || !core::IsSimple(polygon)) {
        doc->Error(area, r.PathOf("area"), "expected a simple polygon of at least 3 [x, y] points");
        return;
      }
      entry->spawn_area = r.PathOf("area");
      entry->spawn_polygon = polygon;
    } else if (auto name = r.RequiredString("area")) {
      auto it = world.places.find(*name);
      if (it == world.places.end() || !it->second.area) {
        doc->Error(area, r.PathOf("area"), "no area place '" + *name + "' in the world");
      } else {
        entry->spawn_area = *name;
        entry->spawn_polygon = it->second.area;
      }
    }
  }
}

// The ids of the world's elements ("floor", walls, boxes, cylinders, meshes, doors).
std::set<std::string> WorldElementIds(const sim::WorldDescription& world) {
  std::set<std::string> ids = {"floor"};
  for (const auto& wall : world.walls) ids.insert(wall.id);
  for (const auto& b : world.boxes) ids.insert(b.id);
  for (const auto& c : world.cylinders) ids.insert(c.id);
  for (const auto& m : world.meshes) ids.insert(m.id);
  for (const auto& d : world.doors) ids.insert(d.id);
  return ids;
}

void ReadBodies(YamlDocument* doc, MapReader& top, const sim::WorldDescription& world,
                Scenario* s) {
  YAML::Node list = top.Child("bodies");
  if (list.IsDefined() && !list.IsNull()) {
    if (!list.IsSequence()) doc->Error(list, "bodies", "expected a list");
    for (std::size_t i = 0; list.IsSequence() && i < list.size(); ++i) {
      MapReader r(doc, list[i], IndexPath("bodies", i));
      if (!r.valid()) continue;
      BodyEntry entry;
      entry.spec.id = r.RequiredString("id").value_or("");
      ReadBodyCommon(doc, r, world, &entry);
      if (r.Has("pose") == r.Has("area")) {
        doc->Error(list[i], IndexPath("bodies", i), "give exactly one of pose or area");
      } else if (r.Has("pose")) {
        if (auto p = r.Numbers("pose", 3, true)) entry.spec.pose = {(*p)[0], (*p)[1], (*p)[2]};
      }
      r.Finish();
      s->bodies.push_back(entry);
    }
  }
  // reset(), not operator=, which would write the groups into the bodies' node.
  list.reset(top.Child("groups"));
  if (list.IsDefined() && !list.IsNull()) {
    if (!list.IsSequence()) doc->Error(list, "groups", "expected a list");
    for (std::size_t i = 0; list.IsSequence() && i < list.size(); ++i) {
      MapReader r(doc, list[i], IndexPath("groups", i));
      if (!r.valid()) continue;
      BodyEntry entry;
      const std::string prefix = r.RequiredString("id").value_or("group");
      const std::int64_t count = r.Integer("count", 1, 0, kMaxGroupCount);
      ReadBodyCommon(doc, r, world, &entry);
      if (!r.Has("area"))
        doc->Error(list[i], IndexPath("groups", i) + ".area", "required key is missing");
      r.Finish();
      for (std::int64_t k = 0; k < count; ++k) {
        char suffix[32];
        std::snprintf(suffix, sizeof suffix, "_%03lld", static_cast<long long>(k));
        BodyEntry body = entry;
        body.spec.id = prefix + suffix;
        s->bodies.push_back(body);
      }
    }
  }
  std::set<std::string> ids = WorldElementIds(world);
  for (const auto& b : s->bodies) {
    if (!ids.insert(b.spec.id).second) {
      doc->Error(top.Child("bodies"), "bodies",
                 "body id '" + b.spec.id + "' is used twice or by a world element");
    }
  }
}

// localization: {map, rate_hz, method: ekf|global, initial: known|unknown,
// A list of the robot model's sensor ids under `key` (e.g. lasers: [front]).
void ReadSensorIds(YamlDocument* doc, MapReader& m, const char* key, const char* what,
                   const std::vector<std::string>& known, const std::string& model,
                   std::vector<std::string>* out) {
  YAML::Node list = m.Child(key);
  if (!list.IsDefined()) return;
  if (!list.IsSequence()) {
    doc->Error(list, m.PathOf(key), std::string("expected a list of ") + what + " ids");
    return;
  }
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string id = list[k].as<std::string>("");
    if (std::find(known.begin(), known.end(), id) == known.end()) {
      doc->Error(list[k], IndexPath(m.PathOf(key), k),
                 "robot model '" + model + "' has no " + what + " '" + id + "'");
    }
    out->push_back(id);
  }
}

// initial_offset: [x, y, theta], initial_sigma: [x, y, theta], significance,
// lasers: [ids], cameras: [ids]} (thesis §4.4, chapter 5).
void ReadLocalization(YamlDocument* doc, MapReader& r, const std::string& base,
                      const Scenario& scenario, RobotEntry* robot) {
  YAML::Node node = r.Child("localization");
  if (!node.IsDefined()) return;
  MapReader m(doc, node, r.PathOf("localization"));
  if (!m.valid()) return;
  LocalizationEntry& l = robot->localization;
  l.enabled = m.Bool("enabled", true);
  const std::string map = m.String("map", "");
  if (map == "derive") {
    l.derive_map_noise_m = MapDerivationOptions{}.noise_sigma_m;  // unless map_noise_m, below
  } else if (m.Has("map_noise_m")) {
    doc->Error(m.Child("map_noise_m"), m.PathOf("map_noise_m"),
               "map_noise_m applies only with 'map: derive'");
  }
  if (map.empty()) {
    l.map_file = (std::filesystem::path(scenario.world_file).parent_path() / "map.yaml").string();
  } else if (map != "derive") {
    l.map_file = (std::filesystem::path(base) / map).string();
  }
  if (!l.derive_map_noise_m && !std::filesystem::exists(l.map_file)) {
    doc->Error(m.Has("map") ? m.Child("map") : node, m.PathOf("map"),
               "no map file '" + l.map_file + "' (derive one: pavilion map derive)");
  }
  if (auto o = m.Numbers("initial_offset", 3, false))
    l.initial_offset = {(*o)[0], (*o)[1], (*o)[2]};
  const std::string method = m.String("method", "ekf");
  if (method != "ekf" && method != "global") {
    doc->Error(m.Child("method"), m.PathOf("method"),
               "expected 'ekf' (thesis chapter 4) or 'global' (chapter 5), not '" + method + "'");
  }
  const std::string initial = m.String("initial", "known");
  if (initial != "known" && initial != "unknown") {
    doc->Error(m.Child("initial"), m.PathOf("initial"),
               "expected 'known' or 'unknown', not '" + initial + "'");
  }
  l.initial_unknown = initial == "unknown";
  const std::string shadow = m.String("shadow", "none");
  if (shadow != "none" && shadow != "mcl") {
    doc->Error(
        m.Child("shadow"), m.PathOf("shadow"),
        "expected 'mcl' (Monte Carlo localization beside it) or 'none', not '" + shadow + "'");
  }
  l.shadow_mcl = shadow == "mcl";
  l.global = method == "global" || l.initial_unknown;
  if (l.initial_unknown && method == "ekf" && m.Has("method")) {
    doc->Error(m.Child("initial"), m.PathOf("initial"),
               "'initial: unknown' needs 'method: global' (the EKF tracks from a known start)");
  }
  std::vector<OptionField<LocalizationEntry>> fields = {
      {"rate_hz", &LocalizationEntry::rate_hz},
      {"initial_sigma", &LocalizationEntry::initial_sigma},
      {"significance", &LocalizationEntry::significance},
      {"line_floor_r_m", &LocalizationEntry::line_floor_r_m},
      {"line_floor_alpha_deg", "line_floor_alpha_rad", &LocalizationEntry::line_floor_alpha_rad,
       kRadPerDeg},
      {"hold_ms", "hold_s", &LocalizationEntry::hold_s, 1e-3},
      {"odometry_k_scale", &LocalizationEntry::odometry_k_scale},
      {"slip_sigma", &LocalizationEntry::slip_sigma}};
  if (l.derive_map_noise_m) {
    fields.push_back({"map_noise_m", "derive_map_noise_m", &LocalizationEntry::derive_map_noise_m});
  }
  ReadOptions(m, &l, fields);
  std::vector<std::string> known_lasers;
  for (const sim::LaserMount& mount : robot->config.lasers) known_lasers.push_back(mount.id);
  ReadSensorIds(doc, m, "lasers", "laser", known_lasers, robot->model, &l.lasers);
  std::vector<std::string> known_cameras;
  for (const sim::CameraMount& mount : robot->config.cameras) known_cameras.push_back(mount.id);
  ReadSensorIds(doc, m, "cameras", "camera", known_cameras, robot->model, &l.cameras);
  for (std::size_t k = 0; k < l.cameras.size(); ++k) {
    for (const sim::CameraMount& mount : robot->config.cameras) {
      if (mount.id == l.cameras[k] &&
          (std::abs(mount.mount.roll_rad) > 1e-6 || std::abs(mount.mount.pitch_rad) > 1e-6)) {
        doc->Error(m.Child("cameras")[k], IndexPath(m.PathOf("cameras"), k),
                   "camera '" + mount.id + "' of robot model '" + robot->model +
                       "' is not level: vertical edges (§3.4) need a camera looking level");
      }
    }
  }
  m.Finish();
}

// route: {stops: [node ids], start_s, max_speed_mps, max_accel_mps2,
// max_turn_rate_radps, max_turn_accel_radps2, lookahead_m, max_lateral_accel_mps2,
// goal_tolerance_m, control_rate_hz}
void ReadRoute(YamlDocument* doc, MapReader& r, RobotEntry* robot) {
  YAML::Node node = r.Child("route");
  if (!node.IsDefined()) return;
  MapReader m(doc, node, r.PathOf("route"));
  if (!m.valid()) return;
  RouteEntry route;
  YAML::Node stops = m.Child("stops", true);
  if (stops.IsDefined() && (!stops.IsSequence() || stops.size() < 2)) {
    doc->Error(stops, m.PathOf("stops"), "expected a list of at least two map node ids");
  }
  for (std::size_t k = 0; stops.IsSequence() && k < stops.size(); ++k) {
    route.stops.push_back(stops[k].as<std::string>(""));
  }
  ReadOptions(
      m, &route,
      {{"start_s", &RouteEntry::start_s}, {"control_rate_hz", &RouteEntry::control_rate_hz}});
  using Follower = nav::PathFollowerOptions;
  ReadOptions(m, &route.follower,
              {{"max_speed_mps", &Follower::max_speed_mps},
               {"max_accel_mps2", &Follower::max_accel_mps2},
               {"max_turn_rate_radps", &Follower::max_turn_rate_radps},
               {"max_turn_accel_radps2", &Follower::max_turn_accel_radps2},
               {"lookahead_m", &Follower::lookahead_m},
               {"max_lateral_accel_mps2", &Follower::max_lateral_accel_mps2},
               {"goal_tolerance_m", &Follower::goal_tolerance_m}});
  m.Finish();
  robot->route = route;
}

// wander: {laser, cruise_speed_mps, avoid_speed_mps, avoid_turn_rate_radps,
// obstruction_distance_m, stop_distance_m, min_avoid_scans, max_avoid_scans};
// every key optional (the peers' values, nav::WanderOptions), `laser`
// defaulting to the model's first.
void ReadWander(YamlDocument* doc, MapReader& r, bool model_ok, RobotEntry* robot) {
  YAML::Node node = r.Child("wander");
  if (!node.IsDefined()) return;
  MapReader m(doc, node, r.PathOf("wander"));
  if (!m.valid()) return;
  WanderEntry wander;
  const auto& lasers = robot->config.lasers;
  if (m.Has("laser")) {
    wander.laser = m.RequiredString("laser").value_or("");
    const bool known = std::any_of(lasers.begin(), lasers.end(),
                                   [&](const sim::LaserMount& l) { return l.id == wander.laser; });
    if (model_ok && !known) {
      doc->Error(m.Child("laser"), m.PathOf("laser"),
                 "robot model '" + robot->model + "' has no laser '" + wander.laser + "'");
    }
  } else if (!lasers.empty()) {
    wander.laser = lasers.front().id;
  } else if (model_ok) {
    doc->Error(node, m.PathOf("laser"),
               "robot model '" + robot->model + "' has no laser for the wander controller");
  }
  using Wander = nav::WanderOptions;
  ReadOptions(m, &wander.options,
              {{"cruise_speed_mps", &Wander::cruise_speed_mps},
               {"avoid_speed_mps", &Wander::avoid_speed_mps},
               {"avoid_turn_rate_radps", &Wander::avoid_turn_rate_radps},
               {"obstruction_distance_m", &Wander::obstruction_distance_m},
               {"stop_distance_m", &Wander::stop_distance_m},
               {"min_avoid_scans", &Wander::min_avoid_scans},
               {"max_avoid_scans", &Wander::max_avoid_scans}});
  m.Finish();
  robot->wander = wander;
}

// A robot's `model`: its robot file, read once per file into `models` (a fleet
// of a thousand robots of one model would otherwise parse its URDF a thousand
// times at start-up). Returns whether the model loaded.
bool ReadRobotModel(YamlDocument* doc, MapReader& r, const std::string& base,
                    std::map<std::string, sim::RobotConfig>* models, RobotEntry* robot) {
  auto model = r.RequiredString("model");
  if (!model) return false;
  robot->model = *model;
  try {
    const std::string model_path = ResolveRobotPath(*model, base);
    auto it = models->find(model_path);
    if (it == models->end()) it = models->emplace(model_path, LoadRobotFile(model_path)).first;
    robot->config = it->second;
    return true;
  } catch (const InputError& e) {
    doc->Error(r.Child("model"), r.PathOf("model"),
               "robot model '" + *model + "' is invalid: " + e.diagnostics().front().ToString());
    return false;
  }
}

// The entry's adjustments of its model: systematic errors, wheel model, and
// the encoders' and lasers' noise switches.
void ReadModelAdjustments(YamlDocument* doc, MapReader& r, const Scenario& s, RobotEntry* robot) {
  if (YAML::Node sys = r.Child("systematic"); sys.IsDefined()) {
    MapReader m(doc, sys, r.PathOf("systematic"));
    ReadOptions(m, &robot->config.systematic,
                {{"wheel_radius_ratio", &sim::SystematicErrors::wheel_radius_ratio},
                 {"wheelbase_factor", &sim::SystematicErrors::wheelbase_factor},
                 {"mean_radius_factor", &sim::SystematicErrors::mean_radius_factor}});
    m.Finish();
  }
  robot->wheel_model = ReadWheelModel(r, s.wheel_model);
  robot->config.encoders.noise = r.Bool("encoder_noise", robot->config.encoders.noise);
  // laser_noise: false turns every laser's range noise, outliers and dark
  // dropouts off (sim::LaserScannerOptions::noise).
  if (r.Has("laser_noise")) {
    const bool laser_noise = r.Bool("laser_noise", true);
    for (sim::LaserMount& mount : robot->config.lasers) mount.options.noise = laser_noise;
  }
}

// drive: [{at_s, left, right} | {at_s, speed_mps, turn_radps}], in time order.
void ReadDrive(YamlDocument* doc, MapReader& r, bool model_ok, RobotEntry* robot) {
  YAML::Node drive = r.Child("drive");
  if (drive.IsDefined() && !drive.IsSequence()) {
    doc->Error(drive, r.PathOf("drive"), "expected a list of {at_s, left, right} steps");
  }
  for (std::size_t k = 0; drive.IsSequence() && k < drive.size(); ++k) {
    const std::string step_path = IndexPath(r.PathOf("drive"), k);
    MapReader d(doc, drive[k], step_path);
    if (!d.valid()) continue;
    DriveCommand c;
    c.at_s = d.RequiredNumber("at_s", 0.0, kMaxDurationS).value_or(0.0);
    const bool wheels = d.Has("left") || d.Has("right");
    const bool body = d.Has("speed_mps") || d.Has("turn_radps");
    if (wheels == body) {
      doc->Error(drive[k], step_path,
                 "give either left and right (rad/s) or speed_mps and turn_radps");
    } else if (wheels) {
      c.left_radps = d.RequiredNumber("left", -1000.0, 1000.0).value_or(0.0);
      c.right_radps = d.RequiredNumber("right", -1000.0, 1000.0).value_or(0.0);
    } else {
      const double v = d.Number("speed_mps", 0.0, -10.0, 10.0);
      const double w = d.Number("turn_radps", 0.0, -20.0, 20.0);
      if (model_ok) {
        // Inverse kinematics with the robot's calibrated odometry (eq. 2.7).
        const auto& o = robot->config.odometry;
        c.left_radps = (v - 0.5 * w * o.wheelbase_m) / o.left_wheel_radius_m;
        c.right_radps = (v + 0.5 * w * o.wheelbase_m) / o.right_wheel_radius_m;
      }
    }
    d.Finish();
    if (!robot->drive.empty() && c.at_s < robot->drive.back().at_s) {
      doc->Error(drive[k], step_path, "drive steps must be in time order");
    }
    robot->drive.push_back(c);
  }
}

// robots: [{id, model, pose: [x, y, theta], drive: [...], systematic: {...},
// encoder_noise: bool, laser_noise: bool, wheel_model: articulated | raycast,
// localization: {...}, route: {...}, mission: {...}, wander: {...}}]
void ReadRobots(YamlDocument* doc, MapReader& top, const std::string& base, Scenario* s) {
  YAML::Node list = top.Child("robots");
  if (!list.IsDefined() || list.IsNull()) return;
  if (!list.IsSequence()) {
    doc->Error(list, "robots", "expected a list");
    return;
  }
  std::set<std::string> ids = WorldElementIds(s->world);
  for (const auto& b : s->bodies) ids.insert(b.spec.id);
  std::map<std::string, sim::RobotConfig> models;  // by resolved robot file
  for (std::size_t i = 0; i < list.size(); ++i) {
    MapReader r(doc, list[i], IndexPath("robots", i));
    if (!r.valid()) continue;
    RobotEntry robot;
    robot.id = r.RequiredString("id").value_or("");
    if (!robot.id.empty() &&
        (!ids.insert(robot.id).second || robot.id.find('/') != std::string::npos)) {
      doc->Error(
          r.Child("id"), r.PathOf("id"),
          "robot id '" + robot.id + "' is used twice, by a world element or body, or has a '/'");
    }
    if (auto p = r.Numbers("pose", 3, true)) robot.pose = {(*p)[0], (*p)[1], (*p)[2]};
    const bool model_ok = ReadRobotModel(doc, r, base, &models, &robot);
    ReadModelAdjustments(doc, r, *s, &robot);
    ReadDrive(doc, r, model_ok, &robot);
    ReadLocalization(doc, r, base, *s, &robot);
    // Cameras are off unless the scenario uses them (rendering is not free).
    robot.model_cameras = robot.config.cameras;
    std::erase_if(robot.config.cameras, [&](const sim::CameraMount& c) {
      const auto& on = robot.localization.cameras;
      return std::find(on.begin(), on.end(), c.id) == on.end();
    });
    ReadRoute(doc, r, &robot);
    ReadMission(doc, r, *s, &robot);
    ReadWander(doc, r, model_ok, &robot);
    // One controller per robot: a scripted drive, a route, a mission or a wander.
    const int controllers =
        static_cast<int>(!robot.drive.empty()) + static_cast<int>(robot.route.has_value()) +
        static_cast<int>(robot.mission.has_value()) + static_cast<int>(robot.wander.has_value());
    if (controllers > 1) {
      const std::string key = robot.wander ? "wander" : robot.mission ? "mission" : "route";
      doc->Error(r.Child(key), r.PathOf(key),
                 "give only one of drive, route, mission and wander (each drives the wheels)");
    }
    r.Finish();
    s->robots.push_back(robot);
  }
}

// A number as people write it: 60, 2.5.
std::string FormatNumber(double value) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", value);
  return buf;
}

// The ids and geometry events are checked against.
EventTargets ReadEventTargets(const Scenario& s) {
  EventTargets targets;
  for (const auto& b : s.bodies) targets.bodies.insert(b.spec.id);
  for (const auto& r : s.robots) {
    targets.bodies.insert(r.id);
    targets.robots.insert(r.id);
    for (const sim::LaserMount& l : r.config.lasers) targets.lasers[r.id].push_back(l.id);
    const sim::RobotDescription& model = r.config.description;
    if (model.footprint_m.size() >= 3) {
      targets.footprints[r.id] =
          RobotFootprint{nav::Circumradius(model.footprint_m), model.chassis_base_z_m,
                         model.chassis_base_z_m + model.chassis_height_m};
    }
  }
  for (const auto& d : s.world.doors) targets.doors.insert(d.id);
  targets.world = &s.world;
  if (s.crowd) targets.crowd_pool = s.crowd->options.pool_size;
  return targets;
}

// Each entry at at_s and, with every_s, again at at_s + k every_s while the
// run lasts. `file_duration_s`: the file's duration_s (before --duration),
// which no event may be due after. An entry with `random:` expands into timed
// events of its type (random_events.h).
void ReadEvents(YamlDocument* doc, MapReader& top, double file_duration_s, Scenario* s) {
  YAML::Node list = top.Child("events");
  if (!list.IsDefined() || list.IsNull()) return;
  if (!list.IsSequence()) {
    doc->Error(list, "events", "expected a list");
    return;
  }
  const EventTargets targets = ReadEventTargets(*s);
  const EventRegistry& registry = EventRegistry::Global();
  for (std::size_t i = 0; i < list.size(); ++i) {
    MapReader r(doc, list[i], IndexPath("events", i));
    if (!r.valid()) continue;
    if (r.Has("random")) {
      ExpandRandomEvent(r, i, targets, {s->seed, file_duration_s, s->duration_s}, &s->events);
      continue;
    }
    TimedEvent e;
    e.at_s = r.RequiredNumber("at_s", 0.0, kMaxDurationS).value_or(0.0);
    if (e.at_s > file_duration_s) {
      doc->Error(r.Child("at_s"), r.PathOf("at_s"),
                 "the event is due after the scenario's duration_s (" +
                     FormatNumber(file_duration_s) + " s)");
    }
    const double every_s = r.Number("every_s", 0.0, 0.0, kMaxDurationS);
    if (r.Has("every_s") && every_s * kMaxEventRepeats < s->duration_s - e.at_s) {
      doc->Error(r.Child("every_s"), r.PathOf("every_s"),
                 "repeats more than " + std::to_string(kMaxEventRepeats) + " times in the run");
    }
    const std::vector<std::string> types = registry.types();
    const std::string type = r.Choice("type", types, types.front(), true);
    if (const EventReader* read = registry.Find(type)) e.event = (*read)(r, targets);
    r.Finish();
    if (!e.event) continue;
    s->events.push_back(e);
    if (every_s <= 0.0 || !doc->ok()) continue;
    for (int k = 1; e.at_s + k * every_s < s->duration_s; ++k) {
      s->events.push_back(TimedEvent{e.at_s + k * every_s, e.event});
    }
  }
  std::stable_sort(s->events.begin(), s->events.end(),
                   [](const TimedEvent& a, const TimedEvent& b) { return a.at_s < b.at_s; });
}

// kind, name, description, seed, duration_s, end_when_routes_done, the laser
// backend and laser_max_tilt_deg; then the command line's seed and duration.
// Returns the file's duration_s.
double ReadHeader(YamlDocument* doc, MapReader& top, const ScenarioOverrides& overrides,
                  Scenario* s) {
  if (auto kind = top.RequiredString("kind"); kind && *kind != "scenario") {
    doc->Error(top.Child("kind"), "kind", "expected 'scenario', got '" + *kind + "'");
  }
  s->name = top.RequiredString("name").value_or("");
  s->description = top.String("description", "");
  s->seed = static_cast<std::uint64_t>(top.Integer("seed", 1, 0, INT64_MAX));
  s->duration_s = top.RequiredNumber("duration_s", 1e-3, kMaxDurationS).value_or(1.0);
  s->end_when_routes_done = top.Bool("end_when_routes_done", false);
  s->laser_backend = top.Choice("laser_backend", {"planar", "bullet"}, "planar") == "bullet"
                         ? LaserBackend::kBullet
                         : LaserBackend::kPlanar;
  ReadOptions(top, &s->planar_laser,
              {{"laser_max_tilt_deg", "max_tilt_rad", &sim::PlanarCasterOptions::max_tilt_rad,
                kRadPerDeg}});
  const double file_duration_s = s->duration_s;
  if (overrides.seed) s->seed = *overrides.seed;
  if (overrides.duration_s) s->duration_s = *overrides.duration_s;
  return file_duration_s;
}

// The optional mapping under `key` of `top`; an empty one (its defaults) when absent.
MapReader OptionalSection(YamlDocument* doc, MapReader& top, const std::string& key) {
  return MapReader(doc, top.Has(key) ? top.Child(key) : YAML::Node(YAML::NodeType::Map), key);
}

// physics: {rate_hz, solver_iterations, gravity_mps2, wheel_model} and
// outputs: {trajectory_rate_hz, body_rate_hz, section_height_m, image_width_px, scan_log,
// scan_log_robot_minutes, people_rate_hz}.
void ReadPhysicsAndOutputs(YamlDocument* doc, MapReader& top, Scenario* s) {
  MapReader physics = OptionalSection(doc, top, "physics");
  using Physics = sim::WorldOptions;
  ReadOptions(physics, &s->physics,
              {{"rate_hz", "physics_rate_hz", &Physics::physics_rate_hz},
               {"solver_iterations", &Physics::solver_iterations},
               {"gravity_mps2", &Physics::gravity_mps2}});
  s->wheel_model = ReadWheelModel(physics, s->wheel_model);
  physics.Finish();
  MapReader outputs = OptionalSection(doc, top, "outputs");
  ReadOptions(outputs, &s->outputs,
              {{"trajectory_rate_hz", &OutputOptions::trajectory_rate_hz},
               {"section_height_m", &OutputOptions::section_height_m},
               {"image_width_px", &OutputOptions::image_width_px},
               {"body_rate_hz", &OutputOptions::body_rate_hz},
               {"scan_log_robot_minutes", &OutputOptions::scan_log_robot_minutes},
               {"people_rate_hz", &OutputOptions::people_rate_hz}});
  // Bodies follow the robots' rate unless given their own.
  if (!outputs.Has("body_rate_hz")) s->outputs.body_rate_hz = s->outputs.trajectory_rate_hz;
  if (outputs.Has("scan_log")) {
    const YAML::Node mode = outputs.Child("scan_log");
    const std::string text = mode.IsScalar() ? mode.Scalar() : "";
    if (text == "auto") {
      s->outputs.scan_log = ScanLogMode::kAuto;
    } else if (text == "true" || text == "false") {
      s->outputs.scan_log = text == "true" ? ScanLogMode::kOn : ScanLogMode::kOff;
    } else {
      doc->Error(mode, "outputs.scan_log", "expected auto, true or false");
    }
  }
  // OutputOptions::Validate() does not bound people_rate_hz (yet): its header's range.
  if (!(s->outputs.people_rate_hz >= 0.0 && s->outputs.people_rate_hz <= kMaxPeopleRateHz)) {
    doc->Error(outputs.Child("people_rate_hz"), "outputs.people_rate_hz",
               "OutputOptions.people_rate_hz must be in [0, 1e4] Hz");
    s->outputs.people_rate_hz = OutputOptions{}.people_rate_hz;
  }
  outputs.Finish();
}

// fleet: {coordination, deadlock_resolution, peak_weight_m, falloff_m,
// horizon_m, occupied_station_cost_m, release_distance_m, claim_ahead_m,
// claim_radius_m}.
void ReadFleet(YamlDocument* doc, MapReader& top, Scenario* s) {
  MapReader fleet = OptionalSection(doc, top, "fleet");
  s->fleet.coordination = fleet.Choice("coordination", {"on", "off"}, "on") == "on";
  s->fleet.deadlock_resolution = fleet.Choice("deadlock_resolution", {"on", "off"}, "on") == "on";
  using Fleet = nav::FleetOptions;
  ReadOptions(fleet, &s->fleet.options,
              {{"peak_weight_m", &Fleet::peak_weight_m},
               {"falloff_m", &Fleet::falloff_m},
               {"horizon_m", &Fleet::horizon_m},
               {"occupied_station_cost_m", &Fleet::occupied_station_cost_m},
               {"release_distance_m", &Fleet::release_distance_m},
               {"claim_ahead_m", &Fleet::claim_ahead_m},
               {"claim_radius_m", &Fleet::claim_radius_m}});
  fleet.Finish();
}

// world (loaded from its own file, its problems reported against it; throws
// with every diagnostic so far when it has any), the scenario's materials
// added to the world's (bodies such as visitors) and door_states.
void ReadWorldAndAdditions(YamlDocument* doc, MapReader& top, const std::string& base,
                           Scenario* s) {
  if (auto world = top.RequiredString("world")) {
    try {
      s->world_file = ResolveWorldPath(*world, base);
      s->world = LoadWorldFile(s->world_file);
    } catch (const InputError& e) {
      auto all = doc->diagnostics();
      all.insert(all.end(), e.diagnostics().begin(), e.diagnostics().end());
      throw InputError(all);
    }
  }
  if (YAML::Node mats = top.Child("materials"); mats.IsDefined()) {
    std::map<std::string, sim::Material> extra;
    ReadMaterialMap(doc, mats, "materials", &extra);
    for (const auto& [name, m] : extra) {
      if (s->world.materials.contains(name)) {
        doc->Error(mats, "materials." + name, "material already defined by the world");
      }
      s->world.materials[name] = m;
    }
  }
  if (YAML::Node states = top.Child("door_states"); states.IsDefined()) {
    MapReader r(doc, states, "door_states");
    for (auto& door : s->world.doors) {
      if (r.Has(door.id)) door.open = r.Choice(door.id, {"open", "closed"}, "closed") == "open";
    }
    r.Finish();
  }
}

// Events due at or after the (overridden) duration never happen: dropped with
// a note, as a shorter --duration asks.
void SkipEventsPastTheEnd(Scenario* s) {
  const auto past = [&](const TimedEvent& e) { return e.at_s >= s->duration_s; };
  const auto skipped = std::count_if(s->events.begin(), s->events.end(), past);
  if (skipped == 0) return;
  std::erase_if(s->events, past);
  s->notes.push_back(std::to_string(skipped) + " event(s) due at or after " +
                     FormatNumber(s->duration_s) + " s skipped (the run is shorter)");
}

// The ids a metric path of `expect:` may name.
MetricIds MetricIdsOf(const Scenario& s) {
  MetricIds ids{{}, {}, KnownEventTypes()};
  for (const RobotEntry& r : s.robots) ids.robots.insert(r.id);
  for (const BodyEntry& b : s.bodies) ids.bodies.insert(b.spec.id);
  return ids;
}

}  // namespace

const char* ToString(LaserBackend backend) {
  return backend == LaserBackend::kBullet ? "bullet" : "planar";
}

Scenario LoadScenarioFile(const std::string& path, const ScenarioOverrides& overrides) {
  YamlDocument doc(path);
  doc.ThrowIfErrors();
  for (const std::string& assignment : overrides.assignments) {
    ApplyOverride(doc.mutable_root(), assignment, true);
  }
  Scenario s;
  s.source_file = path;
  MapReader top(&doc, doc.root(), "");
  if (!top.valid()) doc.ThrowIfErrors();
  const double file_duration_s = ReadHeader(&doc, top, overrides, &s);
  ReadPhysicsAndOutputs(&doc, top, &s);
  ReadFleet(&doc, top, &s);
  const std::string base = std::filesystem::path(path).parent_path().string();
  ReadWorldAndAdditions(&doc, top, base, &s);
  ReadBodies(&doc, top, s.world, &s);
  ReadRobots(&doc, top, base, &s);
  ReadRealism(&doc, top, &s.realism);
  for (RobotEntry& r : s.robots) DrawRealisticRobot(s.realism, s.seed, &r);
  std::vector<std::string> robot_ids;
  for (const RobotEntry& r : s.robots) robot_ids.push_back(r.id);
  ReadSnapshots(&doc, top, robot_ids, &s.snapshots);
  ReadRunReference(&doc, top, &s.reference);
  ReadCrowd(&doc, top, &s);
  ReadEvents(&doc, top, file_duration_s, &s);
  s.expectations = ReadExpectations(top, MetricIdsOf(s));
  top.Finish();
  doc.ThrowIfErrors();
  SkipEventsPastTheEnd(&s);
  return s;
}

}  // namespace pavilion::scenarios
