// Time per 361-reading scan of the probabilistic line extraction (ExtractLines,
// thesis §3.2, LMS 200 preset) and of the split-and-merge baseline, on the same
// simulated sick_lms200 scans (noise and surface effects on) in expo_hall and
// office_floor, measured in the same run. Each iteration extracts one scan,
// cycling through the set, so the reported time is per scan. Counters:
// lines_per_scan (mean segments), mixed_per_scan (mean segments whose readings
// are not >= 90% from one world element by the simulator's per-ray truth, a
// cheap false-positive proxy), readings_per_scan. When both run, the CPU time
// of ExtractLines relative to SplitAndMerge is printed at the end (on stderr,
// with the run's context, so that --benchmark_format=json stays valid).
//
// BM_VerticalEdges: time per 640 x 480 grey image of the vertical edge
// extraction (ExtractVerticalEdges, thesis §3.4) on synthetic office-like
// images (wall, floor, door frames and poles, some of partial height, seen
// through the §2.4 lens by DistortImage, grey-level noise 2), against
// BM_DistortionMap, the per-frame lens resampling a camera sensor does anyway
// (ratio printed at the end as for the lines). Counters: edges_per_image,
// edge_pixels_per_image.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <ostream>
#include <string>
#include <vector>

#include "core/features/camera_model.h"
#include "core/features/line_extraction.h"
#include "core/features/split_and_merge.h"
#include "core/features/vertical_edges.h"
#include "core/random/random_stream.h"
#include "scenarios/config/data_paths.h"
#include "scenarios/config/world_loader.h"
#include "sim/sensors/laser_scanner.h"
#include "sim/world/world.h"

namespace {

using namespace pavilion;

constexpr int kScansPerWorld = 25;
constexpr double kMountHeightM = 0.5;
constexpr double kClearanceM = 0.5;

struct ScanWithTruth {
  core::LaserScan scan;
  core::LaserScanTruth truth;
};

// kScansPerWorld scans from random free-floor poses (>= kClearanceM from the
// section at the scan height) with random headings.
void AddScans(const std::string& world_name, std::uint64_t seed, std::vector<ScanWithTruth>* out) {
  const sim::WorldDescription d = scenarios::LoadWorldFile(scenarios::ResolveWorldPath(world_name));
  const sim::World world(d, sim::WorldOptions{});
  const core::PlanarSection section = world.SectionAt(kMountHeightM);
  auto clear = [&](const Eigen::Vector2d& p) {
    for (const auto& s : section.segments) {
      const Eigen::Vector2d ab = s.b_m - s.a_m;
      const double t = std::clamp((p - s.a_m).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      if ((s.a_m + t * ab - p).norm() < kClearanceM) return false;
    }
    for (const auto& c : section.circles) {
      if ((c.center_m - p).norm() < c.radius_m + kClearanceM) return false;
    }
    return true;
  };
  core::RandomStream rng(seed, 0);
  sim::LaserScanner laser("laser", sim::LaserScannerOptions::Profile("sick_lms200"), core::Pose2{},
                          kMountHeightM, core::RandomStream(seed, 1));
  int made = 0;
  for (int attempt = 0; made < kScansPerWorld && attempt < 100000; ++attempt) {
    const Eigen::Vector2d p(rng.Uniform(d.floor.min_m.x(), d.floor.max_m.x()),
                            rng.Uniform(d.floor.min_m.y(), d.floor.max_m.y()));
    if (!clear(p)) continue;
    const core::Pose2 pose{p.x(), p.y(), rng.Uniform(-std::numbers::pi, std::numbers::pi)};
    ScanWithTruth s;
    s.scan = laser.ScanFrom(world, pose, 0.1 * made, -1, &s.truth);
    out->push_back(std::move(s));
    ++made;
  }
}

const std::vector<ScanWithTruth>& Scans() {
  static const std::vector<ScanWithTruth> scans = [] {
    std::vector<ScanWithTruth> v;
    AddScans("expo_hall", 11, &v);
    AddScans("office_floor", 12, &v);
    return v;
  }();
  return scans;
}

// Segments whose spanned readings are not >= 90% from one world element.
int MixedSegments(const std::vector<core::Segment>& segments, const core::LaserScanTruth& truth) {
  int mixed = 0;
  for (const core::Segment& seg : segments) {
    std::map<int, int> hits;
    int best = 0;
    for (int i = seg.first_index; i <= seg.last_index; ++i) {
      if (truth.element[i] >= 0) best = std::max(best, ++hits[truth.element[i]]);
    }
    mixed += best < 0.9 * seg.point_count;
  }
  return mixed;
}

template <typename Extract>
void RunExtraction(benchmark::State& state, Extract extract) {
  const std::vector<ScanWithTruth>& scans = Scans();
  // Quality counters, outside the timed loop.
  double lines = 0.0;
  double mixed = 0.0;
  double readings = 0.0;
  for (const ScanWithTruth& s : scans) {
    const std::vector<core::Segment> segments = extract(s.scan);
    lines += static_cast<double>(segments.size());
    mixed += MixedSegments(segments, s.truth);
    readings += static_cast<double>(s.scan.readings.size());
  }
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(extract(scans[k].scan));
    if (++k == scans.size()) k = 0;
  }
  const double n = static_cast<double>(scans.size());
  state.SetItemsProcessed(state.iterations());
  state.counters["scans"] = n;
  state.counters["readings_per_scan"] = readings / n;
  state.counters["lines_per_scan"] = lines / n;
  state.counters["mixed_per_scan"] = mixed / n;
}

void BM_ExtractLines(benchmark::State& state) {
  const core::LineExtractionOptions options = core::LineExtractionOptions::SickLms200();
  RunExtraction(state,
                [&](const core::LaserScan& scan) { return core::ExtractLines(scan, options); });
}
BENCHMARK(BM_ExtractLines)->Unit(benchmark::kMicrosecond)->MinTime(2.0);

void BM_SplitAndMerge(benchmark::State& state) {
  const core::SplitAndMergeOptions options = core::SplitAndMergeOptions::SickLms200();
  RunExtraction(state,
                [&](const core::LaserScan& scan) { return core::SplitAndMerge(scan, options); });
}
BENCHMARK(BM_SplitAndMerge)->Unit(benchmark::kMicrosecond)->MinTime(2.0);

constexpr int kCameraImages = 8;
constexpr double kCameraNoiseGrey = 2.0;

// The §2.4 camera: 640 x 480, 54 deg, eq. 3.23 with k1 = -0.25, k2 = 0.08.
core::CameraIntrinsics OfficeCamera() {
  core::CameraIntrinsics c =
      core::CameraIntrinsics::FromHorizontalFov(640, 480, 54.0 * std::numbers::pi / 180.0);
  c.radial = {-0.25, 0.08, 0.0, 0.0};
  return c;
}

// A pinhole view of an office wall: lit unevenly, a darker floor below row
// 360, and vertical bands (door frames, poles, a cupboard) with area-coverage
// edges at sub-pixel columns drawn from `rng`.
core::GrayImage OfficePinhole(core::RandomStream& rng) {
  core::GrayImage image(640, 480);
  struct Band {
    double left, right, level;
    int top, bottom;
  };
  std::vector<Band> bands;
  for (double x = 30.0; x < 560.0; x += rng.Uniform(60.0, 110.0)) {
    const double width = rng.Uniform(6.0, 50.0);
    const double level = rng.Uniform(25.0, 70.0) * (rng.Uniform() < 0.5 ? -1.0 : 1.0);
    const int top = rng.Uniform() < 0.3 ? static_cast<int>(rng.Uniform(60.0, 200.0)) : 0;
    bands.push_back({x, x + width, level, top, 480});
  }
  for (int v = 0; v < 480; ++v) {
    for (int u = 0; u < 640; ++u) {
      double grey = v < 360 ? 120.0 + 20.0 * u / 640.0 : 70.0;
      for (const Band& b : bands) {
        if (v < b.top || v >= b.bottom) continue;
        grey += b.level * std::max(0.0, std::min(u + 1.0, b.right) - std::max(u + 0.0, b.left));
      }
      image.at(u, v) = static_cast<std::uint8_t>(std::clamp(grey, 0.0, 255.0) + 0.5);
    }
  }
  return image;
}

struct CameraFrames {
  core::CameraIntrinsics camera = OfficeCamera();
  std::vector<core::GrayImage> pinhole;
  std::vector<core::GrayImage> distorted;  // with noise
};

const CameraFrames& Frames() {
  static const CameraFrames frames = [] {
    CameraFrames f;
    const core::DistortionMap lens(f.camera);
    core::RandomStream rng(31, 0);
    for (int i = 0; i < kCameraImages; ++i) {
      f.pinhole.push_back(OfficePinhole(rng));
      f.distorted.push_back(lens.Apply(f.pinhole.back()));
      core::AddImageNoise(kCameraNoiseGrey, rng, &f.distorted.back());
    }
    return f;
  }();
  return frames;
}

void BM_VerticalEdges(benchmark::State& state) {
  const CameraFrames& frames = Frames();
  core::VerticalEdgeOptions options;
  options.image_noise_sigma_grey = kCameraNoiseGrey;
  double edges = 0.0, edge_pixels = 0.0;
  for (const core::GrayImage& image : frames.distorted) {
    core::VerticalEdgeStats stats;
    edges += static_cast<double>(
        core::ExtractVerticalEdges(image, frames.camera, options, &stats).size());
    edge_pixels += stats.edge_pixels;
  }
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        core::ExtractVerticalEdges(frames.distorted[k], frames.camera, options));
    if (++k == frames.distorted.size()) k = 0;
  }
  state.SetItemsProcessed(state.iterations());
  state.counters["edges_per_image"] = edges / kCameraImages;
  state.counters["edge_pixels_per_image"] = edge_pixels / kCameraImages;
}
BENCHMARK(BM_VerticalEdges)->Unit(benchmark::kMillisecond)->MinTime(2.0);

void BM_DistortionMap(benchmark::State& state) {
  const CameraFrames& frames = Frames();
  const core::DistortionMap lens(frames.camera);
  core::GrayImage out;
  std::size_t k = 0;
  for (auto _ : state) {
    lens.Apply(frames.pinhole[k], &out);
    benchmark::DoNotOptimize(out.pixels.data());
    if (++k == frames.pinhole.size()) k = 0;
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_DistortionMap)->Unit(benchmark::kMillisecond)->MinTime(2.0);

// The reporter --benchmark_format asks for, plus the ratio of ExtractLines'
// CPU time per scan to the split-and-merge baseline's, and of
// ExtractVerticalEdges' per image to DistortionMap::Apply's (the smallest of
// their repetitions) after the run.
class BaselineRatioReporter : public benchmark::BenchmarkReporter {
 public:
  bool ReportContext(const Context& context) override { return display_->ReportContext(context); }
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs) {
      if (run.run_type != Run::RT_Iteration || run.error_occurred) continue;
      const auto [it, inserted] =
          cpu_time_.emplace(run.run_name.function_name, run.GetAdjustedCPUTime());
      if (!inserted) it->second = std::min(it->second, run.GetAdjustedCPUTime());
    }
    display_->ReportRuns(runs);
  }
  void Finalize() override {
    display_->Finalize();
    PrintRatio("BM_ExtractLines", "BM_SplitAndMerge",
               "ExtractLines / SplitAndMerge CPU time per scan");
    PrintRatio("BM_VerticalEdges", "BM_DistortionMap",
               "ExtractVerticalEdges / DistortionMap::Apply CPU time per image");
  }

 private:
  void PrintRatio(const char* name, const char* baseline_name, const char* label) {
    const auto it = cpu_time_.find(name);
    const auto baseline = cpu_time_.find(baseline_name);
    if (it == cpu_time_.end() || baseline == cpu_time_.end()) return;
    display_->GetErrorStream() << label << ": " << it->second / baseline->second << "\n";
  }

  benchmark::BenchmarkReporter* display_ = benchmark::CreateDefaultDisplayReporter();  // static
  std::map<std::string, double> cpu_time_;  // per benchmark function, in its time unit
};

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  BaselineRatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  benchmark::Shutdown();
  return 0;
}
