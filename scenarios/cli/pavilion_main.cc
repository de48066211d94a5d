// The `pavilion` command line: run scenarios, validate input files, inspect worlds.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "scenarios/cli/bench_command.h"
#include "scenarios/cli/calibrate_command.h"
#include "scenarios/cli/extract_command.h"
#include "scenarios/cli/map_command.h"
#include "scenarios/cli/realism_command.h"
#include "scenarios/cli/run_command.h"
#include "scenarios/cli/scan_command.h"
#include "scenarios/cli/snapshot_command.h"
#include "scenarios/cli/sweep_command.h"
#include "scenarios/cli/test_command.h"
#include "scenarios/config/data_paths.h"
#include "scenarios/config/input_error.h"
#include "scenarios/config/scenario.h"
#include "scenarios/config/validate.h"
#include "scenarios/config/world_loader.h"
#include "scenarios/output/png.h"
#include "scenarios/run/scenario_runner.h"
#include "scenarios/version.h"
#include "sim/render/top_down_view.h"
#include "sim/world/world.h"

namespace {

using namespace pavilion;

constexpr int kExitBadInput = 1;
constexpr int kExitBadUsage = 2;

bool ProgressWanted() { return ::isatty(STDERR_FILENO) == 1 && std::getenv("CI") == nullptr; }

int Fail(const std::string& message) {
  std::fprintf(stderr, "pavilion: error: %s\n", message.c_str());
  return kExitBadInput;
}

int Validate(const std::vector<std::string>& files) {
  int bad = 0;
  for (const std::string& file : files) {
    const auto diagnostics = scenarios::ValidateFile(file);
    for (const auto& d : diagnostics) std::fprintf(stderr, "%s\n", d.ToString().c_str());
    if (diagnostics.empty()) {
      std::printf("%s: ok\n", file.c_str());
    } else {
      ++bad;
    }
  }
  if (bad > 0) {
    std::fprintf(stderr, "pavilion: %d of %zu files have errors\n", bad, files.size());
    return kExitBadInput;
  }
  return 0;
}

struct WorldArgs {
  std::string world;
  std::string png;
  double z_m = 0.5;
  int width_px = 1200;
};

int WorldRender(const WorldArgs& a) {
  sim::World world(scenarios::LoadWorldFile(scenarios::ResolveWorldPath(a.world)), {});
  sim::TopDownOptions options;
  options.section_height_m = a.z_m;
  options.width_px = a.width_px;
  scenarios::WritePng(a.png, sim::RenderTopDown(world, {}, options));
  std::printf("%s\n", a.png.c_str());
  return 0;
}

int WorldInfo(const WorldArgs& a) {
  const std::string path = scenarios::ResolveWorldPath(a.world);
  sim::World world(scenarios::LoadWorldFile(path), {});
  const auto& d = world.description();
  const core::PlanarSection section = world.SectionAt(a.z_m);
  std::printf("world %s (%s)\n", d.name.c_str(), path.c_str());
  std::printf("  floor [%.2f, %.2f] x [%.2f, %.2f] m\n", d.floor.min_m.x(), d.floor.max_m.x(),
              d.floor.min_m.y(), d.floor.max_m.y());
  std::printf("  %zu walls, %zu boxes, %zu cylinders, %zu meshes, %zu doors, %zu places\n",
              d.walls.size(), d.boxes.size(), d.cylinders.size(), d.meshes.size(), d.doors.size(),
              d.places.size());
  std::size_t visible = 0;
  double visible_length = 0.0;
  for (const auto& s : section.segments) {
    if (section.elements[s.element].laser == core::LaserResponse::kTransparent) continue;
    ++visible;
    visible_length += (s.b_m - s.a_m).norm();
  }
  std::printf("  section at z = %.2f m: %zu segments (%zu laser-visible, %.1f m), %zu circles\n",
              a.z_m, section.segments.size(), visible, visible_length, section.circles.size());
  return 0;
}

CLI::App* AddValidateCommand(CLI::App* app, std::vector<std::string>* files) {
  auto* validate = app->add_subcommand(
      "validate", "Check world, robot, scenario and map files, print every error");
  validate->add_option("files", *files, "Files to check")->required();
  validate->footer(
      "Example:\n  pavilion validate worlds/*/world.yaml worlds/*/map.yaml robots/*/robot.yaml "
      "scenarios/*.yaml");
  return validate;
}

// `world render` and `world info`.
struct WorldCommands {
  CLI::App* render = nullptr;
  CLI::App* info = nullptr;
};

WorldCommands AddWorldCommands(CLI::App* app, WorldArgs* args) {
  auto* world = app->add_subcommand("world", "Inspect a world");
  world->require_subcommand(1);
  WorldCommands c;
  c.render = world->add_subcommand("render", "Draw a world from above into a PNG");
  c.render->add_option("world", args->world, "World name (under worlds/) or path")->required();
  c.render->add_option("--png", args->png, "PNG file to write")->required();
  c.render->add_option("--z", args->z_m, "Height of the outlined section (m)")
      ->capture_default_str();
  c.render->add_option("--width", args->width_px, "Image width (px)")
      ->check(CLI::Range(50, 8000))
      ->capture_default_str();
  c.render->footer("Example:\n  pavilion world render expo_hall --png hall.png --z 0.3");
  c.info = world->add_subcommand("info", "Summarize a world and its section at a height");
  c.info->add_option("world", args->world, "World name (under worlds/) or path")->required();
  c.info->add_option("--z", args->z_m, "Height of the section (m)")->capture_default_str();
  c.info->footer("Example:\n  pavilion world info office_floor --z 0.3");
  return c;
}

// The one-line message of an input error, pointing to `validate` for the rest.
int FailOnInput(const scenarios::InputError& e) {
  for (std::size_t i = 1; i < e.diagnostics().size(); ++i) {
    spdlog::debug("also: {}", e.diagnostics()[i].ToString());
  }
  std::string msg = e.what();
  if (e.diagnostics().size() > 1) {
    msg += " (and " + std::to_string(e.diagnostics().size() - 1) +
           " more; run 'pavilion validate' to list all)";
  }
  return Fail(msg);
}

// Every subcommand with its arguments.
struct Commands {
  cli::RunArgs run_args;
  CLI::App* run = nullptr;
  scenarios::TestSuiteOptions test_args;
  CLI::App* test = nullptr;
  std::vector<std::string> validate_files;
  CLI::App* validate = nullptr;
  CLI::App* version = nullptr;
  WorldArgs world_args;
  WorldCommands world;
  cli::ScanArgs scan_args;
  CLI::App* scan = nullptr;
  cli::ExtractArgs extract_args;
  CLI::App* extract = nullptr;
  cli::MapArgs map_args;
  CLI::App* map = nullptr;
  cli::CalibrateArgs calibrate_args;
  CLI::App* calibrate = nullptr;
  cli::BenchArgs bench_args;
  CLI::App* bench_hall = nullptr;
  cli::SweepArgs sweep_args;
  CLI::App* sweep = nullptr;
  cli::RealismArgs realism_args;
  CLI::App* realism_report = nullptr;
  cli::SnapshotArgs snapshot_args;
  CLI::App* snapshot = nullptr;
};

void AddCommands(CLI::App* app, Commands* c) {
  c->run = cli::AddRunCommand(app, &c->run_args);
  c->test = cli::AddTestCommand(app, &c->test_args);
  c->validate = AddValidateCommand(app, &c->validate_files);
  c->version = app->add_subcommand("version", "Print the version");
  c->version->footer("Example:\n  pavilion version");
  c->world = AddWorldCommands(app, &c->world_args);
  c->scan = cli::AddScanCommand(app, &c->scan_args);
  c->extract = cli::AddExtractCommand(app, &c->extract_args);
  // --- map: robot maps (scenarios/cli/map_command.cc) ---
  c->map = cli::AddMapCommand(app, &c->map_args);
  // --- end map ---
  // --- calibrate: odometry calibration (scenarios/cli/calibrate_command.cc) ---
  c->calibrate = cli::AddCalibrateCommand(app, &c->calibrate_args);
  // --- end calibrate ---
  // --- bench: the hall benchmark (scenarios/cli/bench_command.cc) ---
  c->bench_hall = cli::AddBenchCommand(app, &c->bench_args);
  // --- end bench ---
  // --- sweep: seeds x parameter grid (scenarios/cli/sweep_command.cc) ---
  c->sweep = cli::AddSweepCommand(app, &c->sweep_args);
  // --- end sweep ---
  // --- realism: the laser's errors against real logs (scenarios/cli/realism_command.cc) ---
  c->realism_report = cli::AddRealismCommand(app, &c->realism_args);
  // --- end realism ---
  // --- snapshot: camera and overview pictures (scenarios/cli/snapshot_command.cc) ---
  c->snapshot = cli::AddSnapshotCommand(app, &c->snapshot_args);
  // --- end snapshot ---
}

// Runs the parsed subcommand; its exit code.
int Dispatch(Commands& c) {
  if (*c.run) {
    c.run_args.progress = ProgressWanted();
    return cli::RunRunCommand(c.run_args);
  }
  if (*c.test) return cli::RunTestCommand(c.test_args);
  if (*c.validate) return Validate(c.validate_files);
  if (*c.version) {
    std::printf("pavilion %s\n", pavilion::kVersion);
    return 0;
  }
  if (*c.world.render) return WorldRender(c.world_args);
  if (*c.world.info) return WorldInfo(c.world_args);
  if (*c.scan) return cli::RunScanCommand(c.scan_args);
  if (*c.extract) return cli::RunExtractCommand(c.extract_args);
  if (*c.calibrate) return cli::RunCalibrateCommand(c.calibrate_args);  // calibrate
  if (*c.map) return cli::RunMapCommand(c.map_args);                    // map
  if (*c.bench_hall) {
    c.bench_args.progress = ProgressWanted();
    return cli::RunBenchCommand(c.bench_args);
  }
  if (*c.sweep) return cli::RunSweepCommand(c.sweep_args);  // sweep
  if (*c.realism_report) return cli::RunRealismCommand(c.realism_args);
  if (*c.snapshot) return cli::RunSnapshotCommand(c.snapshot_args);
  return kExitBadUsage;
}

}  // namespace

int main(int argc, char** argv) {
  auto logger = spdlog::stderr_color_mt("pavilion");
  spdlog::set_default_logger(logger);
  spdlog::set_pattern("[%l] %v");

  CLI::App app{"Pavilion: a physics-simulation testbed for fleets of mobile robots"};
  app.require_subcommand(1);
  app.fallthrough();  // --log-level may follow the subcommand too
  app.footer(
      "Examples:\n  pavilion run scenarios/expo_visitors.yaml --out out/demo\n"
      "  pavilion validate worlds/*/world.yaml scenarios/*.yaml\n"
      "  pavilion world render expo_hall --png hall.png\n"
      "  pavilion map derive expo_hall --out map.yaml\n"
      "  pavilion scan expo_hall robox --pose 15,3,1.57 --out scan.csv --png scan.png\n"
      "  pavilion bench hall --robots 10 --runs 3\n"
      "  pavilion sweep scenarios/office_tour.yaml --seeds 1-10 --jobs 2 --out out/sweep");
  std::string log_level = "info";
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error or off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}))
      ->capture_default_str();

  Commands commands;
  AddCommands(&app, &commands);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "pavilion: usage error: %s (see --help)\n", e.what());
    return kExitBadUsage;
  }
  spdlog::set_level(spdlog::level::from_str(log_level));

  try {
    return Dispatch(commands);
  } catch (const scenarios::InputError& e) {
    return FailOnInput(e);
  } catch (const std::exception& e) {
    return Fail(e.what());
  }
}
