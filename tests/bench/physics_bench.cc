// Physics steps per second in expo_hall with 100 walking visitor-sized bodies,
// against a baseline measured in the same run: the same bodies on a bare floor.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "core/random/random_stream.h"
#include "scenarios/data_paths.h"
#include "scenarios/world_loader.h"
#include "sim/body_motion.h"
#include "sim/world.h"

namespace {

using namespace pavilion;

constexpr int kBodies = 100;
constexpr int kSettleSteps = 200;

sim::WorldDescription BareFloor(const sim::WorldDescription& like) {
  sim::WorldDescription d;
  d.name = "bare_floor";
  d.materials = like.materials;
  d.floor = like.floor;
  return d;
}

// Places kBodies walking cylinders on a grid of free floor cells of the world.
struct Crowd {
  std::unique_ptr<sim::World> world;
  std::vector<std::unique_ptr<sim::BodyMotion>> motions;

  Crowd(const sim::WorldDescription& d, const sim::WorldDescription& placement_world) {
    world = std::make_unique<sim::World>(d, sim::WorldOptions{});
    sim::World probe(placement_world, sim::WorldOptions{});
    const core::PlanarSection section = probe.SectionAt(0.1);
    auto clear = [&](const Eigen::Vector2d& p) {
      for (const auto& s : section.segments) {
        const Eigen::Vector2d ab = s.b_m - s.a_m;
        const double t = std::clamp((p - s.a_m).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
        if ((s.a_m + t * ab - p).norm() < 0.45) return false;
      }
      for (const auto& c : section.circles) {
        if ((c.center_m - p).norm() < c.radius_m + 0.45) return false;
      }
      return true;
    };
    const std::string material = d.floor.material;
    int placed = 0;
    for (double y = d.floor.min_m.y() + 1.0; y < d.floor.max_m.y() - 1.0 && placed < kBodies;
         y += 0.9) {
      for (double x = d.floor.min_m.x() + 1.0; x < d.floor.max_m.x() - 1.0 && placed < kBodies;
           x += 0.9) {
        if (!clear({x, y})) continue;
        sim::BodySpec s;
        s.id = "visitor_" + std::to_string(placed);
        s.shape.type = sim::BodyShapeType::kCylinder;
        s.shape.radius_m = 0.25;
        s.shape.height_m = 1.7;
        s.mass_kg = 70.0;
        s.pose = {x, y, 0.0};
        s.material = material;
        s.driven = true;
        world->AddBody(s);
        motions.push_back(std::make_unique<sim::RandomWalkMotion>(
            sim::RandomWalkOptions{}, core::RandomStream(1, static_cast<std::uint64_t>(placed))));
        ++placed;
      }
    }
  }

  void Step() {
    const double t = world->time_s();
    for (int b = 0; b < world->body_count(); ++b) {
      const sim::PlanarVelocity v = motions[b]->Update(t, world->body_state(b));
      world->SetPlanarVelocity(b, v.linear_mps, v.yaw_rate_radps);
    }
    world->Step();
  }
};

const sim::WorldDescription& ExpoHall() {
  static const sim::WorldDescription d =
      scenarios::LoadWorldFile(scenarios::ResolveWorldPath("expo_hall"));
  return d;
}

void RunSteps(benchmark::State& state, Crowd& crowd) {
  for (int i = 0; i < kSettleSteps; ++i) crowd.Step();
  for (auto _ : state) crowd.Step();
  state.SetItemsProcessed(state.iterations());
  state.counters["bodies"] = crowd.world->body_count();
  state.counters["rtf_200Hz"] = benchmark::Counter(static_cast<double>(state.iterations()) / 200.0,
                                                   benchmark::Counter::kIsRate);
}

// Baseline: the same 100 walkers on the hall's floor without its walls and exhibits.
void BM_BareFloor100Walkers(benchmark::State& state) {
  Crowd crowd(BareFloor(ExpoHall()), ExpoHall());
  RunSteps(state, crowd);
}
BENCHMARK(BM_BareFloor100Walkers)->Unit(benchmark::kMicrosecond)->MinTime(3.0);

// expo_hall: static geometry plus 100 walkers.
void BM_ExpoHall100Walkers(benchmark::State& state) {
  Crowd crowd(ExpoHall(), ExpoHall());
  RunSteps(state, crowd);
}
BENCHMARK(BM_ExpoHall100Walkers)->Unit(benchmark::kMicrosecond)->MinTime(3.0);

}  // namespace

BENCHMARK_MAIN();
