#include "scenarios/config/crowd_reader.h"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "core/geometry/polygon.h"
#include "scenarios/config/options_reader.h"

namespace pavilion::scenarios {
namespace {

namespace crowd = sim::crowd;

const char* const kDefaultEntrance = "visitor_spawn";
const char* const kDefaultExit = "visitor_exit";
const char* const kDefaultMaterial = "visitor";

// A station: flagged so or named station_* or dock_* (as map derivation decides).
bool IsStation(const std::string& name, const sim::Place& place) {
  return place.station || name.starts_with("station_") || name.starts_with("dock_");
}

// The value of `key` in the mapping `map` (undefined when absent or not a
// mapping), found without operator[].
YAML::Node Lookup(const YAML::Node& map, const std::string& key) {
  if (!map.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
  for (const auto& kv : map) {
    if (kv.first.IsScalar() && kv.first.Scalar() == key) return kv.second;
  }
  return YAML::Node(YAML::NodeType::Undefined);
}

// The key node `key` of the mapping `map` (for its line); `map` when absent.
YAML::Node KeyNode(const YAML::Node& map, const std::string& key) {
  for (const auto& kv : map) {
    if (kv.first.IsScalar() && kv.first.Scalar() == key) return kv.first;
  }
  return map;
}

// The node to report a problem of `key` at: its value when written, else `block`.
YAML::Node At(MapReader& r, const std::string& key, const YAML::Node& block) {
  return r.Has(key) ? r.Child(key) : block;
}

// The integer `key` of `r` as written; `fallback` when absent or not an
// integer (which ReadOptions reports).
int PeekInteger(const MapReader& r, const std::string& key, int fallback) {
  const YAML::Node child = Lookup(r.node(), key);
  int value;
  if (!child.IsDefined() || !child.IsScalar() || !YAML::convert<int>::decode(child, value)) {
    return fallback;
  }
  return value;
}

std::string FormatPoint(const Eigen::Vector2d& p) {
  char text[64];
  std::snprintf(text, sizeof text, "(%g, %g)", p.x(), p.y());
  return text;
}

// Reads the optional mapping `key` of `r` (absent or null: the defaults) into
// *options. A section that Validate() rejected is reported and reset to its
// defaults, so that the crowd's own Validate(), which checks its parts again,
// does not report it a second time.
template <typename Options>
void ReadSection(YamlDocument* doc, MapReader& r, const std::string& key, Options* options,
                 const std::vector<OptionField<Options>>& fields) {
  const YAML::Node node = r.Child(key);
  const bool empty = !node.IsDefined() || node.IsNull();
  MapReader section(doc, empty ? YAML::Node(YAML::NodeType::Map) : node, r.PathOf(key));
  if (!ReadOptions(section, options, fields)) *options = Options{};
  section.Finish();
}

void ReadVisitAndBehaviours(YamlDocument* doc, MapReader& r, crowd::CrowdOptions* o) {
  using Visit = crowd::VisitOptions;
  ReadSection<Visit>(doc, r, "visit", &o->visit,
                     {{"min_exhibits", &Visit::min_exhibits},
                      {"max_exhibits", &Visit::max_exhibits},
                      {"dwell_mean_s", &Visit::dwell_mean_s},
                      {"dwell_std_s", &Visit::dwell_std_s},
                      {"visit_mean_s", &Visit::visit_mean_s},
                      {"visit_std_s", &Visit::visit_std_s},
                      {"desired_speed_mean_mps", &Visit::desired_speed_mean_mps},
                      {"desired_speed_std_mps", &Visit::desired_speed_std_mps},
                      {"group_fraction", &Visit::group_fraction},
                      {"min_group_size", &Visit::min_group_size},
                      {"max_group_size", &Visit::max_group_size}});
  using Behaviour = crowd::BehaviourOptions;
  ReadSection<Behaviour>(doc, r, "behaviours", &o->behaviours,
                         {{"curious", &Behaviour::curious},
                          {"crowding", &Behaviour::crowding},
                          {"blocking", &Behaviour::blocking},
                          {"following", &Behaviour::following},
                          {"pushing", &Behaviour::pushing},
                          {"notice_range_m", &Behaviour::notice_range_m},
                          {"episode_mean_s", &Behaviour::episode_mean_s},
                          {"cooldown_s", &Behaviour::cooldown_s},
                          {"push_force_n", &Behaviour::push_force_n},
                          {"push_duration_s", &Behaviour::push_duration_s},
                          {"kick_duration_s", &Behaviour::kick_duration_s}});
}

void ReadBodyAndSocialForce(YamlDocument* doc, MapReader& r, crowd::CrowdOptions* o) {
  using Body = crowd::PersonBodyOptions;
  ReadSection<Body>(doc, r, "body", &o->body,
                    {{"min_shoulder_radius_m", &Body::min_shoulder_radius_m},
                     {"max_shoulder_radius_m", &Body::max_shoulder_radius_m},
                     {"min_leg_diameter_m", &Body::min_leg_diameter_m},
                     {"max_leg_diameter_m", &Body::max_leg_diameter_m},
                     {"hip_height_m", &Body::hip_height_m},
                     {"height_m", &Body::height_m},
                     {"hip_half_width_m", &Body::hip_half_width_m},
                     {"mass_kg", &Body::mass_kg},
                     {"step_length_m", &Body::step_length_m}});
  using Social = crowd::SocialForceOptions;
  ReadSection<Social>(doc, r, "social_force", &o->social,
                      {{"relaxation_s", &Social::relaxation_s},
                       {"person_strength_n", &Social::person_strength_n},
                       {"person_range_m", &Social::person_range_m},
                       {"anisotropy", &Social::anisotropy},
                       {"wall_strength_n", &Social::wall_strength_n},
                       {"wall_range_m", &Social::wall_range_m},
                       {"robot_strength_n", &Social::robot_strength_n},
                       {"robot_range_m", &Social::robot_range_m},
                       {"body_stiffness_npm", &Social::body_stiffness_npm},
                       {"sliding_friction_nspm2", &Social::sliding_friction_nspm2},
                       {"max_speed_factor", &Social::max_speed_factor},
                       {"social_rate_hz", &Social::social_rate_hz},
                       {"social_cutoff_m", &Social::social_cutoff_m},
                       {"max_substep_s", &Social::max_substep_s},
                       {"max_push_force_n", &Social::max_push_force_n},
                       {"contact_restitution", &Social::contact_restitution}});
}

// The crowd's own fields, after its sections: CrowdOptions::Validate() checks
// them with the sections read (a group must fit the pool). The pool and
// max_present default to each other: the pool to max_present (and at least
// present), max_present to a pool that is given; neither given, the struct's.
void ReadCrowdFields(MapReader& r, crowd::CrowdOptions* o) {
  if (!r.Has("pool")) {
    o->pool_size = std::max({1, PeekInteger(r, "max_present", o->max_present),
                             PeekInteger(r, "present", o->initial_present)});
  } else if (!r.Has("max_present")) {
    o->max_present = PeekInteger(r, "pool", o->max_present);
  }
  using Crowd = crowd::CrowdOptions;
  // Validate() names pool_size and initial_present by their keys.
  ReadOptions(r, o,
              {{"pool", &Crowd::pool_size},
               {"present", &Crowd::initial_present},
               {"max_present", &Crowd::max_present},
               {"arrivals_per_hour", &Crowd::arrivals_per_hour},
               {"route_cell_m", &Crowd::route_cell_m},
               {"route_clearance_m", &Crowd::route_clearance_m},
               {"watch_spots", &Crowd::watch_spots}});
}

// Every vertex of `area` on the floor rectangle; else reports it at `at`.
bool OnTheFloor(YamlDocument* doc, const YAML::Node& at, const std::string& path,
                const std::string& what, const core::Polygon2& area,
                const sim::WorldDescription& world) {
  const Eigen::Vector2d& lo = world.floor.min_m;
  const Eigen::Vector2d& hi = world.floor.max_m;
  for (const Eigen::Vector2d& v : area) {
    if ((v.array() < lo.array()).any() || (v.array() > hi.array()).any()) {
      doc->Error(at, path,
                 what + " reaches off the floor " + FormatPoint(lo) + " to " + FormatPoint(hi) +
                     " at " + FormatPoint(v));
      return false;
    }
  }
  return true;
}

// An inline polygon [[x, y], ...]: at least 3 points, simple, on the floor.
core::Polygon2 ReadPolygon(YamlDocument* doc, const YAML::Node& node, const std::string& path,
                           const sim::WorldDescription& world) {
  core::Polygon2 polygon;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const auto p = ReadNumbers(doc, node[i], IndexPath(path, i), 2);
    if (!p) return {};  // reported
    polygon.emplace_back((*p)[0], (*p)[1]);
  }
  if (polygon.size() < 3 || !core::IsSimple(polygon)) {
    doc->Error(node, path, "expected a simple polygon of at least 3 [x, y] points");
    return {};
  }
  return OnTheFloor(doc, node, path, "the polygon", polygon, world) ? polygon : core::Polygon2{};
}

// The area `key` names: a place of the world with an area, or an inline
// polygon; absent, the place `default_name` (none when that is empty, and a
// missing default is reported at `block`). Every vertex must lie on the floor.
core::Polygon2 ReadArea(YamlDocument* doc, MapReader& r, const YAML::Node& block,
                        const std::string& key, const std::string& default_name,
                        const sim::WorldDescription& world) {
  if (!r.Has(key) && default_name.empty()) {
    r.Child(key);  // known, absent: none
    return {};
  }
  if (r.Has(key) && r.Child(key).IsSequence()) {
    return ReadPolygon(doc, r.Child(key), r.PathOf(key), world);
  }
  const std::optional<std::string> written = r.Has(key) ? r.RequiredString(key) : default_name;
  if (!written) return {};  // neither a name nor a list: reported
  const std::string& name = *written;
  const std::string what = r.Has(key) ? "" : " (the default " + key + ")";
  const YAML::Node at = At(r, key, block);
  const auto it = world.places.find(name);
  if (it == world.places.end()) {
    doc->Error(at, r.PathOf(key), "no place '" + name + "' in world '" + world.name + "'" + what);
    return {};
  }
  if (!it->second.area) {
    doc->Error(at, r.PathOf(key), "place '" + name + "' has no area" + what);
    return {};
  }
  if (!OnTheFloor(doc, at, r.PathOf(key), "place '" + name + "'" + what, *it->second.area, world)) {
    return {};
  }
  return *it->second.area;
}

// `attractions`: listed stations of the world, or by default every station
// but the docks whose attraction is above 0, by name.
std::vector<crowd::Attraction> ReadAttractions(YamlDocument* doc, MapReader& r,
                                               const sim::WorldDescription& world) {
  std::vector<crowd::Attraction> out;
  const YAML::Node list = r.Child("attractions");
  if (!list.IsDefined()) {
    for (const auto& [name, place] : world.places) {
      if (IsStation(name, place) && !name.starts_with("dock_") && place.pose &&
          place.attraction > 0.0) {
        out.push_back(crowd::Attraction{name, *place.pose, place.attraction});
      }
    }
    return out;
  }
  const std::string path = r.PathOf("attractions");
  if (!list.IsSequence()) {
    doc->Error(list, path, "expected a list of station names");
    return out;
  }
  std::set<std::string> listed;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node item = list[i];
    const std::string name = item.IsScalar() ? item.Scalar() : "";
    const auto it = world.places.find(name);
    if (!item.IsScalar()) {
      doc->Error(item, IndexPath(path, i), "expected a station name");
    } else if (it == world.places.end()) {
      doc->Error(item, IndexPath(path, i), "no place '" + name + "' in world '" + world.name + "'");
    } else if (!IsStation(name, it->second) || !it->second.pose) {
      doc->Error(item, IndexPath(path, i),
                 "place '" + name +
                     "' is not a station (station: true, or a name station_* or dock_*, "
                     "with a pose)");
    } else if (!listed.insert(name).second) {
      doc->Error(item, IndexPath(path, i), "station '" + name + "' is listed twice");
    } else {
      out.push_back(crowd::Attraction{name, *it->second.pose, it->second.attraction});
    }
  }
  return out;
}

// Ids the crowd's people take (prefix + 001, ...) must be free: no body,
// group member, robot or world element id may start with the prefix.
void CheckIdsAreFree(YamlDocument* doc, MapReader& top, const YAML::Node& block,
                     const sim::WorldDescription& world, const std::string& prefix) {
  for (const std::string list_key : {"bodies", "groups", "robots"}) {
    const YAML::Node list = Lookup(top.node(), list_key);
    if (!list.IsDefined() || !list.IsSequence()) continue;
    const bool group = list_key == "groups";
    for (std::size_t i = 0; i < list.size(); ++i) {
      const YAML::Node id = Lookup(list[i], "id");
      if (!id.IsDefined() || !id.IsScalar()) continue;
      // A group's members are <id>_000, <id>_001, ...
      if (!(group ? id.Scalar() + "_" : id.Scalar()).starts_with(prefix)) continue;
      doc->Error(
          id, IndexPath(list_key, i) + ".id",
          (group ? "the members of group '" + id.Scalar() + "' (" + id.Scalar() + "_000, ...)"
                 : "id '" + id.Scalar() + "'") +
              " would take ids of the crowd's people (" + prefix + "001, ...): rename it");
    }
  }
  std::vector<std::string> ids;
  for (const auto& w : world.walls) ids.push_back(w.id);
  for (const auto& b : world.boxes) ids.push_back(b.id);
  for (const auto& c : world.cylinders) ids.push_back(c.id);
  for (const auto& m : world.meshes) ids.push_back(m.id);
  for (const auto& d : world.doors) ids.push_back(d.id);
  for (const std::string& id : ids) {
    if (id.starts_with(prefix)) {
      doc->Error(block, "crowd",
                 "world element '" + id + "' would take an id of the crowd's people (" + prefix +
                     "001, ...)");
    }
  }
}

}  // namespace

void ReadCrowd(YamlDocument* doc, MapReader& top, Scenario* scenario) {
  if (!top.Has("crowd")) {
    top.Child("crowd");  // known, absent: no crowd
    return;
  }
  MapReader r(doc, top.Child("crowd"), "crowd");  // `crowd: {}` for every default
  if (!r.valid()) return;
  const YAML::Node block = KeyNode(top.node(), "crowd");  // the `crowd:` line
  const sim::WorldDescription& world = scenario->world;
  sim::CrowdSpec spec;
  ReadVisitAndBehaviours(doc, r, &spec.options);
  ReadBodyAndSocialForce(doc, r, &spec.options);
  ReadCrowdFields(r, &spec.options);
  spec.entrance = ReadArea(doc, r, block, "entrance", kDefaultEntrance, world);
  spec.exit = ReadArea(doc, r, block, "exit", kDefaultExit, world);
  spec.roam_area = ReadArea(doc, r, block, "roam_area", "", world);
  spec.attractions = ReadAttractions(doc, r, world);
  const std::optional<std::string> material =
      r.Has("material") ? r.RequiredString("material") : kDefaultMaterial;
  if (material && !world.materials.contains(*material)) {
    doc->Error(
        At(r, "material", block), r.PathOf("material"),
        "unknown material '" + *material + "' (not in the world or the scenario's materials)");
  }
  spec.material = material.value_or(kDefaultMaterial);
  r.Finish();
  CheckIdsAreFree(doc, top, block, world, spec.id_prefix);
  scenario->crowd = std::move(spec);
}

}  // namespace pavilion::scenarios
