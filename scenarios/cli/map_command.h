#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <string>

namespace pavilion::cli {

// `pavilion map derive WORLD --out map.yaml` and `pavilion map render MAP --png FILE`:
// derive a robot map from a world's section, draw a map file (docs/map_format.md).
struct MapArgs {
  // derive
  std::string world;             // worlds/<name> name or path
  std::string out;               // map file to write
  double beam_height_m = 0.5;    // the robots' laser height (robots/*/robot.urdf)
  double noise_cm = 0.5;         // tape-measure error, one sigma (cm)
  std::int64_t seed = 1;         // seed of that noise
  double robot_radius_m = 0.35;  // clearance of edges
  double via_spacing_m = 3.0;    // grid pitch of via nodes
  bool vertical_edges = false;   // --vertical-edges: map the camera's vertical edges too
  // --keep-direction: keep only lines within keep_tolerance_deg of this direction
  // (deg, world frame), drop points and beacons (scenarios/maps/map_derivation.h).
  double keep_direction_deg = 0.0;
  double keep_tolerance_deg = 5.0;
  // render
  std::string map;           // map file
  std::string png;           // PNG to write
  std::string render_world;  // optional world drawn underneath
  int width_px = 1400;

  CLI::App* derive = nullptr;
  CLI::App* render = nullptr;
};

CLI::App* AddMapCommand(CLI::App* app, MapArgs* args);
// Throws scenarios::InputError for bad files; returns the exit code.
int RunMapCommand(const MapArgs& args);

}  // namespace pavilion::cli
