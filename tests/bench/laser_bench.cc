// Laser rays per second in expo_hall with 10 Robox robots (two LMS 200 each,
// 361 readings) among 100 pedestrian-sized cylinders, and physics steps per
// second of the same scene with the robots driving. The reference measured in
// the same run is Bullet's rayTest against the world's primitive shapes
// (WorldOptions::baked_static_rays = false).
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "core/random/random_stream.h"
#include "scenarios/data_paths.h"
#include "scenarios/robot_loader.h"
#include "scenarios/robot_setup.h"
#include "scenarios/world_loader.h"
#include "sim/body_motion.h"
#include "sim/sim_robot.h"
#include "sim/world.h"

namespace {

using namespace pavilion;

constexpr int kRobots = 10;
constexpr int kWalkers = 100;

// The hall with kRobots robots and kWalkers walkers on free cells of a grid.
struct HallScene {
  std::unique_ptr<sim::World> world;
  std::vector<std::unique_ptr<sim::SimRobot>> robots;
  std::vector<std::unique_ptr<sim::BodyMotion>> motions;

  explicit HallScene(bool baked) {
    sim::WorldDescription d = scenarios::LoadWorldFile(scenarios::ResolveWorldPath("expo_hall"));
    const sim::RobotConfig robox = scenarios::LoadRobotFile(scenarios::ResolveRobotPath("robox"));
    sim::World probe(d, sim::WorldOptions{});
    const core::PlanarSection section = probe.SectionAt(0.1);
    auto clear = [&](const Eigen::Vector2d& p, double r) {
      for (const auto& s : section.segments) {
        const Eigen::Vector2d ab = s.b_m - s.a_m;
        const double t = std::clamp((p - s.a_m).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
        if ((s.a_m + t * ab - p).norm() < r) return false;
      }
      for (const auto& c : section.circles) {
        if ((c.center_m - p).norm() < c.radius_m + r) return false;
      }
      return true;
    };
    std::vector<Eigen::Vector2d> cells;
    for (double y = d.floor.min_m.y() + 0.6; y < d.floor.max_m.y() - 0.6; y += 0.9) {
      for (double x = d.floor.min_m.x() + 0.6; x < d.floor.max_m.x() - 0.6; x += 0.9) {
        if (clear({x, y}, 0.5)) cells.emplace_back(x, y);
      }
    }
    // Robots spread evenly over the free cells, walkers on the cells between.
    std::vector<sim::SimRobotSetup> setups;
    std::vector<bool> used(cells.size(), false);
    const std::size_t stride = cells.size() / kRobots;
    for (int k = 0; k < kRobots; ++k) {
      const std::size_t c = k * stride + stride / 2;
      used[c] = true;
      if (c > 0) used[c - 1] = true;
      if (c + 1 < cells.size()) used[c + 1] = true;
      setups.push_back(scenarios::MakeSimRobotSetup("robox_" + std::to_string(k), robox,
                                                    {cells[c].x(), cells[c].y(), 0.3 * k}, &d));
    }
    sim::WorldOptions options;
    options.baked_static_rays = baked;
    world = std::make_unique<sim::World>(d, options);
    for (auto& setup : setups) {
      robots.push_back(std::make_unique<sim::SimRobot>(world.get(), setup, 1));
    }
    int placed = 0;
    for (std::size_t c = 0; c < cells.size() && placed < kWalkers; c += 2) {
      if (used[c]) continue;
      sim::BodySpec s;
      s.id = "visitor_" + std::to_string(placed);
      s.shape.radius_m = 0.22;
      s.shape.height_m = 1.7;
      s.mass_kg = 70.0;
      s.pose = {cells[c].x(), cells[c].y(), 0.0};
      s.material = d.floor.material;
      s.driven = true;
      world->AddBody(s);
      motions.push_back(std::make_unique<sim::RandomWalkMotion>(
          sim::RandomWalkOptions{}, core::RandomStream(1, static_cast<std::uint64_t>(placed))));
      ++placed;
    }
    for (int i = 0; i < 100; ++i) Step();  // settle
  }

  void Step() {
    const double t = world->time_s();
    for (int b = 0; b < world->body_count(); ++b) {
      const sim::PlanarVelocity v = motions[b]->Update(t, world->body_state(b));
      world->SetPlanarVelocity(b, v.linear_mps, v.yaw_rate_radps);
    }
    world->Step();
  }

  // Every robot's every scanner takes one whole scan; returns the readings.
  std::int64_t ScanAll() {
    std::int64_t readings = 0;
    for (auto& robot : robots) {
      const core::Pose2 pose = world->robot_state(robot->index()).pose;
      for (const sim::LaserScanner& laser : robot->lasers()) {
        sim::LaserScanner copy = laser;
        const core::LaserScan scan = copy.ScanFrom(*world, pose, world->time_s(),
                                                   world->robot_group(robot->index()), nullptr);
        readings += static_cast<std::int64_t>(scan.readings.size());
      }
    }
    return readings;
  }

  // The bare geometric rays of those scans through World::CastRay.
  std::int64_t CastAll() {
    std::int64_t rays = 0;
    for (auto& robot : robots) {
      const core::Pose2 pose = world->robot_state(robot->index()).pose;
      for (const sim::LaserMountSetup& mount : robot->setup().lasers) {
        const core::Pose2 sensor = pose * mount.robot_from_sensor;
        const auto& o = mount.options;
        for (int i = 0; i < o.beams; ++i) {
          const double a = sensor.theta_rad + o.first_bearing_rad + i * o.fov_rad / (o.beams - 1);
          const Eigen::Vector3d from(sensor.x_m, sensor.y_m, mount.mount_height_m);
          const Eigen::Vector3d to =
              from + o.max_range_m * Eigen::Vector3d(std::cos(a), std::sin(a), 0);
          benchmark::DoNotOptimize(world->CastRay(from, to, world->robot_group(robot->index())));
          ++rays;
        }
      }
    }
    return rays;
  }
};

void Report(benchmark::State& state, std::int64_t rays) {
  state.SetItemsProcessed(rays);
  state.counters["rays_per_s"] =
      benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsRate);
}

// Full scans with every error model on (noise, mixed pixels, surfaces): rays
// per second counts every ray cast (mixed-pixel edge rays included), readings
// per second the scans' readings.
void BM_HallScans(benchmark::State& state) {
  HallScene scene(state.range(0) != 0);
  std::int64_t readings = 0;
  const std::int64_t rays_before = scene.world->rays_cast();
  for (auto _ : state) readings += scene.ScanAll();
  Report(state, scene.world->rays_cast() - rays_before);
  state.counters["readings_per_s"] =
      benchmark::Counter(static_cast<double>(readings), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_HallScans)
    ->ArgName("baked")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(3.0);

// The same rays, geometry only (World::CastRay).
void BM_HallRays(benchmark::State& state) {
  HallScene scene(state.range(0) != 0);
  std::int64_t rays = 0;
  for (auto _ : state) rays += scene.CastAll();
  Report(state, rays);
}
BENCHMARK(BM_HallRays)
    ->ArgName("baked")
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(3.0);

// Physics: the 10 robots driving arcs among the 100 walkers, 200 Hz.
void BM_HallPhysics10Robots100Walkers(benchmark::State& state) {
  HallScene scene(true);
  for (std::size_t k = 0; k < scene.robots.size(); ++k) {
    scene.robots[k]->SetWheelSpeeds(3.0 + 0.2 * static_cast<double>(k), 3.5);
  }
  for (auto _ : state) scene.Step();
  state.SetItemsProcessed(state.iterations());
  state.counters["rtf_200Hz"] = benchmark::Counter(static_cast<double>(state.iterations()) / 200.0,
                                                   benchmark::Counter::kIsRate);
}
BENCHMARK(BM_HallPhysics10Robots100Walkers)->Unit(benchmark::kMicrosecond)->MinTime(3.0);

}  // namespace

BENCHMARK_MAIN();
