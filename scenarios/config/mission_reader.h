#pragma once

// A robot's `mission:` block (issue 14): the goals of the chapter 6 navigation
// and its options.
//
//   mission:
//     stations: [station_03, station_07]      # these goals in order, or
//     tour: {stations: 15, repeat: true, among: [station_01, ...]}
//     dwell_s: 10            # wait at each goal, s
//     timeout_s: 300         # abort a mission not completed by then, s
//     start_s: 0
//     rest_among: [dock_01, ...]  # where to make way when no station is free
//     initial_planner: nf1 | ompl_rrt_connect | ompl_rrt_star
//     dwa_rate_hz: 10, band_rate_hz: 5, ...  (docs/scenario_format.md)
//
// A tour draws `stations` of the candidates (`among`, default every station
// node of the robot's map) from the scenario's seed, each once per round, in a
// new order each round when `repeat`. Station names are checked against the
// robot's map file (file:line:key errors); a derived map is checked at run start.

#include <string>

#include "scenarios/config/scenario.h"
#include "scenarios/config/yaml_reader.h"

namespace pavilion::scenarios {

void ReadMission(YamlDocument* doc, MapReader& robot_reader, const Scenario& scenario,
                 RobotEntry* robot);

}  // namespace pavilion::scenarios
