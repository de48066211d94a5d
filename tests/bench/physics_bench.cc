// Physics steps per second in expo_hall with 100 walking visitor-sized bodies,
// against a baseline measured in the same run: the same bodies on a bare floor.
// And N robots driving in a hall (the hall benchmark's walls, exhibits and
// robot), with the articulated reference and the fast ray-cast wheel model
// (the baseline of the same run), at 200 and 100 Hz physics.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/random/random_stream.h"
#include "scenarios/config/data_paths.h"
#include "scenarios/config/world_loader.h"
#include "sim/bodies/body_motion.h"
#include "sim/world/world.h"
#include "tests/support/world_robot.h"

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

// The hall of ../shared/bench/hall_bench.md: 20 m × 16 m inside four walls 0.2 m
// thick and 0.5 m tall, 15 exhibits of 1 m × 1 m × 0.5 m (hall_layout.json).
constexpr double kHallHalfX = 10.0;
constexpr double kHallHalfY = 8.0;
constexpr double kExhibitCentres[15][2] = {
    {-7.78, -5.76}, {-8.36, -0.44}, {-7.62, 5.28}, {-3.37, -5.66}, {-4.12, -0.75},
    {-4.45, 5.01},  {-0.76, -5.48}, {0.24, 0.07},  {-0.45, 5.14},  {4.5, -5.79},
    {4.49, 0.32},   {3.74, 4.45},   {8.73, -5.26}, {7.35, -0.65},  {8.56, 5.17}};
// Robots start on a grid of this pitch, clear of walls and exhibits by this much (m).
constexpr double kGridPitchM = 0.5;
constexpr double kClearanceM = 0.25;
// Each robot cruises at 0.4 m/s with a turn rate in ±0.5 rad/s drawn every
// second from its own stream; when its chassis starts touching anything it
// backs off turning at 0.5 rad/s for 1–1.9 s (the hall controller's speeds
// and manoeuvre lengths, with contacts instead of its laser).
constexpr double kCruiseMps = 0.4;
constexpr double kMaxTurnRadps = 0.5;
constexpr double kCommandPeriodS = 1.0;
constexpr double kBackOffMps = -0.05;
constexpr double kAvoidTurnRadps = 0.5;
constexpr double kMinAvoidS = 1.0;
constexpr double kMaxAvoidS = 1.9;
constexpr double kRobotSettleS = 0.25;

sim::WorldDescription Hall() {
  sim::WorldDescription d;
  d.name = "hall";
  d.materials["floor"] = sim::Material{0.8, 0.0, {0.6, 0.6, 0.6, 1}, core::LaserResponse::kNormal};
  d.materials["wall"] = sim::Material{0.8, 0.0, {0.8, 0.8, 0.8, 1}, core::LaserResponse::kNormal};
  d.floor = {{-kHallHalfX - 1, -kHallHalfY - 1}, {kHallHalfX + 1, kHallHalfY + 1}, "floor", {}};
  const Eigen::Vector2d corners[4] = {{-kHallHalfX, -kHallHalfY},
                                      {kHallHalfX, -kHallHalfY},
                                      {kHallHalfX, kHallHalfY},
                                      {-kHallHalfX, kHallHalfY}};
  for (int k = 0; k < 4; ++k) {
    sim::Wall wall;
    wall.id = "wall_" + std::to_string(k);
    wall.points_m = {corners[k], corners[(k + 1) % 4]};
    wall.thickness_m = 0.2;
    wall.height_m = 0.5;
    wall.material = "wall";
    d.walls.push_back(wall);
  }
  for (int k = 0; k < 15; ++k) {
    d.boxes.push_back({"exhibit_" + std::to_string(k),
                       {kExhibitCentres[k][0], kExhibitCentres[k][1], 0.0},
                       {1.0, 1.0, 0.5},
                       0.0,
                       "wall"});
  }
  return d;
}

// The hall benchmark's robot: 0.30 × 0.30 × 0.20 m, wheels of 0.10 m diameter
// at y = ±0.12 m, chassis 5 kg, wheels 0.5 kg; two casters and the motor
// limits chosen.
sim::RobotDescription HallRobot() {
  sim::RobotDescription m;
  m.model = "hall_robot";
  m.footprint_m = {{-0.15, -0.15}, {0.15, -0.15}, {0.15, 0.15}, {-0.15, 0.15}};
  m.chassis_base_z_m = 0.04;
  m.chassis_height_m = 0.16;
  m.chassis_mass_kg = 5.0;
  m.chassis_com_m = {0.0, 0.0, 0.1};
  m.left_wheel = {"left", 0.05, 0.02, 0.5, {0.0, 0.12}};
  m.right_wheel = {"right", 0.05, 0.02, 0.5, {0.0, -0.12}};
  m.casters = {{"caster_front", {0.11, 0.0}, 0.02}, {"caster_rear", {-0.11, 0.0}, 0.02}};
  m.max_wheel_torque_nm = 2.0;
  m.max_wheel_speed_radps = 20.0;
  m.max_wheel_accel_radps2 = 20.0;
  m.material = "wall";
  return m;
}

// N robots of one wheel model driving in the hall.
struct Fleet {
  std::unique_ptr<sim::World> world;
  std::vector<core::RandomStream> streams;
  std::int64_t command_period_ticks = 1;

  Fleet(sim::WheelModel wheels, int count, double rate_hz) {
    sim::WorldOptions options;
    options.physics_rate_hz = rate_hz;
    world = std::make_unique<sim::World>(Hall(), options);
    command_period_ticks = std::llround(kCommandPeriodS * rate_hz);
    const auto clear = [](double x, double y) {
      if (std::abs(x) > kHallHalfX - 0.1 - kClearanceM) return false;
      if (std::abs(y) > kHallHalfY - 0.1 - kClearanceM) return false;
      for (const auto& c : kExhibitCentres) {
        if (std::abs(x - c[0]) < 0.5 + kClearanceM && std::abs(y - c[1]) < 0.5 + kClearanceM) {
          return false;
        }
      }
      return true;
    };
    core::RandomStream headings(7, 0);
    for (double y = -kHallHalfY + kGridPitchM; y < kHallHalfY && world->robot_count() < count;
         y += kGridPitchM) {
      for (double x = -kHallHalfX + kGridPitchM; x < kHallHalfX && world->robot_count() < count;
           x += kGridPitchM) {
        if (!clear(x, y)) continue;
        pavilion::testing::WorldRobot spec;
        spec.id = "robot_" + std::to_string(world->robot_count());
        spec.model = HallRobot();
        spec.pose = {x, y, headings.Uniform(-std::numbers::pi, std::numbers::pi)};
        spec.wheel_model = wheels;
        const int r = pavilion::testing::AddRobot(*world, spec);
        streams.emplace_back(7, static_cast<std::uint64_t>(r + 1));
      }
    }
    if (world->robot_count() < count) throw std::runtime_error("the hall holds fewer robots");
    avoid_until_tick.assign(count, 0);
  }

  std::vector<std::int64_t> avoid_until_tick;  // per robot: end of its manoeuvre

  void Drive(int r, double speed_mps, double turn_radps) {
    const sim::RobotDescription& m = world->robot_model(r);
    const double half = 0.5 * turn_radps * m.wheelbase_m();
    world->SetWheelSpeeds(r, (speed_mps - half) / m.left_wheel.radius_m,
                          (speed_mps + half) / m.right_wheel.radius_m);
  }

  void Step() {
    const std::int64_t tick = world->tick();
    if (tick % command_period_ticks == 0) {
      for (int r = 0; r < world->robot_count(); ++r) {
        const double turn = streams[r].Uniform(-kMaxTurnRadps, kMaxTurnRadps);
        if (tick >= avoid_until_tick[r]) Drive(r, kCruiseMps, turn);
      }
    }
    world->Step();
    const auto& elements = world->elements();
    for (const sim::ContactChange& c : world->TakeContactChanges()) {
      if (c.phase != sim::ContactPhase::kBegin) continue;
      for (const int e : {c.a, c.b}) {
        const int r = elements[e].group;
        if (r < 0 || tick < avoid_until_tick[r]) continue;
        const double seconds = streams[r].Uniform(kMinAvoidS, kMaxAvoidS);
        avoid_until_tick[r] =
            tick + std::llround(seconds * static_cast<double>(command_period_ticks));
        Drive(r, kBackOffMps, streams[r].Uniform(0, 1) < 0.5 ? -kAvoidTurnRadps : kAvoidTurnRadps);
      }
    }
    for (int r = 0; r < world->robot_count(); ++r) {
      if (tick + 1 == avoid_until_tick[r]) Drive(r, kCruiseMps, 0.0);
    }
  }
};

// Args: wheel model (0 articulated, 1 raycast), robots, physics rate (Hz).
void BM_HallRobotsDriving(benchmark::State& state) {
  const auto wheels =
      state.range(0) == 0 ? sim::WheelModel::kArticulated : sim::WheelModel::kRaycast;
  const int count = static_cast<int>(state.range(1));
  const double rate_hz = static_cast<double>(state.range(2));
  Fleet fleet(wheels, count, rate_hz);
  const int settle = static_cast<int>(std::lround(kRobotSettleS * rate_hz));
  for (int i = 0; i < settle; ++i) fleet.Step();
  for (auto _ : state) fleet.Step();
  state.SetItemsProcessed(state.iterations());
  state.SetLabel(std::string(sim::WheelModelName(wheels)) + " " + std::to_string(count) +
                 " robots " + std::to_string(state.range(2)) + " Hz");
  state.counters["rtf"] = benchmark::Counter(static_cast<double>(state.iterations()) / rate_hz,
                                             benchmark::Counter::kIsRate);
}
BENCHMARK(BM_HallRobotsDriving)
    ->ArgsProduct({{0, 1}, {1, 10, 100, 1000}, {200, 100}})
    ->Unit(benchmark::kMicrosecond)
    ->MinTime(2.0);

}  // namespace

BENCHMARK_MAIN();
