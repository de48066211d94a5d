#include "scenarios/config/mission_reader.h"

#include <algorithm>
#include <filesystem>
#include <optional>
#include <set>

#include "core/map/robot_map.h"
#include "nav/planning/graph_planner.h"
#include "scenarios/config/options_reader.h"
#include "scenarios/maps/closed_doors.h"
#include "scenarios/maps/map_file.h"

namespace pavilion::scenarios {
namespace {

// The map a mission's stations are checked against: the robot's map file, or
// none for a derived map (checked when the run derives it).
std::optional<core::RobotMap> MissionMap(YamlDocument* doc, const YAML::Node& at,
                                         const std::string& key, const Scenario& scenario,
                                         const RobotEntry& robot) {
  if (robot.localization.derive_map_noise_m) return std::nullopt;
  std::string file = robot.localization.map_file;
  if (file.empty()) {
    file = (std::filesystem::path(scenario.world_file).parent_path() / "map.yaml").string();
  }
  try {
    return LoadMapFile(file);
  } catch (const std::exception& e) {
    doc->Error(at, key, std::string("cannot read the robot's map: ") + e.what());
    return std::nullopt;
  }
}

std::set<std::string> StationIds(const core::RobotMap& map) {
  std::set<std::string> ids;
  for (const core::MapNode& n : map.nodes) {
    if (n.station) ids.insert(n.id);
  }
  return ids;
}

// Every goal must be reachable over the topology from the robot's start with
// the doors closed at the start (an error before the run, not a timeout).
void CheckReachable(YamlDocument* doc, MapReader& m, const std::string& key,
                    const std::vector<std::string>& goals, core::RobotMap map,
                    const Scenario& scenario, const RobotEntry& robot) {
  RemoveEdgesThroughClosedDoors(scenario.world.doors, &map);
  const nav::TopologyGraph graph(map);
  YAML::Node list = m.Child(key);
  for (std::size_t k = 0; k < goals.size(); ++k) {
    const std::optional<int> goal = graph.FindIndex(goals[k]);
    if (!goal) continue;  // reported as unknown
    if (!nav::PlanFromPosition(graph, map, robot.pose.translation(), *goal)) {
      doc->Error(list[k], IndexPath(m.PathOf(key), k),
                 "station '" + goals[k] + "' is unreachable for robot '" + robot.id +
                     "' from its start in map '" + map.name +
                     "' (no path over the topology; a closed door on the way?)");
    }
  }
}

// A list of station ids at `key`; each is checked against `stations` when known.
std::vector<std::string> ReadStationList(YamlDocument* doc, MapReader& m, const std::string& key,
                                         const std::optional<std::set<std::string>>& stations) {
  std::vector<std::string> ids;
  YAML::Node list = m.Child(key);
  if (!list.IsSequence() || list.size() == 0) {
    doc->Error(list, m.PathOf(key), "expected a non-empty list of station node ids");
    return ids;
  }
  for (std::size_t k = 0; k < list.size(); ++k) {
    const std::string id = list[k].as<std::string>("");
    if (stations && !stations->contains(id)) {
      doc->Error(list[k], IndexPath(m.PathOf(key), k),
                 "unknown station '" + id + "' (not a station node of the robot's map)");
    }
    ids.push_back(id);
  }
  return ids;
}

void ReadTour(YamlDocument* doc, MapReader& m, const std::optional<core::RobotMap>& map,
              const Scenario& scenario, const RobotEntry& robot, MissionEntry* mission) {
  MapReader t(doc, m.Child("tour"), m.PathOf("tour"));
  if (!t.valid()) return;
  std::optional<std::set<std::string>> stations;
  if (map) stations = StationIds(*map);
  if (t.Has("among")) {
    mission->tour_among = ReadStationList(doc, t, "among", stations);
    if (map) CheckReachable(doc, t, "among", mission->tour_among, *map, scenario, robot);
  } else if (stations) {
    mission->tour_among.assign(stations->begin(), stations->end());
  }
  const std::int64_t count = t.Integer("stations", 0, 1, 100000);
  if (!t.Has("stations")) doc->Error(t.node(), t.PathOf("stations"), "required key missing");
  const bool known = map || t.Has("among");
  if (known && count > static_cast<std::int64_t>(mission->tour_among.size())) {
    doc->Error(t.Child("stations"), t.PathOf("stations"),
               "a tour of " + std::to_string(count) + " stations is longer than the " +
                   std::to_string(mission->tour_among.size()) + " stations it draws from");
  }
  mission->tour_stations = static_cast<int>(count);
  mission->tour_repeat = t.Bool("repeat", false);
  t.Finish();
}

void ReadNavigationOptions(MapReader& m, nav::NavigationControllerOptions* o) {
  using Nav = nav::NavigationControllerOptions;
  ReadOptions(m, o,
              {{"dwell_s", &Nav::dwell_s},
               {"timeout_s", &Nav::timeout_s},
               {"start_s", &Nav::start_s},
               {"dwa_rate_hz", &Nav::dwa_rate_hz},
               {"band_rate_hz", &Nav::band_rate_hz},
               {"dwa_reach_m", &Nav::dwa_reach_m},
               {"band_lookahead_m", &Nav::band_lookahead_m},
               {"approach_radius_m", &Nav::approach_radius_m},
               {"blocked_node_cost_m", &Nav::blocked_node_cost_m},
               {"relocalization_timeout_s", &Nav::relocalization_timeout_s}});
  using Ghost = nav::GhostBarrier;
  ReadOptions(m, &o->ghost_barrier,
              {{"ghost_link_m", "link_m", &Ghost::link_m},
               {"ghost_fill_m", "fill_m", &Ghost::fill_m},
               {"ghost_clearance_m", "clearance_m", &Ghost::clearance_m}});
  using Uncertainty = nav::UncertaintyOptions;
  ReadOptions(m, &o->uncertainty,
              {{"uncertain_reach_m", "reach_m", &Uncertainty::reach_m},
               {"uncertain_slow_m", "slow_m", &Uncertainty::slow_m},
               {"uncertain_stop_m", "stop_m", &Uncertainty::stop_m},
               {"uncertain_hold_max_s", "hold_max_s", &Uncertainty::hold_max_s},
               {"uncertain_crawl_mps", "crawl_mps", &Uncertainty::crawl_mps}});
  using Dwa = nav::DynamicWindowOptions;
  ReadOptions(m, &o->dwa, {{"max_speed_mps", &Dwa::max_speed_mps}});
  using Grid = nav::LocalGridOptions;
  ReadOptions(m, &o->local.grid,
              {{"grid_size_m", "size_m", &Grid::size_m}, {"grid_cell_m", "cell_m", &Grid::cell_m}});
}

}  // namespace

void ReadMission(YamlDocument* doc, MapReader& r, const Scenario& scenario, RobotEntry* robot) {
  YAML::Node node = r.Child("mission");
  if (!node.IsDefined()) return;
  MapReader m(doc, node, r.PathOf("mission"));
  if (!m.valid()) return;
  MissionEntry mission;
  const std::optional<core::RobotMap> map = MissionMap(doc, node, m.path(), scenario, *robot);
  if (m.Has("stations") == m.Has("tour")) {
    doc->Error(node, m.path(), "give exactly one of stations (a list) and tour");
  } else if (m.Has("stations")) {
    std::optional<std::set<std::string>> stations;
    if (map) stations = StationIds(*map);
    mission.stations = ReadStationList(doc, m, "stations", stations);
    if (map) CheckReachable(doc, m, "stations", mission.stations, *map, scenario, *robot);
  } else {
    ReadTour(doc, m, map, scenario, *robot, &mission);
  }
  if (m.Has("rest_among")) {  // station nodes off the tour: the docks
    std::optional<std::set<std::string>> stations;
    if (map) stations = StationIds(*map);
    mission.navigation.rest_among = ReadStationList(doc, m, "rest_among", stations);
    if (map) {
      CheckReachable(doc, m, "rest_among", mission.navigation.rest_among, *map, scenario, *robot);
    }
  }
  const std::string planner =
      m.Choice("initial_planner", {"nf1", "ompl_rrt_connect", "ompl_rrt_star"}, "nf1");
  mission.navigation.initial_planner = planner == "nf1" ? nav::InitialPlanner::kNf1
                                       : planner == "ompl_rrt_connect"
                                           ? nav::InitialPlanner::kOmplRrtConnect
                                           : nav::InitialPlanner::kOmplRrtStar;
  ReadNavigationOptions(m, &mission.navigation);
  mission.navigation.hold_belief_at_goal = m.Bool("hold_belief_at_goal", true);
  m.Finish();
  robot->mission = std::move(mission);
}

}  // namespace pavilion::scenarios
