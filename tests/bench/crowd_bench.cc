// The crowd alone in the Expo.02 hall: 100 visitors present, social forces
// at 20 Hz, contacts and integration at the 200 Hz physics rate, arrivals and
// departures at 400 an hour, and the legs cut for a laser at 0.5 m every
// step (what the planar caster asks of the world). Reports the real-time
// factor: the goal is >= 200x on one core.
#include <benchmark/benchmark.h>

#include <memory>

#include "core/geometry/polygon.h"
#include "scenarios/config/world_loader.h"
#include "sim/world/world.h"

namespace pavilion {
namespace {

constexpr double kPhysicsRateHz = 200.0;
constexpr double kLaserHeightM = 0.5;

std::unique_ptr<sim::World> ExpoHallWithCrowd(int present) {
  sim::WorldDescription d =
      scenarios::LoadWorldFile(PAVILION_SOURCE_DIR "/worlds/expo_hall/world.yaml");
  d.materials["visitor"] = sim::Material{};
  auto world = std::make_unique<sim::World>(d, sim::WorldOptions{});
  sim::CrowdSpec spec;
  spec.options.pool_size = present + 20;
  spec.options.max_present = present + 10;
  spec.options.initial_present = present;
  spec.options.arrivals_per_hour = 400;
  spec.material = "visitor";
  spec.entrance = *d.places.at("visitor_spawn").area;
  spec.exit = *d.places.at("visitor_exit").area;
  for (const auto& [name, place] : d.places) {
    if (name.rfind("station_", 0) == 0 && place.pose) {
      spec.attractions.push_back({name, *place.pose, place.attraction});
    }
  }
  world->AddCrowd(spec, 1);
  return world;
}

// One iteration: one simulated second of the crowd (200 steps), the legs cut
// at the laser's height after each.
void BM_CrowdAloneExpoHall(benchmark::State& state) {
  const int present = static_cast<int>(state.range(0));
  std::unique_ptr<sim::World> world = ExpoHallWithCrowd(present);
  sim::crowd::Crowd& crowd = *world->mutable_crowd();
  const double dt = 1.0 / kPhysicsRateHz;
  core::PlanarSection section;
  std::vector<sim::UncutElement> uncut;
  const std::vector<sim::crowd::CrowdRobot> robots;
  for (int i = 0; i < 60 * 200; ++i) crowd.Step(dt, robots, nullptr);  // a minute of warm-up
  double present_sum = 0.0;
  for (auto _ : state) {
    for (int i = 0; i < 200; ++i) {
      crowd.Step(dt, robots, nullptr);
      section.segments.clear();
      section.circles.clear();
      world->AppendDynamicSection(kLaserHeightM, 0.0, &section, &uncut);
    }
    present_sum += crowd.present();
    benchmark::DoNotOptimize(section.circles.data());
  }
  state.counters["real_time_factor"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["present"] = present_sum / static_cast<double>(state.iterations());
}
BENCHMARK(BM_CrowdAloneExpoHall)->Arg(100)->Arg(200)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace pavilion

BENCHMARK_MAIN();
