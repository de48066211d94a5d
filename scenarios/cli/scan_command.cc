#include "scenarios/cli/scan_command.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "scenarios/config/data_paths.h"
#include "scenarios/config/input_error.h"
#include "scenarios/config/robot_loader.h"
#include "scenarios/config/robot_setup.h"
#include "scenarios/config/world_loader.h"
#include "scenarios/output/output_files.h"
#include "scenarios/output/png.h"
#include "sim/render/top_down_view.h"
#include "sim/robot/sim_robot.h"

namespace pavilion::cli {
namespace {

core::Pose2 ParsePose(const std::string& text) {
  std::stringstream in(text);
  double v[3];
  char comma = 0;
  if (!(in >> v[0] >> comma >> v[1] >> comma >> v[2]) || !in.eof() || !std::isfinite(v[0]) ||
      !std::isfinite(v[1]) || !std::isfinite(v[2])) {
    throw scenarios::InputError(scenarios::Diagnostic{
        "--pose", 0, "", "expected x,y,theta (m, m, rad), got '" + text + "'"});
  }
  return {v[0], v[1], v[2]};
}

std::string Num(double v, int decimals) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v == 0.0 ? 0.0 : v);
  return buf;
}

}  // namespace

CLI::App* AddScanCommand(CLI::App* app, ScanArgs* args) {
  auto* scan = app->add_subcommand("scan", "Cast one scan of each of a robot's lasers in a world");
  scan->add_option("world", args->world, "World name (under worlds/) or path")->required();
  scan->add_option("robot", args->robot, "Robot name (under robots/) or path")->required();
  scan->add_option("--pose", args->pose, "Robot pose x,y,theta (m, m, rad)")->required();
  scan->add_option("--out", args->out, "CSV file to write")->required();
  scan->add_option("--png", args->png, "Top-down picture of the scan");
  scan->add_option("--seed", args->seed, "Seed of the sensors' noise")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  scan->add_flag("!--no-noise", args->noise, "Geometric ranges: noise and surface effects off");
  scan->footer(
      "Columns: sensor,index,bearing_rad,time_offset_s,range_m,valid,reflector,true_range_m,\n"
      "element,hit_x_m,hit_y_m (hit point in the world from the true sensor pose).\n"
      "Example:\n  pavilion scan expo_hall robox --pose 15,3,1.57 --out scan.csv --png scan.png");
  return scan;
}

int RunScanCommand(const ScanArgs& args) {
  const core::Pose2 pose = ParsePose(args.pose);
  sim::WorldDescription description =
      scenarios::LoadWorldFile(scenarios::ResolveWorldPath(args.world));
  sim::RobotConfig config = scenarios::LoadRobotFile(scenarios::ResolveRobotPath(args.robot));
  if (!args.noise) {
    for (sim::LaserMount& laser : config.lasers) {
      laser.options.noise = false;
      laser.options.effects = false;
    }
  }
  sim::RobotConfig robot_config = scenarios::WithWorldMaterials(config, &description);
  sim::World world(std::move(description), sim::WorldOptions{});
  sim::SimRobot robot(&world, std::move(robot_config), sim::RobotPlacement{"robot", pose},
                      static_cast<std::uint64_t>(args.seed));

  scenarios::LineWriter csv(args.out);
  csv.Append(
      "sensor,index,bearing_rad,time_offset_s,range_m,valid,reflector,true_range_m,element,"
      "hit_x_m,hit_y_m");
  std::vector<sim::TopDownTrack> overlay;
  const int group = world.robot_group(robot.index());
  for (const sim::LaserScanner& laser : robot.lasers()) {
    sim::LaserScanner scanner = laser;
    core::LaserScanTruth truth;
    const core::LaserScan scan = scanner.ScanFrom(world, pose, 0.0, group, &truth);
    int valid = 0, reflectors = 0;
    std::vector<Eigen::Vector2d> outline;
    for (std::size_t i = 0; i < scan.readings.size(); ++i) {
      const core::LaserReading& r = scan.readings[i];
      const core::Pose2& sensor = truth.world_from_sensor[i];
      const double a = sensor.theta_rad + r.bearing_rad;
      const Eigen::Vector2d hit =
          sensor.translation() + r.range_m * Eigen::Vector2d(std::cos(a), std::sin(a));
      const int element = truth.element[i];
      csv.Append(scan.sensor_id + "," + std::to_string(i) + "," + Num(r.bearing_rad, 6) + "," +
                 Num(r.time_offset_s, 6) + "," + Num(r.range_m, 4) + "," + (r.valid ? "1" : "0") +
                 "," + (r.reflector ? "1" : "0") + "," + Num(truth.true_range_m[i], 4) + "," +
                 (element >= 0 ? world.elements()[element].id : "") + "," + Num(hit.x(), 4) + "," +
                 Num(hit.y(), 4));
      valid += r.valid;
      reflectors += r.reflector;
      // The scan outline, broken at invalid readings and depth jumps.
      if (r.valid && !outline.empty() && (outline.back() - hit).norm() > 0.3) {
        overlay.push_back({outline, {220, 30, 30}, 1.0, 2.5});
        outline.clear();
      }
      if (r.valid) {
        outline.push_back(hit);
        if (r.reflector) {
          overlay.push_back({{sensor.translation(), hit}, {240, 200, 0}, 0.6, 1.0});
        }
      } else if (!outline.empty()) {
        overlay.push_back({outline, {220, 30, 30}, 1.0, 2.5});
        outline.clear();
      }
    }
    if (!outline.empty()) overlay.push_back({outline, {220, 30, 30}, 1.0, 2.5});
    std::printf("%s: %zu readings, %d valid, %d on reflectors\n", scan.sensor_id.c_str(),
                scan.readings.size(), valid, reflectors);
  }
  csv.Flush();
  std::printf("%s\n", args.out.c_str());
  if (!args.png.empty()) {
    sim::TopDownOptions view;
    view.section_height_m = config.lasers.empty() ? 0.5 : config.lasers.front().z_m;
    view.width_px = 1400;
    scenarios::WritePng(args.png, sim::RenderTopDown(world, overlay, view));
    std::printf("%s\n", args.png.c_str());
  }
  return 0;
}

}  // namespace pavilion::cli
