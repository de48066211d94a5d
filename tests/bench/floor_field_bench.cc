// Cost of the crowd's floor fields (sim/crowd/floor_field.h) on a 35 m x 15 m
// exhibition floor at 0.2 m cells (175 x 75 cells) with 20 box exhibits and
// the floor's walls, goal the exit at the far end. Budgets: one field in a few
// ms; Direction well under 1 us (100+ people every 50 ms).
// Baselines measured in the same run: for construction, a 4-connected
// breadth-first wavefront over the same free cells (the cheapest grid field,
// NF1-like, no Euclidean distances); for queries, walking straight at the goal.
// The ratios to them are printed after the run.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/random/random_stream.h"
#include "sim/crowd/floor_field.h"

namespace {

using namespace pavilion;
using sim::crowd::DistanceField;
using sim::crowd::ObstacleSegment;
using sim::crowd::WalkableGrid;

constexpr double kFloorW_m = 35.0;
constexpr double kFloorH_m = 15.0;
constexpr int kExhibitCols = 5;
constexpr int kExhibitRows = 4;
constexpr int kQueryPoints = 4096;

struct Scene {
  std::vector<ObstacleSegment> walls;
  Eigen::Vector2d exit{34.0, 7.5};
  double exit_radius_m = 0.5;
  std::vector<Eigen::Vector2d> points;  // free query points, seeded
};

const Scene& TheScene() {
  static const Scene scene = [] {
    Scene s;
    const Eigen::Vector2d corners[4] = {
        {0, 0}, {kFloorW_m, 0}, {kFloorW_m, kFloorH_m}, {0, kFloorH_m}};
    for (int i = 0; i < 4; ++i) s.walls.push_back({corners[i], corners[(i + 1) % 4]});
    // 20 exhibits of 1.6 m x 1.0 m, rows staggered.
    for (int i = 0; i < kExhibitCols; ++i) {
      for (int j = 0; j < kExhibitRows; ++j) {
        const Eigen::Vector2d lo(4.0 + 6.0 * i + 1.5 * (j % 2), 1.8 + 3.4 * j);
        const Eigen::Vector2d hi = lo + Eigen::Vector2d(1.6, 1.0);
        s.walls.push_back({lo, {hi.x(), lo.y()}});
        s.walls.push_back({{hi.x(), lo.y()}, hi});
        s.walls.push_back({hi, {lo.x(), hi.y()}});
        s.walls.push_back({{lo.x(), hi.y()}, lo});
      }
    }
    const WalkableGrid grid({0, 0}, {kFloorW_m, kFloorH_m}, s.walls, {}, {});
    core::RandomStream random(1, core::RandomStream::StreamId("floor_field_bench"));
    while (static_cast<int>(s.points.size()) < kQueryPoints) {
      const Eigen::Vector2d p(random.Uniform(0.0, kFloorW_m), random.Uniform(0.0, kFloorH_m));
      if (grid.IsFree(p)) s.points.push_back(p);
    }
    return s;
  }();
  return scene;
}

const WalkableGrid& TheGrid() {
  static const WalkableGrid grid({0, 0}, {kFloorW_m, kFloorH_m}, TheScene().walls, {}, {});
  return grid;
}

// The baseline field: steps of a 4-connected breadth-first wavefront from the
// free cells within the exit disc.
std::vector<std::int32_t> BreadthFirst(const WalkableGrid& grid, const Eigen::Vector2d& goal,
                                       double radius_m) {
  const int cols = grid.cols();
  const int n = cols * grid.rows();
  std::vector<std::int32_t> steps(n, -1);
  std::vector<std::int32_t> queue;
  queue.reserve(n);
  for (int k = 0; k < n; ++k) {
    const sim::crowd::FloorCell cell(k % cols, k / cols);
    if (grid.kind(cell) == sim::crowd::CellKind::kFree &&
        (grid.CellCenter(cell) - goal).norm() <= radius_m) {
      steps[k] = 0;
      queue.push_back(k);
    }
  }
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const int k = queue[head];
    const int col = k % cols;
    const int row = k / cols;
    const int next[4][2] = {{col + 1, row}, {col - 1, row}, {col, row + 1}, {col, row - 1}};
    for (const auto& c : next) {
      if (c[0] < 0 || c[1] < 0 || c[0] >= cols || c[1] >= grid.rows()) continue;
      const int m = c[1] * cols + c[0];
      if (steps[m] >= 0 || grid.kind({c[0], c[1]}) != sim::crowd::CellKind::kFree) continue;
      steps[m] = steps[k] + 1;
      queue.push_back(m);
    }
  }
  return steps;
}

void BM_WalkableGridBuild(benchmark::State& state) {
  const Scene& scene = TheScene();
  for (auto _ : state) {
    const WalkableGrid grid({0, 0}, {kFloorW_m, kFloorH_m}, scene.walls, {}, {});
    benchmark::DoNotOptimize(grid.cols());
  }
  state.counters["segments"] = static_cast<double>(scene.walls.size());
}
BENCHMARK(BM_WalkableGridBuild)->Unit(benchmark::kMicrosecond);

void BM_BreadthFirstField(benchmark::State& state) {
  const Scene& scene = TheScene();
  for (auto _ : state) {
    benchmark::DoNotOptimize(BreadthFirst(TheGrid(), scene.exit, scene.exit_radius_m).data());
  }
}
BENCHMARK(BM_BreadthFirstField)->Unit(benchmark::kMicrosecond);

void BM_DistanceFieldToDisc(benchmark::State& state) {
  const Scene& scene = TheScene();
  const WalkableGrid& grid = TheGrid();
  for (auto _ : state) {
    const DistanceField field = DistanceField::ToDisc(grid, scene.exit, scene.exit_radius_m);
    benchmark::DoNotOptimize(&field);
  }
  int free = 0;
  for (int row = 0; row < grid.rows(); ++row) {
    for (int col = 0; col < grid.cols(); ++col) {
      free += grid.kind({col, row}) == sim::crowd::CellKind::kFree;
    }
  }
  state.counters["cells"] = grid.cols() * grid.rows();
  state.counters["free_cells"] = free;
}
BENCHMARK(BM_DistanceFieldToDisc)->Unit(benchmark::kMicrosecond);

void BM_StraightDirection(benchmark::State& state) {
  const Scene& scene = TheScene();
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize((scene.exit - scene.points[i]).normalized());
    i = (i + 1) % scene.points.size();
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_StraightDirection);

void BM_Direction(benchmark::State& state) {
  const Scene& scene = TheScene();
  const DistanceField field = DistanceField::ToDisc(TheGrid(), scene.exit, scene.exit_radius_m);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(field.Direction(scene.points[i]));
    i = (i + 1) % scene.points.size();
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Direction);

void BM_Distance(benchmark::State& state) {
  const Scene& scene = TheScene();
  const DistanceField field = DistanceField::ToDisc(TheGrid(), scene.exit, scene.exit_radius_m);
  std::size_t i = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(field.Distance(scene.points[i]));
    i = (i + 1) % scene.points.size();
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Distance);

// The reporter --benchmark_format asks for, plus the ratios of the field's
// CPU times to the baselines' (the smallest of their repetitions) after the run.
class BaselineRatioReporter : public benchmark::BenchmarkReporter {
 public:
  bool ReportContext(const Context& context) override { return display_->ReportContext(context); }
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& run : runs) {
      if (run.run_type != Run::RT_Iteration || run.error_occurred) continue;
      const double ns =
          run.GetAdjustedCPUTime() * (run.time_unit == benchmark::kMicrosecond ? 1e3 : 1.0);
      const auto [it, inserted] = cpu_ns_.emplace(run.run_name.function_name, ns);
      if (!inserted) it->second = std::min(it->second, ns);
    }
    display_->ReportRuns(runs);
  }
  void Finalize() override {
    display_->Finalize();
    Ratio("DistanceField::ToDisc / breadth-first wavefront", "BM_DistanceFieldToDisc",
          "BM_BreadthFirstField");
    Ratio("Direction / straight at the goal", "BM_Direction", "BM_StraightDirection");
  }

 private:
  void Ratio(const char* label, const std::string& name, const std::string& baseline) {
    const auto a = cpu_ns_.find(name);
    const auto b = cpu_ns_.find(baseline);
    if (a == cpu_ns_.end() || b == cpu_ns_.end()) return;
    display_->GetErrorStream() << label << " CPU time: " << a->second / b->second << "\n";
  }

  benchmark::BenchmarkReporter* display_ = benchmark::CreateDefaultDisplayReporter();  // static
  std::map<std::string, double> cpu_ns_;  // per benchmark function
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
