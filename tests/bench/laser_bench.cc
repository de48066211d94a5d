// Laser rays per second in expo_hall with 10 Robox robots (two LMS 200 each,
// 361 readings) among 100 pedestrian-sized cylinders, and physics steps per
// second of the same scene with the robots driving. The reference measured in
// the same run is Bullet's rayTest against the world's primitive shapes
// (WorldOptions::baked_static_rays = false). The planar caster
// (sim/raycast/planar_caster.h) is measured on the same hall with 100 legs
// (r 0.06 m) against World::CastRay in the same run (issue 7: ≥ 3 M rays/s).
#include <benchmark/benchmark.h>
#include <time.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "core/random/random_stream.h"
#include "scenarios/config/data_paths.h"
#include "scenarios/config/robot_loader.h"
#include "scenarios/config/robot_setup.h"
#include "scenarios/config/world_loader.h"
#include "sim/bodies/body_motion.h"
#include "sim/raycast/planar_caster.h"
#include "sim/robot/sim_robot.h"
#include "sim/world/world.h"

namespace {

using namespace pavilion;

constexpr int kRobots = 10;
constexpr int kWalkers = 100;
constexpr double kPedestrianRadiusM = 0.22;
constexpr double kLegRadiusM = 0.06;

// The hall with kRobots robots and kWalkers walkers on free cells of a grid.
struct HallScene {
  std::unique_ptr<sim::World> world;
  std::vector<std::unique_ptr<sim::SimRobot>> robots;
  std::int64_t scan_rays = 0;  // rays of ScanAll(finder) so far (central and edge rays)
  std::vector<std::unique_ptr<sim::BodyMotion>> motions;

  // `systematic`: every laser with the realistic profile's systematic and
  // correlated errors (issue 20) set.
  explicit HallScene(bool baked, double walker_radius_m = kPedestrianRadiusM,
                     const sim::LaserSystematicErrors* systematic = nullptr) {
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
    std::vector<sim::RobotConfig> configs;
    std::vector<sim::RobotPlacement> placements;
    std::vector<bool> used(cells.size(), false);
    const std::size_t stride = cells.size() / kRobots;
    for (int k = 0; k < kRobots; ++k) {
      const std::size_t c = k * stride + stride / 2;
      used[c] = true;
      if (c > 0) used[c - 1] = true;
      if (c + 1 < cells.size()) used[c + 1] = true;
      configs.push_back(scenarios::WithWorldMaterials(robox, &d));
      if (systematic != nullptr) {
        for (sim::LaserMount& m : configs.back().lasers) m.options.systematic = *systematic;
      }
      placements.push_back({"robox_" + std::to_string(k), {cells[c].x(), cells[c].y(), 0.3 * k}});
    }
    sim::WorldOptions options;
    options.baked_static_rays = baked;
    world = std::make_unique<sim::World>(d, options);
    for (std::size_t k = 0; k < configs.size(); ++k) {
      robots.push_back(std::make_unique<sim::SimRobot>(world.get(), configs[k], placements[k], 1));
    }
    int placed = 0;
    for (std::size_t c = 0; c < cells.size() && placed < kWalkers; c += 2) {
      if (used[c]) continue;
      sim::BodySpec s;
      s.id = "visitor_" + std::to_string(placed);
      s.shape.radius_m = walker_radius_m;
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

  // The bare geometric rays of those scans through a hit finder.
  std::int64_t CastAll(const sim::LaserHitFinder& finder) {
    std::int64_t rays = 0;
    for (auto& robot : robots) {
      const core::Pose2 pose = world->robot_state(robot->index()).pose;
      const int group = world->robot_group(robot->index());
      for (const sim::LaserMount& mount : robot->config().lasers) {
        const core::Pose2 sensor = pose * mount.robot_from_sensor;
        const auto& o = mount.options;
        const Eigen::Vector3d from(sensor.x_m, sensor.y_m, mount.z_m);
        for (int i = 0; i < o.beams; ++i) {
          const double a = sensor.theta_rad + o.first_bearing_rad + i * o.fov_rad / (o.beams - 1);
          benchmark::DoNotOptimize(
              finder.Cast(from, {std::cos(a), std::sin(a)}, o.max_range_m, group));
          ++rays;
        }
      }
    }
    return rays;
  }

  // Whole scans (every error model) through a hit finder.
  std::int64_t ScanAll(const sim::LaserHitFinder& finder) {
    std::int64_t readings = 0;
    for (auto& robot : robots) {
      const core::Pose2 pose = world->robot_state(robot->index()).pose;
      for (const sim::LaserScanner& laser : robot->lasers()) {
        sim::LaserScanner copy = laser;
        const std::int64_t rays_before = copy.rays_cast();
        const core::LaserScan scan = copy.ScanFrom(finder, pose, world->time_s(),
                                                   world->robot_group(robot->index()), nullptr);
        readings += static_cast<std::int64_t>(scan.readings.size());
        scan_rays += copy.rays_cast() - rays_before;
      }
    }
    return readings;
  }

  // The bare geometric rays of those scans through World::CastRay.
  std::int64_t CastAll() {
    std::int64_t rays = 0;
    for (auto& robot : robots) {
      const core::Pose2 pose = world->robot_state(robot->index()).pose;
      for (const sim::LaserMount& mount : robot->config().lasers) {
        const core::Pose2 sensor = pose * mount.robot_from_sensor;
        const auto& o = mount.options;
        for (int i = 0; i < o.beams; ++i) {
          const double a = sensor.theta_rad + o.first_bearing_rad + i * o.fov_rad / (o.beams - 1);
          const Eigen::Vector3d from(sensor.x_m, sensor.y_m, mount.z_m);
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

// Bullet's (World::CastRay's) rays per second on `scene`, timed over a few
// passes: the baseline of the planar benchmarks, measured in the same run.
// Thread CPU time, as Google Benchmark's rates (the machine may be shared).
double ThreadCpuS() {
  timespec t;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double BulletRaysPerS(HallScene& scene) {
  const sim::WorldHitFinder bullet(*scene.world);
  std::int64_t rays = 0;
  const double start = ThreadCpuS();
  double s = 0.0;
  while (s < 2.0) {
    rays += scene.CastAll(bullet);
    s = ThreadCpuS() - start;
  }
  return static_cast<double>(rays) / s;
}

// Planar casting (sim/raycast/planar_caster.h) of the 20 scanners' 361-beam scans in
// the hall with 10 robots and 100 legs, geometry only; `bullet_rays_per_s`
// and `ratio_to_bullet` compare with World::CastRay on the same scene and rays.
// Arg: the grid's cell size in cm.
void BM_HallPlanarRays(benchmark::State& state) {
  HallScene scene(true, kLegRadiusM);
  sim::PlanarCasterOptions options;
  options.cell_size_m = 0.01 * static_cast<double>(state.range(0));
  sim::PlanarCaster caster(scene.world.get(), options);
  const sim::PlanarSlice& slice = caster.SliceAt(scene.robots.front()->config().lasers.front().z_m);
  std::int64_t rays = 0;
  for (auto _ : state) rays += scene.CastAll(slice);
  Report(state, rays);
  const double bullet = BulletRaysPerS(scene);
  state.counters["bullet_rays_per_s"] = bullet;
  state.counters["ratio_to_bullet"] =
      benchmark::Counter(static_cast<double>(rays) / bullet, benchmark::Counter::kIsRate);
}
BENCHMARK(BM_HallPlanarRays)
    ->ArgName("cell_cm")
    ->Arg(25)
    ->Arg(50)
    ->Arg(100)
    ->Arg(200)
    ->Unit(benchmark::kMillisecond)
    ->MinTime(3.0);

// The same scene's whole scans with every error model, planar hits; the
// per-tick refresh of the legs' and robots' cross-sections included (one
// step and one refresh per iteration, as in a run at 10 Hz scans with 20 ticks).
// Arg 1: with `realism: realistic`'s laser errors (surface biases, correlated
// noise, intensity bias, mount error, stamp jitter).
void BM_HallPlanarScans(benchmark::State& state) {
  sim::LaserSystematicErrors realistic;
  realistic.mount_error = core::Pose2{0.003, -0.002, 0.002};
  realistic.surface_bias_sigma_m = 0.004;
  realistic.surface_seed = 3;
  realistic.correlated_sigma_m = 0.004;
  realistic.correlation_readings = 4.0;
  realistic.intensity_bias_m = 0.01;
  realistic.stamp_jitter_s = 0.0005;
  realistic.seed = 5;
  HallScene scene(true, kLegRadiusM, state.range(0) == 1 ? &realistic : nullptr);
  sim::PlanarCaster caster(scene.world.get(), sim::PlanarCasterOptions{});
  const double height = scene.robots.front()->config().lasers.front().z_m;
  std::int64_t readings = 0;
  for (auto _ : state) {
    state.PauseTiming();
    scene.Step();
    state.ResumeTiming();
    caster.Update();
    readings += scene.ScanAll(caster.SliceAt(height));
  }
  Report(state, scene.scan_rays);
  state.counters["readings_per_s"] =
      benchmark::Counter(static_cast<double>(readings), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_HallPlanarScans)
    ->ArgName("realistic")
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
