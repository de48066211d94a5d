// The nav_bench executable: reactive (dwa_bench.cc), planning (planning_bench.cc)
// and local-planning (band_bench.cc) benchmarks of issue 14.
#include <benchmark/benchmark.h>

BENCHMARK_MAIN();
