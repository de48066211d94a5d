#include "scenarios/cli/map_command.h"

#include <spdlog/spdlog.h>

#include <cstdio>
#include <memory>
#include <numbers>
#include <vector>

#include "scenarios/config/data_paths.h"
#include "scenarios/config/world_loader.h"
#include "scenarios/maps/map_derivation.h"
#include "scenarios/maps/map_file.h"
#include "scenarios/maps/map_render.h"
#include "scenarios/output/png.h"

namespace pavilion::cli {
namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

}  // namespace

CLI::App* AddMapCommand(CLI::App* app, MapArgs* args) {
  auto* map = app->add_subcommand("map", "Derive and draw robot maps (docs/map_format.md)");
  map->require_subcommand(1);
  map->footer(
      "Examples:\n  pavilion map derive expo_hall --out worlds/expo_hall/map.yaml\n"
      "  pavilion map render worlds/expo_hall/map.yaml --png map.png --world expo_hall");

  auto* derive = map->add_subcommand(
      "derive", "Derive the a-priori robot map of a world from its section at the beam height");
  derive->add_option("world", args->world, "World name (under worlds/) or path")->required();
  derive->add_option("--out", args->out, "Map file to write (YAML)")->required();
  derive
      ->add_option("--beam-height", args->beam_height_m,
                   "Height of the laser scan plane (m); the robots' lasers are at 0.5 m")
      ->check(CLI::Range(0.01, 10.0))
      ->capture_default_str();
  derive
      ->add_option("--noise-cm", args->noise_cm,
                   "Tape-measure error of corners and centres, one sigma (cm); 0 = exact")
      ->check(CLI::Range(0.0, 10.0))
      ->capture_default_str();
  derive->add_option("--seed", args->seed, "Seed of the tape-measure noise")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  derive
      ->add_option("--robot-radius", args->robot_radius_m,
                   "Clearance every edge keeps from every obstacle (m)")
      ->check(CLI::Range(0.05, 2.0))
      ->capture_default_str();
  derive->add_option("--via-spacing", args->via_spacing_m, "Grid pitch of the via nodes (m)")
      ->check(CLI::Range(0.5, 20.0))
      ->capture_default_str();
  derive->add_flag("--vertical-edges", args->vertical_edges,
                   "Also map the vertical edges a camera sees (wall corners and ends, door frames, "
                   "corners of pillars and exhibits) as points edge_NNN");
  derive
      ->add_option("--keep-direction", args->keep_direction_deg,
                   "Keep only the lines along this direction (deg, world frame); drop points and "
                   "beacons")
      ->check(CLI::Range(-360.0, 360.0));
  derive
      ->add_option("--tolerance-deg", args->keep_tolerance_deg,
                   "Largest angle between a kept line and --keep-direction (deg)")
      ->check(CLI::Range(0.001, 90.0))
      ->capture_default_str();
  derive->footer(
      "Example:\n  pavilion map derive expo_hall --out worlds/expo_hall/map.yaml\n"
      "  pavilion map derive small_lab --out exact.yaml --noise-cm 0\n"
      "  pavilion map derive office_floor --out worlds/office_floor/map_corridor_parallel.yaml "
      "--keep-direction 0 --tolerance-deg 5");
  args->derive = derive;

  auto* render = map->add_subcommand("render", "Draw a robot map from above into a PNG");
  render->add_option("map", args->map, "Map file (YAML)")->required();
  render->add_option("--png", args->png, "PNG file to write")->required();
  render->add_option("--world", args->render_world,
                     "World (name or path) drawn underneath in grey");
  render->add_option("--width", args->width_px, "Image width (px)")
      ->check(CLI::Range(50, 8000))
      ->capture_default_str();
  render->footer(
      "Example:\n  pavilion map render worlds/expo_hall/map.yaml --png map.png --world expo_hall");
  args->render = render;
  return map;
}

int RunMapCommand(const MapArgs& args) {
  if (args.derive != nullptr && args.derive->parsed()) {
    sim::World world(scenarios::LoadWorldFile(scenarios::ResolveWorldPath(args.world)), {});
    scenarios::MapDerivationOptions options;
    options.beam_height_m = args.beam_height_m;
    options.noise_sigma_m = args.noise_cm / 100.0;
    options.seed = static_cast<std::uint64_t>(args.seed);
    options.robot_radius_m = args.robot_radius_m;
    options.via_spacing_m = args.via_spacing_m;
    options.vertical_edges = args.vertical_edges;
    std::vector<std::string> warnings;
    core::RobotMap map = scenarios::DeriveRobotMap(world, options, &warnings);
    if (args.derive->count("--keep-direction") > 0) {
      map = scenarios::KeepLinesAlongDirection(map, args.keep_direction_deg * kRadPerDeg,
                                               args.keep_tolerance_deg * kRadPerDeg);
    }
    for (const std::string& w : warnings) spdlog::warn("{}", w);
    scenarios::WriteMapFile(args.out, map);
    int stations = 0;
    for (const auto& n : map.nodes) stations += n.station;
    std::printf(
        "map %s: %zu segments, %zu multi-segment lines, %zu points, %zu beacons, "
        "%d station and %zu via nodes, %zu edges, %zu ghost points\n",
        map.name.c_str(), map.segments.size(), map.multi_segment_lines.size(), map.points.size(),
        map.beacons.size(), stations, map.nodes.size() - stations, map.edges.size(),
        map.ghost_points.size());
    std::printf("%s\n", args.out.c_str());
    return 0;
  }
  if (args.render != nullptr && args.render->parsed()) {
    const core::RobotMap map = scenarios::LoadMapFile(args.map);
    std::unique_ptr<sim::World> world;
    if (!args.render_world.empty()) {
      world = std::make_unique<sim::World>(
          scenarios::LoadWorldFile(scenarios::ResolveWorldPath(args.render_world)),
          sim::WorldOptions{});
    }
    scenarios::MapRenderOptions options;
    options.width_px = args.width_px;
    scenarios::WritePng(args.png, scenarios::RenderRobotMap(map, world.get(), options));
    std::printf("%s\n", args.png.c_str());
    return 0;
  }
  return 2;
}

}  // namespace pavilion::cli
