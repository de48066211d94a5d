// Off-screen camera frames (sim/render/offscreen_renderer.h) in the expo_hall
// world with 10 Robox robots at the exhibits' stations facing the hall and 100 visitors of a
// crowd: 640 x 480 grey frames from the robots' forward cameras (each robot's
// own body hidden), render and readback. Issue 19's goal: >= 100 frames/s on
// one core including the later distortion and noise, so render + readback
// should stay well under 10 ms. BM_CameraFrame* time the whole frame of a
// camera sensor (sim/sensors/camera_sensor.h: render, readback, lens, noise),
// its parts, and the vertical edges extracted from it. llvmpipe's thread count is process-wide:
// --llvmpipe_threads=N (default kDefaultLlvmpipeThreads) picks it per run.
//
//   render_bench --llvmpipe_threads=0 --benchmark_counters_tabular=true
#include <benchmark/benchmark.h>

#include <array>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <numbers>
#include <string>
#include <thread>
#include <vector>

#include "core/features/camera_model.h"
#include "core/features/vertical_edges.h"
#include "scenarios/config/data_paths.h"
#include "scenarios/config/robot_loader.h"
#include "scenarios/config/robot_setup.h"
#include "scenarios/config/world_loader.h"
#include "sim/render/offscreen_renderer.h"
#include "sim/sensors/camera_sensor.h"
#include "sim/world/world.h"

namespace pavilion {
namespace {

constexpr int kRobots = 10;
constexpr int kPeople = 100;
constexpr int kSettleSteps = 400;  // 2 s of the crowd walking before the frames

// The hall, its robots on the first kRobots stations and the crowd; the
// robots' forward cameras as views.
struct ExpoScene {
  std::unique_ptr<sim::World> world;
  std::vector<sim::RenderView> views;  // by robot
  sim::RenderScene people;             // the crowd's material

  ExpoScene() {
    sim::WorldDescription d = scenarios::LoadWorldFile(scenarios::ResolveWorldPath("expo_hall"));
    d.materials["visitor"] = sim::Material{0.5, 0.0, {0.75, 0.45, 0.3, 1.0}};
    const sim::RobotConfig robox = scenarios::WithWorldMaterials(
        scenarios::LoadRobotFile(scenarios::ResolveRobotPath("robox")), &d);
    world = std::make_unique<sim::World>(d, sim::WorldOptions{});
    const sim::CameraMount* camera = nullptr;
    for (const sim::CameraMount& c : robox.cameras) {
      if (c.id == "forward") camera = &c;
    }
    if (camera == nullptr) throw std::runtime_error("robox has no forward camera");
    sim::CrowdSpec crowd;
    crowd.options.pool_size = kPeople + 20;
    crowd.options.max_present = kPeople;
    crowd.options.initial_present = kPeople;
    crowd.material = "visitor";
    crowd.entrance = *d.places.at("visitor_spawn").area;
    crowd.exit = *d.places.at("visitor_exit").area;
    for (const auto& [name, place] : d.places) {
      if (name.rfind("station_", 0) != 0 || !place.pose) continue;
      crowd.attractions.push_back({name, *place.pose, place.attraction});
      if (world->robot_count() == kRobots) continue;
      // At the station, its back to the exhibit: the camera looks into the hall.
      core::Pose2 pose = *place.pose;
      pose.theta_rad = core::NormalizeAngle(pose.theta_rad + std::numbers::pi);
      world->AddRobot(
          robox.description, robox.systematic,
          {"robox_" + std::to_string(world->robot_count()), pose, sim::WheelModel::kRaycast});
    }
    world->AddCrowd(crowd, 1);
    for (int i = 0; i < kSettleSteps; ++i) world->Step();
    people.people_material = "visitor";
    for (int r = 0; r < world->robot_count(); ++r) {
      sim::RenderView view;
      view.world_from_camera = sim::WorldFromMount(world->robot_state(r).pose, camera->mount);
      view.intrinsics = core::CameraIntrinsics::FromHorizontalFov(
          camera->width_px, camera->height_px, camera->hfov_rad);
      views.push_back(view);
    }
  }

  sim::RenderScene SceneOf(int robot) const {
    sim::RenderScene s = people;
    s.hide_robot = robot;
    return s;
  }
};

const ExpoScene& Scene() {
  static const ExpoScene scene;
  return scene;
}

void SetCounters(benchmark::State& state, std::int64_t frames, std::size_t triangles) {
  state.counters["frames_per_s"] =
      benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
  state.counters["time_per_frame"] = benchmark::Counter(
      static_cast<double>(frames), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["triangles"] = static_cast<double>(triangles);
  state.counters["lp_threads"] = sim::LlvmpipeThreads();
}

// One renderer draws the robots' cameras in turn (one frame per iteration).
void BM_RenderFrame(benchmark::State& state) {
  const ExpoScene& scene = Scene();
  sim::OffscreenRenderer renderer;
  int robot = 0;
  std::int64_t frames = 0;
  for (auto _ : state) {
    const core::GrayImage image =
        renderer.RenderGray(*scene.world, scene.views[robot], scene.SceneOf(robot));
    benchmark::DoNotOptimize(image.pixels.data());
    robot = (robot + 1) % kRobots;
    ++frames;
  }
  SetCounters(state, frames, renderer.last_triangle_count());
}
BENCHMARK(BM_RenderFrame)->Unit(benchmark::kMillisecond)->UseRealTime();

// Each robot has its own renderer (as each camera sensor does); one iteration
// is a frame of every robot, on `state.range(0)` threads sharing the robots.
void BM_RenderFrameThreads(benchmark::State& state) {
  const ExpoScene& scene = Scene();
  const int threads = static_cast<int>(state.range(0));
  std::vector<std::unique_ptr<sim::OffscreenRenderer>> renderers;
  for (int r = 0; r < kRobots; ++r) renderers.push_back(std::make_unique<sim::OffscreenRenderer>());
  const auto render_share = [&](int t) {
    for (int r = t; r < kRobots; r += threads) {
      const core::GrayImage image =
          renderers[r]->RenderGray(*scene.world, scene.views[r], scene.SceneOf(r));
      benchmark::DoNotOptimize(image.pixels.data());
    }
  };
  std::int64_t frames = 0;
  for (auto _ : state) {
    std::vector<std::thread> pool;
    for (int t = 1; t < threads; ++t) pool.emplace_back(render_share, t);
    render_share(0);
    for (std::thread& t : pool) t.join();
    frames += kRobots;
  }
  SetCounters(state, frames, renderers[0]->last_triangle_count());
}
BENCHMARK(BM_RenderFrameThreads)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

// Issue 19's camera frame: Pygmalion's lens (k1 = 0.06, k2 = 0.01 of eq. 3.23)
// and noise (2 grey levels) on Robox's forward camera (640 x 480, 60 deg),
// no grabber delay (it costs nothing).
sim::CameraMount LensCamera() {
  const sim::RobotConfig robox = scenarios::LoadRobotFile(scenarios::ResolveRobotPath("robox"));
  for (sim::CameraMount c : robox.cameras) {
    if (c.id != "forward") continue;
    c.grayscale = true;
    c.radial_k1 = 0.06;
    c.radial_k2 = 0.01;
    c.noise_grey = 2.0;
    c.grabber_delay_s = 0.0;
    c.grabber_delay_sigma_s = 0.0;
    return c;
  }
  throw std::runtime_error("robox has no forward camera");
}

// One exposure of robot r's camera (tick 0 exposes; no delay: it arrives at once).
core::GrayImage SampleCamera(const ExpoScene& scene, sim::CameraSensor& sensor, int r) {
  sim::SensorTick tick;
  tick.world = scene.world.get();
  tick.robot = r;
  tick.before = tick.after = scene.world->robot_state(r);
  sim::SensorOutputs out;
  sensor.Sample(tick, &out);
  if (out.images.size() != 1) throw std::runtime_error("the camera delivered no image");
  return std::move(out.images.front().image.image);
}

// A camera sensor on every robot (each with its own renderer, as in a run),
// each past its first frame (the context and the world's display lists).
std::vector<std::unique_ptr<sim::CameraSensor>> CameraSensors(const ExpoScene& scene) {
  const sim::CameraMount mount = LensCamera();
  std::vector<std::unique_ptr<sim::CameraSensor>> sensors;
  for (int r = 0; r < kRobots; ++r) {
    sensors.push_back(std::make_unique<sim::CameraSensor>(mount, core::RandomStream(1, 2 * r),
                                                          core::RandomStream(1, 2 * r + 1), 200.0));
    SampleCamera(scene, *sensors.back(), r);
  }
  return sensors;
}

void SetFrameRate(benchmark::State& state, std::int64_t frames) {
  state.counters["frames_per_s"] =
      benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
  state.counters["time_per_frame"] = benchmark::Counter(
      static_cast<double>(frames), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.counters["lp_threads"] = sim::LlvmpipeThreads();
}

// A camera frame as CameraSensor::Sample makes it: render the enlarged
// pinhole (core::PinholeSource) + readback + lens (DistortionMap) + noise;
// the robots' cameras in turn. Issue 19's goal: >= 100 frames/s on one core.
// Arg: 10, a sensor (and renderer) per robot as in a run; 1, one sensor
// imaging from every robot in turn (one OpenGL context kept hot).
void BM_CameraFrame(benchmark::State& state) {
  const ExpoScene& scene = Scene();
  auto sensors = CameraSensors(scene);
  const auto used = static_cast<int>(state.range(0));
  int robot = 0;
  std::int64_t frames = 0;
  for (auto _ : state) {
    const core::GrayImage image = SampleCamera(scene, *sensors[robot % used], robot);
    benchmark::DoNotOptimize(image.pixels.data());
    robot = (robot + 1) % kRobots;
    ++frames;
  }
  SetFrameRate(state, frames);
}
BENCHMARK(BM_CameraFrame)->Arg(kRobots)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same frame from its parts, each timed: render_ms (render and readback
// of the enlarged pinhole, source_px pixels), lens_ms and noise_ms per frame.
void BM_CameraFrameParts(benchmark::State& state) {
  using Clock = std::chrono::steady_clock;
  const ExpoScene& scene = Scene();
  const sim::CameraMount mount = LensCamera();
  const core::CameraIntrinsics camera = mount.Intrinsics();
  const core::CameraIntrinsics source = core::PinholeSource(camera);
  const core::DistortionMap lens(camera, source);
  core::RandomStream noise(1, 1);
  sim::OffscreenRenderer renderer;
  core::GrayImage image;
  std::array<double, 3> seconds{};
  int robot = 0;
  std::int64_t frames = 0;
  for (auto _ : state) {
    sim::RenderView view;
    view.world_from_camera = sim::WorldFromMount(scene.world->robot_state(robot).pose, mount.mount);
    view.intrinsics = source;
    sim::RenderScene hide;
    hide.hide_robot = robot;
    const auto t0 = Clock::now();
    const core::GrayImage pinhole = renderer.RenderGray(*scene.world, view, hide);
    const auto t1 = Clock::now();
    lens.Apply(pinhole, &image);
    const auto t2 = Clock::now();
    core::AddImageNoise(mount.noise_grey, noise, &image);
    const auto t3 = Clock::now();
    benchmark::DoNotOptimize(image.pixels.data());
    seconds[0] += std::chrono::duration<double>(t1 - t0).count();
    seconds[1] += std::chrono::duration<double>(t2 - t1).count();
    seconds[2] += std::chrono::duration<double>(t3 - t2).count();
    robot = (robot + 1) % kRobots;
    ++frames;
  }
  SetFrameRate(state, frames);
  const double per_frame_ms = 1e3 / static_cast<double>(std::max<std::int64_t>(frames, 1));
  state.counters["render_ms"] = seconds[0] * per_frame_ms;
  state.counters["lens_ms"] = seconds[1] * per_frame_ms;
  state.counters["noise_ms"] = seconds[2] * per_frame_ms;
  state.counters["source_px"] = static_cast<double>(source.width_px) * source.height_px;
}
BENCHMARK(BM_CameraFrameParts)->Unit(benchmark::kMillisecond)->UseRealTime();

// BM_CameraFrame and the vertical edges of each image (§3.4,
// core::ExtractVerticalEdges with the camera's noise): edges_ms per image
// and the edges found.
void BM_CameraFrameWithEdges(benchmark::State& state) {
  using Clock = std::chrono::steady_clock;
  const ExpoScene& scene = Scene();
  auto sensors = CameraSensors(scene);
  const sim::CameraMount& mount = sensors[0]->mount();
  core::VerticalEdgeOptions options;
  options.image_noise_sigma_grey = mount.noise_grey;
  options.calibration_sigma_px = mount.calibration_sigma_px;
  double edge_seconds = 0.0;
  std::int64_t edges = 0;
  int robot = 0;
  std::int64_t frames = 0;
  for (auto _ : state) {
    const core::GrayImage image = SampleCamera(scene, *sensors[robot], robot);
    const auto t0 = Clock::now();
    const std::vector<core::VerticalEdge> found =
        core::ExtractVerticalEdges(image, sensors[robot]->intrinsics(), options);
    edge_seconds += std::chrono::duration<double>(Clock::now() - t0).count();
    edges += static_cast<std::int64_t>(found.size());
    robot = (robot + 1) % kRobots;
    ++frames;
  }
  SetFrameRate(state, frames);
  const auto n = static_cast<double>(std::max<std::int64_t>(frames, 1));
  state.counters["edges_ms"] = 1e3 * edge_seconds / n;
  state.counters["edges_per_image"] = static_cast<double>(edges) / n;
}
BENCHMARK(BM_CameraFrameWithEdges)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace pavilion

// Takes --llvmpipe_threads=N before Google Benchmark reads the rest.
int main(int argc, char** argv) {
  constexpr const char* kFlag = "--llvmpipe_threads=";
  std::vector<char*> rest;
  for (int i = 0; i < argc; ++i) {
    if (std::strncmp(argv[i], kFlag, std::strlen(kFlag)) == 0) {
      pavilion::sim::ConfigureLlvmpipe(std::atoi(argv[i] + std::strlen(kFlag)));
    } else {
      rest.push_back(argv[i]);
    }
  }
  int rest_argc = static_cast<int>(rest.size());
  benchmark::Initialize(&rest_argc, rest.data());
  if (benchmark::ReportUnrecognizedArguments(rest_argc, rest.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
