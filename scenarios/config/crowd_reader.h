#pragma once

// A scenario's `crowd:` block: visitors of sim/crowd/ who arrive at an entrance
// of the world, visit its stations and leave by its exit. Every key is
// optional; defaults and ranges are those of sim::crowd::CrowdOptions and its
// parts, whose Validate() errors are reported at their key
// (file:line: crowd.visit.dwell_mean_s: ...).
//
//   crowd:
//     pool: 120                  # bodies (default: max_present, at least present)
//     present: 60                # placed mid-visit at t = 0
//     max_present: 100
//     arrivals_per_hour: 400
//     entrance: visitor_spawn    # places with an area, or inline polygons
//     exit: visitor_exit         # [[x, y], ...], on the floor (these defaults)
//     roam_area: circulation     # optional, the same; default: the floor
//     attractions: [station_01]  # default: every station but the docks, attraction > 0
//     material: visitor          # of the world or the scenario's `materials:`
//     visit: {...}               # crowd::VisitOptions, by field name
//     behaviours: {...}          # crowd::BehaviourOptions
//     body: {...}                # crowd::PersonBodyOptions
//     social_force: {...}        # crowd::SocialForceOptions
//     route_cell_m: 0.2
//     route_clearance_m: 0.3
//     watch_spots: 12
//
// People are elements visitor_001, visitor_002, ...: with a crowd, no body,
// group member, robot or world element may have an id starting with
// "visitor_". README.md ("Crowd") lists every key with its unit and range.

#include "scenarios/config/scenario.h"
#include "scenarios/config/yaml_reader.h"

namespace pavilion::scenarios {

// Reads `crowd` of the scenario's top-level mapping into scenario->crowd (left
// empty when the key is absent). Needs the world with the scenario's materials
// merged; reports to `doc`.
void ReadCrowd(YamlDocument* doc, MapReader& top, Scenario* scenario);

}  // namespace pavilion::scenarios
